#pragma once
// Facts about the schema's job states that the server and the client both
// need; kept beside job.proto so that neither restates them.

#include "loom/v1/job.pb.h"

namespace loom::v1 {

// SUCCEEDED, FAILED or CANCELLED: the job will not change again.
bool IsTerminal(JobState state);

}  // namespace loom::v1
