#pragma once
// The Pareto front of a speed-versus-accuracy chart: the configurations no other
// configuration beats on both cost (time, lower is better) and error (lower is
// better). A chart of PSNR passes −PSNR as the error.

#include <cstddef>
#include <vector>

namespace loom::lab {

struct CostError {
  double cost = 0.0;
  double error = 0.0;
};

// Indices of the points on the front, by increasing cost (so by decreasing error).
// A point is on it when no other point has cost <= and error <= with one of them
// strictly lower; of identical points the first is kept. Points with a non-finite
// figure are left out.
std::vector<size_t> ParetoFront(const std::vector<CostError>& points);

}  // namespace loom::lab
