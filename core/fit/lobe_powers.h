#pragma once
// The transcendental work of the lobe fit, vectorised: for every lobe argument
// d > 0 of a texel, log d and d^N = exp(N·log d). LobeCost refreshes both for every
// sample whenever Levenberg–Marquardt tries a point, and with the scalar libm
// functions that was a third of the fit's time; these loops are branch-free
// polynomial versions the compiler vectorises (AVX2 and FMA where the CPU has
// them), within a few ulp of std::log and std::exp.

#include <cstddef>

namespace loom {

// For i < count: where dots[i] > min_argument, logs[i] = log dots[i] and
// values[i] = dots[i]^exponent; elsewhere both are 0 (the lobe is off). A power
// that overflows is +Inf, one that underflows below the smallest normal double is 0.
void LobePowers(const double* dots, size_t count, double exponent, double min_argument, double* logs,
                double* values);

}  // namespace loom
