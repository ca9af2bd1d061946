#include "core/fit/lobe_powers.h"

#include <gtest/gtest.h>

#include <cmath>
#include <limits>
#include <random>
#include <vector>

namespace loom {
namespace {

constexpr double kMinArgument = 1e-30;

struct Powers {
  std::vector<double> logs, values;
};

Powers Compute(const std::vector<double>& dots, double exponent) {
  Powers out{std::vector<double>(dots.size(), -1.0), std::vector<double>(dots.size(), -1.0)};
  LobePowers(dots.data(), dots.size(), exponent, kMinArgument, out.logs.data(), out.values.data());
  return out;
}

// Over the arguments and exponents a lobe fit meets (C·a up to |C| ≤ 50 times unit
// products, N in [0.5, 256]), within a few ulp of the scalar functions.
TEST(LobePowers, MatchesLogAndPow) {
  std::mt19937 random(11);
  std::uniform_real_distribution<double> log_dot(std::log(1e-12), std::log(150.0));
  std::uniform_real_distribution<double> exponent(0.5, 256.0);
  for (int round = 0; round < 200; ++round) {
    const double n = exponent(random);
    std::vector<double> dots(37);  // not a multiple of the vector width
    for (double& d : dots) d = std::exp(log_dot(random));
    const Powers out = Compute(dots, n);
    for (size_t i = 0; i < dots.size(); ++i) {
      const double log_expected = std::log(dots[i]);
      EXPECT_NEAR(out.logs[i], log_expected, 4e-16 * std::max(1.0, std::abs(log_expected))) << dots[i];
      const double expected = std::pow(dots[i], n);
      if (expected == 0.0 || expected > std::numeric_limits<double>::max()) continue;
      if (expected < std::numeric_limits<double>::min()) continue;  // flushed to 0 (below)
      // The power inherits the logarithm's rounding times N·|log d|.
      EXPECT_NEAR(out.values[i], expected, 1e-15 * (1.0 + n * std::abs(log_expected)) * expected) << dots[i] << "^" << n;
    }
  }
}

TEST(LobePowers, OffLobesAreZeroAndExtremesStayDefined) {
  const std::vector<double> dots = {0.0, -2.0, 1e-31, 1.0, 1e-20, 40.0};
  const Powers out = Compute(dots, 256.0);
  for (size_t i = 0; i < 3; ++i) {  // at or below the minimum argument: off
    EXPECT_EQ(out.logs[i], 0.0);
    EXPECT_EQ(out.values[i], 0.0);
  }
  EXPECT_EQ(out.logs[3], 0.0);
  EXPECT_EQ(out.values[3], 1.0);
  EXPECT_EQ(out.values[4], 0.0);                                        // 1e-5120 underflows to 0
  EXPECT_EQ(out.values[5], std::numeric_limits<double>::infinity());  // 40^256 overflows
}

}  // namespace
}  // namespace loom
