#include "lab/pareto_front.h"

#include <algorithm>
#include <cmath>

namespace loom::lab {

std::vector<size_t> ParetoFront(const std::vector<CostError>& points) {
  std::vector<size_t> order;
  for (size_t i = 0; i < points.size(); ++i) {
    if (std::isfinite(points[i].cost) && std::isfinite(points[i].error)) order.push_back(i);
  }
  // By cost, then error, then index: walking in this order a point is on the front
  // exactly when its error is below every error seen so far.
  std::sort(order.begin(), order.end(), [&](size_t a, size_t b) {
    if (points[a].cost != points[b].cost) return points[a].cost < points[b].cost;
    if (points[a].error != points[b].error) return points[a].error < points[b].error;
    return a < b;
  });
  std::vector<size_t> front;
  double best_error = INFINITY;
  for (const size_t i : order) {
    if (points[i].error < best_error) {
      front.push_back(i);
      best_error = points[i].error;
    }
  }
  return front;
}

}  // namespace loom::lab
