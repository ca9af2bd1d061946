#include "core/acquire/indirect_light.h"

#include <algorithm>
#include <cmath>

#include "core/acquire/hemisphere_directions.h"
#include "core/util/parallel_for.h"
#include "core/acquire/random_stream.h"
#include "core/acquire/surface_point.h"

namespace loom {
namespace {

// An orthonormal basis (t, b, n) around unit n without branches on n's direction
// that would break continuity (Duff et al. 2017, "Building an orthonormal basis,
// revisited").
void Basis(glm::vec3 n, glm::vec3& t, glm::vec3& b) {
  const float sign = std::copysign(1.0f, n.z);
  const float a = -1.0f / (sign + n.z);
  const float c = n.x * n.y * a;
  t = {1.0f + sign * n.x * n.x * a, sign * c, -sign * n.x};
  b = {c, sign + n.y * n.y * a, -n.y};
}

}  // namespace

void VertexIrradiance::Interpolate(const TriangleMesh& mesh, const RayHit& hit, glm::vec3* out) const {
  const uint32_t* corner = &mesh.indices[3 * size_t{hit.triangle}];
  const float w1 = hit.barycentric.x, w2 = hit.barycentric.y, w0 = 1.0f - w1 - w2;
  const glm::vec3* e0 = &values[corner[0] * light_count];
  const glm::vec3* e1 = &values[corner[1] * light_count];
  const glm::vec3* e2 = &values[corner[2] * light_count];
  for (size_t light = 0; light < light_count; ++light) out[light] = w0 * e0[light] + w1 * e1[light] + w2 * e2[light];
}

IndirectLight::IndirectLight(const FabricTile& tile, const PeriodicScene& scene, uint32_t bounces, uint64_t seed,
                             unsigned threads, const std::function<void(double)>& progress)
    : tile_(tile), scene_(scene), bounces_(bounces) {
  const TriangleMesh& mesh = tile.mesh;
  const size_t vertices = mesh.positions.size();
  normals_.resize(vertices);
  for (size_t i = 0; i < vertices; ++i) normals_[i] = SafeNormalize(mesh.normals[i], glm::vec3(0.0f));

  constexpr uint32_t kRays = kGatherStrata * kGatherStrata;
  std::vector<std::vector<Entry>> rows(vertices);
  threads = ResolveThreadCount(threads);
  PerWorkerCount rays(threads);
  ParallelFor(
      vertices, threads,
      [&](size_t i, unsigned worker) {
        const glm::vec3 n = normals_[i];
        if (n == glm::vec3(0.0f)) return;  // no hemisphere to gather over
        glm::vec3 t, b;
        Basis(n, t, b);
        const glm::vec3 origin = mesh.positions[i] + n * kRayOffset;
        RandomStream random(seed, RandomStream::kGatherDirections, i);
        std::vector<Entry>& row = rows[i];
        for (uint32_t sy = 0; sy < kGatherStrata; ++sy) {
          for (uint32_t sx = 0; sx < kGatherStrata; ++sx) {
            // Malley's method: uniform points on the disk lifted to the hemisphere
            // are cosine-distributed, so each ray carries weight 1/64 of π·L.
            const float u = (sx + random.Uniform()) / kGatherStrata;
            const float v = (sy + random.Uniform()) / kGatherStrata;
            const glm::vec2 disk = ConcentricSquareToDisk({u, v});
            const float z = std::sqrt(std::max(0.0f, 1.0f - glm::dot(disk, disk)));
            const glm::vec3 direction = SafeNormalize(t * disk.x + b * disk.y + n * z, n);
            ++rays[worker];
            const auto hit = scene.Intersect(origin, direction);
            if (!hit) continue;
            const SurfacePoint point = MakeSurfacePoint(tile, *hit, direction);
            if (!point.front) continue;  // the inside of a yarn is unlit
            const glm::vec3 albedo = tile.materials[point.material].diffuse_albedo / static_cast<float>(kRays);
            const uint32_t* corner = &mesh.indices[3 * size_t{hit->triangle}];
            const float w1 = hit->barycentric.x, w2 = hit->barycentric.y;
            row.push_back({corner[0], albedo * (1.0f - w1 - w2)});
            row.push_back({corner[1], albedo * w1});
            row.push_back({corner[2], albedo * w2});
          }
        }
        // Merge entries per vertex (in vertex order: the bounce sums then run in a
        // fixed order and walk the irradiance array forwards).
        std::sort(row.begin(), row.end(), [](const Entry& a, const Entry& b) { return a.vertex < b.vertex; });
        size_t kept = 0;
        for (const Entry& entry : row) {
          if (kept > 0 && row[kept - 1].vertex == entry.vertex) {
            row[kept - 1].weight += entry.weight;
          } else {
            row[kept++] = entry;
          }
        }
        row.resize(kept);
      },
      [&](size_t done) {
        if (progress) progress(static_cast<double>(done) / static_cast<double>(std::max<size_t>(vertices, 1)));
      });
  gather_rays_ = rays.Total();

  row_start_.assign(vertices + 1, 0);
  for (size_t i = 0; i < vertices; ++i) row_start_[i + 1] = row_start_[i] + rows[i].size();
  entries_.reserve(row_start_[vertices]);
  for (std::vector<Entry>& row : rows) {
    entries_.insert(entries_.end(), row.begin(), row.end());
    std::vector<Entry>().swap(row);
  }
}

VertexIrradiance IndirectLight::Irradiance(const std::vector<glm::vec3>& lights, unsigned threads,
                                           const std::function<void(double)>& progress) const {
  const TriangleMesh& mesh = tile_.mesh;
  const size_t vertices = mesh.positions.size();
  const size_t count = lights.size();
  threads = ResolveThreadCount(threads);
  // Progress: the shadow-ray pass is the cost; the bounces are sparse products.
  auto report = [&](size_t done) {
    if (progress) progress(static_cast<double>(done) / static_cast<double>(std::max<size_t>(vertices, 1)));
  };

  // E₀: direct irradiance per vertex.
  std::vector<glm::vec3> previous(vertices * count, glm::vec3(0.0f));
  PerWorkerCount rays(threads);
  ParallelFor(
      vertices, threads,
      [&](size_t i, unsigned worker) {
        const glm::vec3 n = normals_[i];
        const glm::vec3 origin = mesh.positions[i] + n * kRayOffset;
        for (size_t light = 0; light < count; ++light) {
          const float cosine = glm::dot(n, lights[light]);
          if (!(cosine > 0.0f)) continue;
          ++rays[worker];
          if (!scene_.Occluded(origin, lights[light])) previous[i * count + light] = glm::vec3(cosine);
        }
      },
      report);

  VertexIrradiance result{count, std::vector<glm::vec3>(vertices * count, glm::vec3(0.0f)), rays.Total()};
  std::vector<glm::vec3> next(vertices * count);
  for (uint32_t bounce = 0; bounce < bounces_; ++bounce) {
    ParallelFor(vertices, threads, [&](size_t i, unsigned) {
      glm::vec3* out = &next[i * count];
      std::fill(out, out + count, glm::vec3(0.0f));
      for (size_t e = row_start_[i]; e < row_start_[i + 1]; ++e) {
        const glm::vec3* in = &previous[entries_[e].vertex * count];
        for (size_t light = 0; light < count; ++light) out[light] += entries_[e].weight * in[light];
      }
      glm::vec3* sum = &result.values[i * count];
      for (size_t light = 0; light < count; ++light) sum[light] += out[light];
    });
    previous.swap(next);
  }
  return result;
}

}  // namespace loom
