#include "loom/v1/job_state.h"

namespace loom::v1 {

bool IsTerminal(JobState state) {
  return state == JOB_STATE_SUCCEEDED || state == JOB_STATE_FAILED || state == JOB_STATE_CANCELLED;
}

}  // namespace loom::v1
