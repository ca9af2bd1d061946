#include "server/store/artifact_store.h"

// Implementation follows in the next commit (headers published first for the RPC work).
