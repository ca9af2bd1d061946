#include "core/util/parallel_for.h"

#include <gtest/gtest.h>

#include <algorithm>
#include <atomic>
#include <mutex>
#include <thread>
#include <stdexcept>
#include <vector>

namespace loom {
namespace {

// What ParallelRounds called, in the order it called it: 'p' prepare, 'i' an item,
// 'f' finish, each with its round.
struct Event {
  char kind;
  size_t round;
};

class RoundLog {
 public:
  void Add(char kind, size_t round) {
    const std::lock_guard lock(mutex_);
    events_.push_back({kind, round});
  }
  std::vector<Event> events() const { return events_; }

 private:
  mutable std::mutex mutex_;
  std::vector<Event> events_;
};

// Each round is prepare, then `items` items, then finish, the rounds in order.
void ExpectRounds(const std::vector<Event>& events, size_t rounds, size_t items, bool last_finished = true) {
  const size_t per_round = items + 2;
  ASSERT_EQ(events.size(), rounds * per_round - (last_finished ? 0 : 1));
  for (size_t e = 0; e < events.size(); ++e) {
    const size_t round = e / per_round, at = e % per_round;
    EXPECT_EQ(events[e].round, round) << "event " << e;
    EXPECT_EQ(events[e].kind, at == 0 ? 'p' : at == per_round - 1 ? 'f' : 'i') << "event " << e;
  }
}

TEST(ParallelRounds, EachRoundPreparesRunsEveryItemOnceThenFinishes) {
  for (unsigned threads : {1u, 2u, 4u}) {
    RoundLog log;
    std::vector<std::vector<int>> seen(5, std::vector<int>(7, 0));
    ParallelRounds(
        5, 7, threads, [&](size_t round) { log.Add('p', round); },
        [&](size_t round, size_t item, unsigned worker) {
          EXPECT_LT(worker, threads);
          ++seen[round][item];
          log.Add('i', round);
        },
        [&](size_t round) { log.Add('f', round); });
    ExpectRounds(log.events(), 5, 7);
    for (const auto& round : seen) EXPECT_EQ(round, std::vector<int>(7, 1)) << threads << " threads";
  }
}

TEST(ParallelRounds, ThrowingFromAnItemEndsTheLoopBeforeThatRoundFinishes) {
  RoundLog log;
  EXPECT_THROW(ParallelRounds(
                   6, 2, 2, [&](size_t round) { log.Add('p', round); },
                   [&](size_t round, size_t item, unsigned) {
                     log.Add('i', round);
                     if (round == 3 && item == 0) throw std::runtime_error("item");
                   },
                   [&](size_t round) { log.Add('f', round); }),
               std::runtime_error);
  // Rounds 0-2 whole, then round 3's prepare and the items started before the throw.
  std::vector<Event> events = log.events();
  ASSERT_GE(events.size(), 3 * 4 + 2u);
  ASSERT_LE(events.size(), 3 * 4 + 3u);
  for (size_t e = 3 * 4; e < events.size(); ++e) {
    EXPECT_EQ(events[e].round, 3u);
    EXPECT_EQ(events[e].kind, e == 3 * 4 ? 'p' : 'i');
  }
  events.resize(3 * 4);
  ExpectRounds(events, 3, 2);
}

TEST(ParallelRounds, ThrowingFromFinishOrPrepareEndsTheLoop) {
  RoundLog log;
  EXPECT_THROW(ParallelRounds(
                   6, 3, 2, [&](size_t round) { log.Add('p', round); },
                   [&](size_t round, size_t, unsigned) { log.Add('i', round); },
                   [&](size_t round) {
                     log.Add('f', round);
                     if (round == 2) throw std::runtime_error("finish");
                   }),
               std::runtime_error);
  ExpectRounds(log.events(), 3, 3);

  size_t items = 0;
  EXPECT_THROW(ParallelRounds(
                   6, 3, 2, [](size_t round) { if (round == 1) throw std::runtime_error("prepare"); },
                   [&](size_t, size_t, unsigned) { ++items; }, [](size_t) {}),
               std::runtime_error);
  EXPECT_EQ(items, 3u);
}

TEST(ParallelRounds, NoRoundsCallsNothing) {
  int calls = 0;
  ParallelRounds(0, 4, 2, [&](size_t) { ++calls; }, [&](size_t, size_t, unsigned) { ++calls; },
                 [&](size_t) { ++calls; });
  EXPECT_EQ(calls, 0);
}

// Each item once, each worker index on one thread at a time and below the
// thread count, progress rising to the count.
TEST(ParallelFor, EveryItemOnceWorkerIndicesInRangeProgressEndsAtTheCount) {
  for (const unsigned threads : {1u, 2u, 5u}) {
    constexpr size_t kItems = 10000;
    std::vector<std::atomic<int>> seen(kItems);
    std::vector<std::atomic<int>> inside(threads);
    std::atomic<bool> overlapped{false}, out_of_range{false};
    std::vector<size_t> reports;
    ParallelFor(
        kItems, threads,
        [&](size_t item, unsigned worker) {
          if (worker >= threads) {
            out_of_range = true;
            return;
          }
          if (++inside[worker] != 1) overlapped = true;
          ++seen[item];
          --inside[worker];
        },
        [&](size_t done) { reports.push_back(done); });
    for (size_t i = 0; i < kItems; ++i) ASSERT_EQ(seen[i], 1) << "item " << i << ", " << threads << " threads";
    EXPECT_FALSE(overlapped);
    EXPECT_FALSE(out_of_range);
    ASSERT_FALSE(reports.empty());
    EXPECT_EQ(reports.back(), kItems);
    EXPECT_TRUE(std::is_sorted(reports.begin(), reports.end()));
  }
}

// The helpers are started once and kept: a thousand loops run on no more threads
// than one loop does (not a new team per loop). A thread's thread_local is made
// fresh in each new thread, whatever id the system reuses for it.
std::atomic<int> threads_started{0};
thread_local const bool kCounted = (++threads_started, true);

TEST(ParallelFor, LoopsReuseTheirHelperThreads) {
  const int before = threads_started;
  for (int loop = 0; loop < 1000; ++loop) {
    ParallelFor(64, 3, [&](size_t, unsigned) { EXPECT_TRUE(kCounted); });
  }
  // This thread and at most 2 helpers (the pool may have grown already, for other
  // tests' wider loops in this process, without this test's threads counted).
  EXPECT_LE(threads_started - before, 3);
}

TEST(ParallelFor, TheFirstExceptionIsRethrownAndLoopsInsideLoopsAndSideBySideFinish) {
  EXPECT_THROW(ParallelFor(1000, 2,
                           [](size_t item, unsigned) {
                             if (item == 500) throw std::runtime_error("item 500");
                           }),
               std::runtime_error);
  // Nested: the inner loops run on their own threads; nothing waits for a busy helper.
  std::atomic<size_t> inner{0};
  ParallelFor(8, 2, [&](size_t, unsigned) { ParallelFor(100, 2, [&](size_t, unsigned) { ++inner; }); });
  EXPECT_EQ(inner, 800u);
  // Two threads looping at once share the helpers.
  std::atomic<size_t> total{0};
  auto loops = [&] {
    for (int i = 0; i < 200; ++i) ParallelFor(50, 2, [&](size_t, unsigned) { ++total; });
  };
  std::thread other(loops);
  loops();
  other.join();
  EXPECT_EQ(total, 2u * 200 * 50);
}

}  // namespace
}  // namespace loom
