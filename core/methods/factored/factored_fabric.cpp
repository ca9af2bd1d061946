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

// One texel's channel: the top `rank` singular triplets of its V×L table M, from the
// eigenvectors of M·Mᵀ (V×V), so
// A_k = √σ_k u_k and B_k = Mᵀ u_k / √σ_k = √σ_k v_k. Returns the squared residual
// ‖M‖² − Σ σ_k².
double FactorChannel(const Matrix& table, uint32_t rank, Matrix& view_terms, Matrix& light_terms) {
  const Matrix gram = table * table.transpose();
  const Eigen::SelfAdjointEigenSolver<Matrix> eigen(gram);
  const Eigen::Index views = table.rows();
  view_terms.setZero(views, rank);
  light_terms.setZero(table.cols(), rank);
  double kept = 0.0;
  for (uint32_t k = 0; k < rank; ++k) {
    const Eigen::Index column = views - 1 - static_cast<Eigen::Index>(k);  // eigenvalues ascend
    const double lambda = eigen.eigenvalues()(column);
    if (!(lambda > 1e-20)) break;
    kept += lambda;
    Eigen::VectorXd u = eigen.eigenvectors().col(column);
    if (u.sum() < 0.0) u = -u;  // a sign per term, the same on every run
    const double scale = std::sqrt(std::sqrt(lambda));  // √σ
    view_terms.col(k) = scale * u;
    light_terms.col(k) = table.transpose() * u / scale;
  }
  return std::max(table.squaredNorm() - kept, 0.0);
}

FactoredLevel FactorLevel(const TabulatedLevel& tabulated, uint32_t rank, size_t views, size_t lights,
                          unsigned threads) {
  FactoredLevel level;
  level.resolution = tabulated.resolution;
  level.alpha = tabulated.alpha;
  const size_t texels = tabulated.texel_count();
  level.view_terms.assign(texels * rank * views, glm::vec3(0.0f));
  level.light_terms.assign(texels * rank * lights, glm::vec3(0.0f));
  level.ambient.assign(texels * views, glm::vec3(0.0f));
  std::vector<double> residual(texels, 0.0), total(texels, 0.0);
  const float solid_angle = 2.0f * std::numbers::pi_v<float> / static_cast<float>(lights);
  ParallelFor(texels, threads, [&](size_t texel, unsigned) {
    Matrix table(static_cast<Eigen::Index>(views), static_cast<Eigen::Index>(lights));
    Matrix a, b;
    for (int c = 0; c < 3; ++c) {
      for (size_t view = 0; view < views; ++view) {
        for (size_t light = 0; light < lights; ++light) {
          table(Eigen::Index(view), Eigen::Index(light)) = tabulated.radiance[(texel * views + view) * lights + light][c];
        }
      }
      residual[texel] += FactorChannel(table, rank, a, b);
      total[texel] += table.sum();
      for (uint32_t k = 0; k < rank; ++k) {
        const size_t term = texel * rank + k;
        float light_sum = 0.0f;
        for (size_t light = 0; light < lights; ++light) {
          level.light_terms[term * lights + light][c] = static_cast<float>(b(Eigen::Index(light), k));
          light_sum += static_cast<float>(b(Eigen::Index(light), k));
        }
        for (size_t view = 0; view < views; ++view) {
          const float value = static_cast<float>(a(Eigen::Index(view), k));
          level.view_terms[term * views + view][c] = value;
          level.ambient[texel * views + view][c] += solid_angle * value * light_sum;
        }
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

glm::vec4 EvaluateFactored(const FactoredFabric& fabric, uint32_t level_index, size_t texel, glm::vec3 view,
                           glm::vec3 light) {
  const FactoredLevel& level = fabric.levels.at(level_index);
  const size_t views = fabric.view_count(), lights = fabric.light_count();
  const uint32_t view_side = GridSide(views);
  const uint32_t light_side = GridSide(lights);
  const GridPoint v = LocateOnGrid(view, view_side);
  const GridPoint l = LocateOnGrid(light, light_side);
  glm::vec3 sum(0.0f);
  for (uint32_t k = 0; k < fabric.rank; ++k) {
    const size_t term = texel * fabric.rank + k;
    const glm::vec3 a =
        Bilinear<glm::vec3>(v, view_side, [&](size_t stored) { return level.view_terms[term * views + stored]; });
    const glm::vec3 b =
        Bilinear<glm::vec3>(l, light_side, [&](size_t stored) { return level.light_terms[term * lights + stored]; });
    sum += a * b;
  }
  const float alpha = Bilinear<float>(v, view_side, [&](size_t stored) { return level.alpha[texel * views + stored]; });
  return {LightWeight(light, l) * glm::max(sum, glm::vec3(0.0f)), glm::mix(alpha, 1.0f, v.beyond_ring)};
}

}  // namespace loom
