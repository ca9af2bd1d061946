#pragma once
// How many requests may parse meshes at once (loom-server --max-concurrent-parses).
// A parse may take as much memory as the caps of core/spec/limits.h allow
// (docs/operations.md "Limits"), so the server's peak for parsing is the slot count
// times that. A request beyond the limit waits for a slot for as long as its client
// waits.

#include <condition_variable>
#include <functional>
#include <mutex>
#include <utility>

namespace loom::server {

class ParseSlots {
 public:
  // `slots` >= 1.
  explicit ParseSlots(int slots);

  // Held while a request parses; released when destroyed.
  class Slot {
   public:
    explicit Slot(ParseSlots* owner) : owner_(owner) {}
    Slot(Slot&& other) noexcept : owner_(std::exchange(other.owner_, nullptr)) {}
    Slot& operator=(Slot&&) = delete;
    ~Slot();

   private:
    ParseSlots* owner_;
  };

  // Waits for a free slot, looking every 100 ms at `cancelled` (a client that hung
  // up): Error(kUnavailable) when it says so before a slot is free.
  Slot Acquire(const std::function<bool()>& cancelled);

  int capacity() const { return capacity_; }
  int in_use() const;

 private:
  void Release();

  const int capacity_;
  mutable std::mutex mu_;
  std::condition_variable freed_;
  int in_use_ = 0;
};

}  // namespace loom::server
