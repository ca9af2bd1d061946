#pragma once
// A minimal parallel loop for independent work items (texels, vertices, texel
// channels). Items are handed out in index order through an atomic counter; each
// item must write only its own outputs and draw its random numbers from a
// generator seeded by its index, so the result does not depend on the schedule or
// on the thread count.

#include <cstddef>
#include <cstdint>
#include <functional>
#include <vector>

namespace loom {

// 0 means every core (std::thread::hardware_concurrency, at least 1).
unsigned ResolveThreadCount(unsigned threads);

// Calls body(item, worker) for every item in [0, count) on `threads` threads
// (including the calling thread), worker in [0, threads) naming the thread so the
// body can use per-thread scratch. progress(done) is called on the calling thread
// only, between items, whenever at least 1% more items are done, and once at the
// end with done = count. The first exception thrown by a body or by progress stops
// the loop (items already started finish) and is rethrown here.
void ParallelFor(size_t count, unsigned threads, const std::function<void(size_t item, unsigned worker)>& body,
                 const std::function<void(size_t done)>& progress = {});

// `rounds` rounds of a loop whose rounds depend on each other (training steps), on
// `threads` threads started once rather than once a round: in round r, prepare(r)
// on the calling thread, then body(r, item, worker) for every item in [0, count) as
// ParallelFor does, then finish(r) on the calling thread. The first exception thrown
// by any of them ends the loop after the round's started items and is rethrown.
void ParallelRounds(size_t rounds, size_t count, unsigned threads, const std::function<void(size_t round)>& prepare,
                    const std::function<void(size_t round, size_t item, unsigned worker)>& body,
                    const std::function<void(size_t round)>& finish);

// One counter per worker (e.g. rays cast), each on its own cache line so that
// workers counting in their hot loops do not contend.
class PerWorkerCount {
 public:
  explicit PerWorkerCount(unsigned workers) : counts_(workers) {}
  uint64_t& operator[](unsigned worker) { return counts_[worker].value; }
  uint64_t Total() const;

 private:
  struct alignas(64) Padded {
    uint64_t value = 0;
  };
  std::vector<Padded> counts_;
};

}  // namespace loom
