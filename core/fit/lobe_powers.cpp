#include "core/fit/lobe_powers.h"

#include <algorithm>
#include <bit>
#include <cstdint>
#include <cstring>
#include <limits>
#include <utility>

#include "core/util/target_clones.h"

// The helpers below take and return 32-byte vectors; they have internal linkage
// and are inlined, so the ABI note that GCC gives for them does not apply.
#pragma GCC diagnostic ignored "-Wpsabi"

namespace loom {
namespace {

// Four lanes in GCC's vector extension (two with clang, below): the arithmetic is
// written once and compiled to AVX2 (one register) in the x86-64-v3 clone, to SSE2
// pairs otherwise.
// Selects are lane masks, so there is no control flow per value.
#if defined(__clang__)
// clang refuses a 32-byte vector return in the default (non-AVX) clone of
// target_clones, so a clang build (the fuzz build) takes 2 lanes and no clones:
// the same arithmetic per element, half the width.
constexpr size_t kLanes = 2;
#define LOOM_LOBE_POWERS_CLONES
#else
constexpr size_t kLanes = 4;
#define LOOM_LOBE_POWERS_CLONES LOOM_TARGET_CLONES
#endif
using Vec = double __attribute__((vector_size(8 * kLanes)));
using Bits = uint64_t __attribute__((vector_size(8 * kLanes)));
using Mask = int64_t __attribute__((vector_size(8 * kLanes)));

[[gnu::always_inline]] inline Vec Splat(double x) { return Vec{} + x; }
[[gnu::always_inline]] inline Bits SplatBits(uint64_t x) { return Bits{} + x; }
[[gnu::always_inline]] inline Vec Select(const Mask& mask, const Vec& a, const Vec& b) { return mask ? a : b; }

constexpr double kLn2Hi = 6.93147180369123816490e-01;  // fdlibm's split of ln 2
constexpr double kLn2Lo = 1.90821492927058770002e-10;
constexpr double kSqrt2 = 1.41421356237309504880;
constexpr uint64_t kMantissa = (uint64_t{1} << 52) - 1;
constexpr uint64_t kOneExponent = uint64_t{1023} << 52;
constexpr double kTwo52 = 0x1p52;
// t + kRound rounds t to an integer held in the low mantissa bits (|t| < 2^51).
constexpr double kRound = 0x1.8p52;

constexpr uint64_t BitsOf(double x) { return std::bit_cast<uint64_t>(x); }

// log x for normal x > 0: x = 2^e·m with m in [√½, √2), and
// log m = 2 atanh s = 2s (1 + s²/3 + s⁴/5 + …), s = (m − 1)/(m + 1), |s| < 0.172, so
// ten terms reach double precision.
[[gnu::always_inline]] inline Vec Log(const Vec& x) {
  const Bits bits = std::bit_cast<Bits>(x);
  // The biased exponent as a double, exactly: (2^52 + e_biased) − 2^52.
  const Bits exponent_bits = (bits >> 52) | SplatBits(BitsOf(kTwo52));
  Vec e = std::bit_cast<Vec>(exponent_bits) - Splat(kTwo52 + 1023.0);
  const Bits mantissa_bits = (bits & SplatBits(kMantissa)) | SplatBits(kOneExponent);
  Vec m = std::bit_cast<Vec>(mantissa_bits);
  const Mask high = m > Splat(kSqrt2);
  m = Select(high, 0.5 * m, m);
  e = Select(high, e + 1.0, e);
  const Vec s = (m - 1.0) / (m + 1.0);
  const Vec z = s * s;
  Vec p = Splat(1.0 / 19.0);
  for (const double c : {1.0 / 17, 1.0 / 15, 1.0 / 13, 1.0 / 11, 1.0 / 9, 1.0 / 7, 1.0 / 5, 1.0 / 3}) p = p * z + c;
  // 2s·(1 + z·p), the leading 2s kept apart from the small rest.
  const Vec two_s = 2.0 * s;
  return e * kLn2Hi + (two_s + (two_s * z * p + e * kLn2Lo));
}

// exp y (NaN stays NaN): y = k ln 2 + r, |r| ≤ ln2/2, e^r by its Taylor series to
// r^13 (remainder below 2e-16), and 2^k added to the exponent bits. Above the
// overflow threshold +Inf, below the smallest normal result 0.
[[gnu::always_inline]] inline Vec Exp(const Vec& y) {
  constexpr double kMaxArgument = 709.78;
  constexpr double kMinArgument = -708.39;
  Vec clamped = Select(y < kMinArgument, Splat(kMinArgument), y);
  clamped = Select(clamped > kMaxArgument, Splat(kMaxArgument), clamped);
  const Vec t = clamped * 1.44269504088896340736 + kRound;
  const Vec k = t - kRound;
  const Vec r = (clamped - k * kLn2Hi) - k * kLn2Lo;
  Vec p = Splat(1.0 / 6227020800.0);  // 1/13!
  for (const double c : {1.0 / 479001600, 1.0 / 39916800, 1.0 / 3628800, 1.0 / 362880, 1.0 / 40320, 1.0 / 5040,
                         1.0 / 720, 1.0 / 120, 1.0 / 24, 1.0 / 6, 0.5, 1.0, 1.0}) {
    p = p * r + c;
  }
  const Bits shift = (std::bit_cast<Bits>(t) - SplatBits(BitsOf(kRound))) << 52;
  const Bits result_bits = std::bit_cast<Bits>(p) + shift;
  Vec result = std::bit_cast<Vec>(result_bits);
  result = Select(y > kMaxArgument, Splat(std::numeric_limits<double>::infinity()), result);
  result = Select(y < kMinArgument, Splat(0.0), result);
  return Select(y != y, y, result);
}

}  // namespace

LOOM_LOBE_POWERS_CLONES void LobePowers(const double* dots, size_t count, double exponent, double min_argument,
                                        double* logs, double* values) {
  auto group = [&](const Vec& dot, Vec& log_out, Vec& value_out) {
    const Mask on = dot > min_argument;
    // Off lanes run the arithmetic on min_argument and are discarded.
    const Vec log_dot = Log(Select(on, dot, Splat(min_argument)));
    const Vec value = Exp(exponent * log_dot);
    log_out = Select(on, log_dot, Splat(0.0));
    value_out = Select(on, value, Splat(0.0));
  };
  size_t begin = 0;
  Vec log_out, value_out;
  for (; begin + kLanes <= count; begin += kLanes) {
    Vec dot;
    std::memcpy(&dot, dots + begin, sizeof dot);
    group(dot, log_out, value_out);
    std::memcpy(logs + begin, &log_out, sizeof log_out);
    std::memcpy(values + begin, &value_out, sizeof value_out);
  }
  if (begin < count) {  // the last partial group, padded with off lanes
    const size_t n = count - begin;
    Vec dot = Splat(min_argument);
    std::memcpy(&dot, dots + begin, n * sizeof(double));
    group(dot, log_out, value_out);
    std::memcpy(logs + begin, &log_out, n * sizeof(double));
    std::memcpy(values + begin, &value_out, n * sizeof(double));
  }
}

}  // namespace loom
