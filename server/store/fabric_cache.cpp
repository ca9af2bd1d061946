#include "server/store/fabric_cache.h"

// Implementation follows in the next commit (headers published first for the RPC work).
