#pragma once
// Deterministic random numbers for one work item: a SplitMix64 generator seeded by
// (PrecomputeSettings.seed, a stream naming the use, the item's index). Each work
// item draws from its own stream, so results do not depend on which thread ran it
// or when. The float conversion is spelled out (not std::uniform_real_distribution,
// whose output differs between standard libraries).

#include <cstdint>

namespace loom {

class RandomStream {
 public:
  // Uses of random numbers in acquisition; each gets independent streams.
  enum Stream : uint64_t { kTexelJitter = 1, kGatherDirections = 2, kVolumeJitter = 3, kFibreWalk = 4 };

  RandomStream(uint64_t seed, Stream stream, uint64_t index) : state_(Mix(seed ^ Mix(stream ^ Mix(index)))) {}

  uint64_t NextBits() { return Mix(state_ += kGolden); }
  // Uniform in [0, 1): the top 24 bits, exactly representable as a float.
  float Uniform() { return static_cast<float>(NextBits() >> 40) * 0x1p-24f; }

 private:
  static constexpr uint64_t kGolden = 0x9E3779B97F4A7C15ull;
  // SplitMix64's finaliser (Steele, Lea and Flood 2014).
  static constexpr uint64_t Mix(uint64_t z) {
    z = (z ^ (z >> 30)) * 0xBF58476D1CE4E5B9ull;
    z = (z ^ (z >> 27)) * 0x94D049BB133111EBull;
    return z ^ (z >> 31);
  }

  uint64_t state_;
};

}  // namespace loom
