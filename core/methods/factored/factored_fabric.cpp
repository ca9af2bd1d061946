#include "core/methods/factored/factored_fabric.h"

#include <Eigen/Dense>

#include <algorithm>
#include <cmath>
#include <numbers>

#include "core/methods/direction_grid.h"
#include "core/util/parallel_for.h"
#include "core/util/stopwatch.h"

namespace loom {
namespace {

using Matrix = Eigen::MatrixXd;

// The top `rank` singular triplets of a V×L table M, from the eigenvectors of M·Mᵀ
// (V×V), so a_k = √σ_k u_k and b_k = Mᵀ u_k / √σ_k = √σ_k v_k.
void FactorTable(const Matrix& table, uint32_t rank, Matrix& view_terms, Matrix& light_terms) {
  const Matrix gram = table * table.transpose();
  const Eigen::SelfAdjointEigenSolver<Matrix> eigen(gram);
  const Eigen::Index views = table.rows();
  view_terms.setZero(views, rank);
  light_terms.setZero(table.cols(), rank);
  for (uint32_t k = 0; k < rank; ++k) {
    const Eigen::Index column = views - 1 - static_cast<Eigen::Index>(k);  // eigenvalues ascend
    const double lambda = eigen.eigenvalues()(column);
    if (!(lambda > 1e-20)) break;
    Eigen::VectorXd u = eigen.eigenvectors().col(column);
    if (u.sum() < 0.0) u = -u;  // a sign per term, the same on every run
    const double scale = std::sqrt(std::sqrt(lambda));  // √σ
    view_terms.col(k) = scale * u;
    light_terms.col(k) = table.transpose() * u / scale;
  }
}

FactoredLevel FactorLevel(const TabulatedLevel& tabulated, uint32_t rank, size_t views, size_t lights,
                          unsigned threads) {
  FactoredLevel level;
  level.resolution = tabulated.resolution;
  level.alpha = tabulated.alpha;
  level.ambient = tabulated.ambient;
  const size_t texels = tabulated.texel_count();
  level.view_terms.assign(texels * rank * views, 0.0f);
  level.light_terms.assign(texels * rank * lights, 0.0f);
  std::vector<double> residual(texels, 0.0), total(texels, 0.0);
  const auto V = static_cast<Eigen::Index>(views), L = static_cast<Eigen::Index>(lights);
  ParallelFor(texels, threads, [&](size_t texel, unsigned) {
    const auto gain = [&](Eigen::Index v) {
      return glm::dvec3(tabulated.ambient[texel * views + size_t(v)]) / std::numbers::pi;
    };
    const auto target = [&](Eigen::Index v, Eigen::Index l) {
      return glm::dvec3(tabulated.radiance[(texel * views + size_t(v)) * lights + size_t(l)]);
    };
    // Row v of the weighted shape: |g|·(g·L)/|g|² = ĝ·L, g = A(v)/π; views that
    // see (next to) nothing get no terms.
    Eigen::VectorXd weight(V);
    for (Eigen::Index v = 0; v < V; ++v) weight(v) = glm::length(gain(v));
    const double floor = 1e-6 * weight.maxCoeff();
    Matrix shape = Matrix::Zero(V, L);
    for (Eigen::Index v = 0; v < V; ++v) {
      if (!(weight(v) > floor)) continue;
      const glm::dvec3 direction = gain(v) / weight(v);
      for (Eigen::Index l = 0; l < L; ++l) shape(v, l) = glm::dot(direction, target(v, l));
    }
    Matrix a, b;
    FactorTable(shape, rank, a, b);
    for (Eigen::Index v = 0; v < V; ++v) {
      a.row(v) *= weight(v) > floor ? 1.0 / weight(v) : 0.0;
    }
    for (uint32_t k = 0; k < rank; ++k) {
      const size_t term = texel * rank + k;
      for (Eigen::Index v = 0; v < V; ++v) level.view_terms[term * views + size_t(v)] = static_cast<float>(a(v, k));
      for (Eigen::Index l = 0; l < L; ++l) level.light_terms[term * lights + size_t(l)] = static_cast<float>(b(l, k));
    }
    // The error as rendered: the stored (single) precision, the clamp at 0.
    const Matrix product = a.cast<float>().cast<double>() * b.cast<float>().cast<double>().transpose();
    for (Eigen::Index v = 0; v < V; ++v) {
      for (Eigen::Index l = 0; l < L; ++l) {
        const glm::dvec3 d = gain(v) * std::max(product(v, l), 0.0) - target(v, l);
        residual[texel] += glm::dot(d, d);
        total[texel] += target(v, l).x + target(v, l).y + target(v, l).z;
      }
    }
  });
  level.relative_rmse = RelativeRmse(residual, total, texels * views * lights * 3);
  return level;
}

}  // namespace

FactoredFabric FactorFabric(const TabulatedFabric& table, uint32_t rank, unsigned threads,
                            const std::function<void(double)>& progress) {
  const Stopwatch stopwatch;
  FactoredFabric fabric;
  fabric.rank = std::min<uint32_t>(
      rank, static_cast<uint32_t>(std::min(table.view_count(), table.light_count())));
  fabric.view_directions = table.view_directions;
  fabric.light_directions = table.light_directions;
  fabric.view_heights = table.view_heights;
  for (size_t j = 0; j < table.levels.size(); ++j) {
    fabric.levels.push_back(
        FactorLevel(table.levels[j], fabric.rank, table.view_count(), table.light_count(), threads));
    if (progress) progress(static_cast<double>(j + 1) / static_cast<double>(table.levels.size()));
  }
  fabric.seconds = stopwatch.Seconds();
  return fabric;
}

float FactoredShape(const FactoredFabric& fabric, uint32_t level_index, size_t texel, const GridPoint& view,
                    const GridPoint& light) {
  const FactoredLevel& level = fabric.levels.at(level_index);
  const size_t views = fabric.view_count(), lights = fabric.light_count();
  float sum = 0.0f;
  for (uint32_t k = 0; k < fabric.rank; ++k) {
    const size_t term = texel * fabric.rank + k;
    const float a =
        Bilinear<float>(view, GridSide(views), [&](size_t stored) { return level.view_terms[term * views + stored]; });
    const float b = Bilinear<float>(light, GridSide(lights),
                                    [&](size_t stored) { return level.light_terms[term * lights + stored]; });
    sum += a * b;
  }
  return sum;
}

glm::vec4 EvaluateFactored(const FactoredFabric& fabric, uint32_t level_index, size_t texel, glm::vec3 view,
                           glm::vec3 light) {
  const GridPoint v = LocateOnGrid(view, GridSide(fabric.view_count()));
  const GridPoint l = LocateOnGrid(light, GridSide(fabric.light_count()));
  const float shape = FactoredShape(fabric, level_index, texel, v, l);
  return GainTimesShape(fabric.levels.at(level_index), texel, fabric.view_count(), v, LightWeight(light, l),
                        glm::vec3(shape));
}

}  // namespace loom
