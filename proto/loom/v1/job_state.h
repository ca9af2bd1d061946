#pragma once
// Facts about the schema's job states that the server, the worker and the
// client all need; kept beside job.proto so that no side restates them.

#include "loom/v1/job.pb.h"

namespace loom::v1 {

// SUCCEEDED, FAILED or CANCELLED: the job will not change again.
bool IsTerminal(JobState state);

}  // namespace loom::v1
