#include "server/parse_slots.h"

#include <chrono>

#include "core/util/error.h"

namespace loom::server {

using namespace std::chrono_literals;

ParseSlots::ParseSlots(int slots) : capacity_(slots) {
  if (slots < 1) throw Error(ErrorCode::kInvalidArgument, "--max-concurrent-parses: must be >= 1");
}

ParseSlots::Slot::~Slot() {
  if (owner_ != nullptr) owner_->Release();
}

ParseSlots::Slot ParseSlots::Acquire(const std::function<bool()>& cancelled) {
  std::unique_lock lock(mu_);
  while (in_use_ >= capacity_) {
    if (cancelled()) {
      throw Error(ErrorCode::kUnavailable, "the client left while its request waited for one of the server's " +
                                               std::to_string(capacity_) + " mesh-parse slots");
    }
    freed_.wait_for(lock, 100ms);
  }
  ++in_use_;
  return Slot(this);
}

int ParseSlots::in_use() const {
  std::lock_guard lock(mu_);
  return in_use_;
}

void ParseSlots::Release() {
  {
    std::lock_guard lock(mu_);
    --in_use_;
  }
  freed_.notify_one();
}

}  // namespace loom::server
