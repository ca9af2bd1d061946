#include "server/store/job_queue.h"

// Implementation follows in the next commit (headers published first for the RPC work).
