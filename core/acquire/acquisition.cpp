#include "core/acquire/acquisition.h"

#include <algorithm>
#include <cmath>
#include <optional>
#include <sstream>
#include <string>
#include <vector>

#include "core/acquire/hemisphere_directions.h"
#include "core/acquire/indirect_light.h"
#include "core/acquire/periodic_scene.h"
#include "core/acquire/random_stream.h"
#include "core/acquire/surface_point.h"
#include "core/acquire/fibre_walk.h"
#include "core/acquire/volume_radiance.h"
#include "core/acquire/yarn_radiance.h"
#include "core/acquire/yarn_shading.h"
#include "core/fabric/yarn_volume.h"
#include "core/spec/defaults.h"
#include "core/spec/limits.h"
#include "core/spec/validate.h"
#include "core/util/parallel_for.h"
#include "core/util/stopwatch.h"

namespace loom {
namespace {

// How far the sampling grid sits above the geometry (tile units).
constexpr float kTopFaceOffset = 1e-4f;

// --- Tile validation ------------------------------------------------------------------

template <typename... Parts>
std::string Cat(const Parts&... parts) {
  std::ostringstream out;
  (out << ... << parts);
  return out.str();
}

// One issue per kind of problem (the first offending element), not one per element.
ValidationIssues ValidateTile(const FabricTile& tile) {
  ValidationIssues issues;
  auto report = [&](std::string path, std::string message) { issues.push_back({std::move(path), std::move(message)}); };
  auto finite = [](glm::vec3 v) { return std::isfinite(v.x) && std::isfinite(v.y) && std::isfinite(v.z); };
  auto first_bad = [](const auto& values, auto bad) -> std::optional<size_t> {
    for (size_t i = 0; i < values.size(); ++i) {
      if (bad(values[i])) return i;
    }
    return std::nullopt;
  };
  const TriangleMesh& mesh = tile.mesh;
  const size_t vertices = mesh.positions.size();

  const bool range_ok = std::isfinite(tile.z_min) && std::isfinite(tile.z_max) && tile.z_min <= tile.z_max;
  if (!range_ok) report("tile.z_min", Cat("[", tile.z_min, ", ", tile.z_max, "] is not a finite range"));
  if (auto i = first_bad(mesh.positions, [&](glm::vec3 p) { return !finite(p); })) {
    report(Cat("tile.mesh.positions[", *i, "]"), "is not finite");
  } else if (range_ok) {
    // The sampling grid starts above z_max: geometry above it would be cut off.
    const float tolerance = 1e-4f * std::max({1.0f, std::abs(tile.z_min), std::abs(tile.z_max)});
    if (auto j = first_bad(mesh.positions, [&](glm::vec3 p) {
          return p.z < tile.z_min - tolerance || p.z > tile.z_max + tolerance;
        })) {
      report(Cat("tile.mesh.positions[", *j, "]"), Cat("z = ", mesh.positions[*j].z, " is outside [tile.z_min, tile.z_max] = [",
                                                        tile.z_min, ", ", tile.z_max, "]"));
    }
  }
  for (const auto& [name, size] : {std::pair{"normals", mesh.normals.size()}, std::pair{"tangents", mesh.tangents.size()}}) {
    if (size != vertices) report(Cat("tile.mesh.", name), Cat(size, " entries for ", vertices, " positions"));
  }
  if (auto i = first_bad(mesh.normals, [&](glm::vec3 n) { return !finite(n); })) {
    report(Cat("tile.mesh.normals[", *i, "]"), "is not finite");
  }
  if (auto i = first_bad(mesh.tangents, [&](glm::vec4 t) { return !finite(glm::vec3(t)); })) {
    report(Cat("tile.mesh.tangents[", *i, "]"), "is not finite");
  }
  if (mesh.indices.size() % 3 != 0) {
    report("tile.mesh.indices", Cat(mesh.indices.size(), " entries is not a multiple of 3"));
  }
  if (auto i = first_bad(mesh.indices, [&](uint32_t index) { return index >= vertices; })) {
    report(Cat("tile.mesh.indices[", *i, "]"), Cat(mesh.indices[*i], " is out of range (", vertices, " vertices)"));
  }
  if (tile.triangle_material.size() != mesh.triangle_count()) {
    report("tile.triangle_material",
           Cat(tile.triangle_material.size(), " entries for ", mesh.triangle_count(), " triangles"));
  }
  if (auto i = first_bad(tile.triangle_material, [&](uint32_t m) { return m >= tile.materials.size(); })) {
    report(Cat("tile.triangle_material[", *i, "]"),
           Cat(tile.triangle_material[*i], " is out of range (", tile.materials.size(), " materials)"));
  }
  for (size_t m = 0; m < tile.materials.size(); ++m) {
    const YarnMaterial& material = tile.materials[m];
    const std::string at = Cat("tile.materials[", m, "].");
    for (const auto& [name, albedo] : {std::pair{"diffuse_albedo", material.diffuse_albedo},
                                       std::pair{"specular_albedo", material.specular_albedo}}) {
      if (!finite(albedo) || glm::any(glm::lessThan(albedo, glm::vec3(0.0f))) ||
          glm::any(glm::greaterThan(albedo, glm::vec3(1.0f)))) {
        report(at + name, "every channel must be in [0, 1]");
      }
    }
    const glm::vec3 sum = material.diffuse_albedo + material.specular_albedo;
    if (glm::any(glm::greaterThan(sum, glm::vec3(1.0f + kAlbedoSumTolerance)))) {
      report(at + "diffuse_albedo", "diffuse + specular albedo exceeds 1 in a channel (energy conservation)");
    }
    if (!std::isfinite(material.specular_exponent) || material.specular_exponent < 0.0f) {
      report(at + "specular_exponent", Cat(material.specular_exponent, " is not a finite number ≥ 0"));
    }
    if (material.model == YarnShadingModel::kMicroflake) {
      if (!(material.roughness > 0.0f && material.roughness <= 1.0f)) {
        report(at + "roughness", Cat(material.roughness, " is not in (0, 1]"));
      }
      if (!(material.height_scale >= 0.0f && material.height_scale <= kMaxHeightScale)) {
        report(at + "height_scale", Cat(material.height_scale, " is not in [0, ", kMaxHeightScale, "]"));
      }
      if (!(material.lambert_blend >= 0.0f && material.lambert_blend <= 1.0f)) {
        report(at + "lambert_blend", Cat(material.lambert_blend, " is not in [0, 1]"));
      }
      if (!(material.diffuse_transmission >= 0.0f && material.diffuse_transmission <= 1.0f)) {
        report(at + "diffuse_transmission", Cat(material.diffuse_transmission, " is not in [0, 1]"));
      }
    }
  }
  return issues;
}

// --- Helpers ----------------------------------------------------------------------------

// |tan θ| of the direction closest to the horizon (above or below it): how far a ray
// travels sideways per unit of depth.
float MaxTangent(const std::vector<glm::vec3>& directions) {
  float result = 0.0f;
  for (const glm::vec3& d : directions) {
    result = std::max(result, std::sqrt(std::max(0.0f, 1.0f - d.z * d.z)) / std::abs(d.z));
  }
  return result;
}


// Progress over the whole acquisition: each stage has a weight (its estimated
// rays) and reports the fraction of it that is done.
class ProgressTracker {
 public:
  ProgressTracker(const AcquireProgress& callback, double total) : callback_(callback), total_(std::max(total, 1.0)) {}

  void Begin(std::string stage, double weight) {
    base_ += weight_;
    weight_ = weight;
    stage_ = std::move(stage);
    Report(0.0);
  }
  void Report(double fraction) const {
    if (callback_) callback_(std::min(1.0, (base_ + fraction * weight_) / total_), stage_);
  }
  std::function<void(double)> Stage() const {
    return [this](double fraction) { Report(fraction); };
  }

 private:
  const AcquireProgress& callback_;
  double total_;
  double base_ = 0.0;
  double weight_ = 0.0;
  std::string stage_;
};

// Zeroes non-finite channels (and counts them): the samples never hold NaN or Inf.
glm::vec3 Finite(glm::vec3 v, uint64_t& replaced) {
  for (int c = 0; c < 3; ++c) {
    if (!std::isfinite(v[c])) {
      v[c] = 0.0f;
      ++replaced;
    }
  }
  return v;
}

// Everything a texel's work item reads.
struct TexelPass {
  const FabricTile& tile;
  const PeriodicScene& scene;
  const std::vector<YarnBrdf>& brdfs;
  const VertexIrradiance& indirect;  // light_count 0 without bounces
  uint32_t supersampling;
  uint64_t seed;
  float top;                         // z the rays start at
  size_t first_light, light_count;   // the batch of lights
  const std::vector<LightTransmittance>& transmittance;  // per light, for volumetric yarn
};

// Scratch space of one worker: radiance sums and interpolated irradiance per light.
struct TexelScratch {
  std::vector<glm::vec3> sum, irradiance;
};

// Sub-sample (i, j) of `texel`'s s×s cells: a point of the tile's [0,1)² square.
// The tile is a grid of (res·s)² cells with one jittered ray each, every cell's
// jitter drawn from its own stream: 8 texels of 8×8 rays and 32 texels of 2×2 cast
// the same rays, so a mip level pools the same samples whatever resolution it was
// acquired at (fabric_fit.h), and the planner's resolution variations change the
// finest level only. The same pattern for every view: a view's samples then differ
// from the next view's only by the projection.
glm::vec2 SubSample(uint32_t res, uint32_t s, uint64_t seed, size_t texel, uint32_t i, uint32_t j) {
  const uint64_t side = uint64_t{res} * s;
  const uint64_t cell_x = uint64_t{texel % res} * s + i, cell_y = uint64_t{texel / res} * s + j;
  RandomStream random(seed, RandomStream::kTexelJitter, cell_y * side + cell_x);
  const glm::vec2 cell(static_cast<float>(cell_x) + random.Uniform(), static_cast<float>(cell_y) + random.Uniform());
  return cell / static_cast<float>(side);
}

// Where the ray of view `v` through `xy` on the plane z = `height` starts, on the
// plane z = `top` above it (wrapped into the tile by PeriodicScene).
glm::vec3 RayStart(glm::vec2 xy, float height, glm::vec3 v, float top) {
  return {xy + glm::vec2(v) / v.z * (top - height), top};
}

// Per view, the mean z at which the rays of every texel's sub-samples, cast from the
// top face, first meet yarn; `top` for a view none of whose rays does. Sums are per
// texel, then over texels in order: the same for any thread count.
std::vector<float> ViewDepthHeights(const PeriodicScene& scene, const RadianceSamples& samples, uint32_t s,
                                    uint64_t seed, float top, unsigned threads, uint64_t& rays,
                                    const std::function<void(double)>& progress) {
  const size_t texels = samples.texel_count(), views = samples.view_count();
  std::vector<glm::dvec2> sums(texels * views);  // (Σ z, hits) per texel and view
  ParallelFor(texels, threads, [&](size_t texel, unsigned) {
    for (size_t view = 0; view < views; ++view) {
      const glm::vec3 v = samples.view_directions[view];
      glm::dvec2& sum = sums[texel * views + view];
      for (uint32_t j = 0; j < s; ++j) {
        for (uint32_t i = 0; i < s; ++i) {
          const auto hit = scene.Intersect({SubSample(samples.resolution, s, seed, texel, i, j), top}, -v);
          if (hit) sum += glm::dvec2(hit->position.z, 1.0);
        }
      }
    }
  }, [&](size_t done) { progress(static_cast<double>(done) / static_cast<double>(texels)); });
  rays += uint64_t{texels} * views * s * s;
  std::vector<float> heights(views, top);
  for (size_t view = 0; view < views; ++view) {
    glm::dvec2 total(0.0);
    for (size_t texel = 0; texel < texels; ++texel) total += sums[texel * views + view];
    if (total.y > 0) heights[view] = static_cast<float>(total.x / total.y);
  }
  return heights;
}

// Fibre walks a sub-sample's ray through volumetric yarn takes (core/acquire/fibre_walk.h).
constexpr int kAcquisitionWalks = 4;

// The volumetric yarn along one sub-sample's ray (core/acquire/volume_radiance.h): adds
// each of the batch's lights' radiance, premultiplied by the ray's opacity, to
// scratch.sum, the light scattered between fibres by kAcquisitionWalks walks from a step
// drawn by its weight; returns the opacity.
float AcquireVolumeRay(const TexelPass& pass, const RadianceSamples& samples, glm::vec3 start, glm::vec3 v, float jitter,
                       RandomStream& walk, TexelScratch& scratch) {
  const std::vector<YarnMaterial>& materials = pass.tile.materials;
  auto light_direction = [&](size_t light) { return samples.light_directions[pass.first_light + light]; };
  WeightedStep walked;
  const float transmittance = MarchVolume(*pass.tile.volume, start, -v, jitter, [&](const VolumeStep& step) {
    const YarnMaterial& material = materials[step.sample.material];
    for (size_t light = 0; light < pass.light_count; ++light) {
      const glm::vec3 f = FibreScattering(material, step.sample.fibre, light_direction(light), v);
      if (f == glm::vec3(0.0f)) continue;
      scratch.sum[light] += step.weight * f * pass.transmittance[pass.first_light + light](step.position);
    }
    walked.Offer(step, walk);
  });
  if (const std::optional<VolumeStep>& step = walked.chosen()) {
    for (int i = 0; i < kAcquisitionWalks; ++i) {
      WalkFibres(TileVolumeMedium{*pass.tile.volume}, materials, step->position, step->sample, walk,
                 [&](glm::vec3 q, const VolumeSample& at, glm::vec3 throughput) {
                   const glm::vec3 weight = walked.total() / kAcquisitionWalks * throughput;
                   const glm::vec3 albedo = FibreAlbedo(materials[at.material].diffuse_albedo);
                   for (size_t light = 0; light < pass.light_count; ++light) {
                     const glm::vec3 f = FibreDiffuseScattering(albedo, at.fibre, light_direction(light));
                     scratch.sum[light] += weight * f * pass.transmittance[pass.first_light + light](q);
                   }
                 });
    }
  }
  return 1.0f - transmittance;
}

// One texel, every view, the batch's lights; returns the texel's normal sum.
glm::vec3 AcquireTexel(const TexelPass& pass, RadianceSamples& samples, size_t texel, TexelScratch& scratch,
                       uint64_t& rays, uint64_t& replaced) {
  const uint32_t s = pass.supersampling;
  const bool indirect = pass.indirect.light_count > 0;
  scratch.sum.resize(pass.light_count);
  scratch.irradiance.resize(pass.light_count);
  glm::vec3 normal_sum(0.0f);
  for (size_t view = 0; view < samples.view_count(); ++view) {
    const glm::vec3 v = samples.view_directions[view];
    std::fill(scratch.sum.begin(), scratch.sum.end(), glm::vec3(0.0f));
    float covered = 0.0f;  // rays that met yarn; for volumetric yarn, their opacities
    for (uint32_t j = 0; j < s; ++j) {
      for (uint32_t i = 0; i < s; ++i) {
        const glm::vec2 xy = SubSample(samples.resolution, s, pass.seed, texel, i, j);
        const glm::vec3 start = RayStart(xy, samples.view_heights[view], v, pass.top);
        ++rays;
        const auto hit = pass.scene.Intersect(start, -v);
        if (pass.tile.volume) {
          // The tubes the volume is centred on give the texel's normal.
          if (hit) {
            const SurfacePoint point = MakeSurfacePoint(pass.tile, *hit, -v);
            normal_sum += point.front ? point.normal : -point.normal;
          }
          const uint64_t ray = (texel * samples.view_count() + view) * s * s + j * s + i;
          RandomStream jitter(pass.seed, RandomStream::kVolumeJitter, ray);
          RandomStream walk(pass.seed, RandomStream::kFibreWalk, ray);
          covered += AcquireVolumeRay(pass, samples, start, v, jitter.Uniform(), walk, scratch);
          continue;
        }
        if (!hit) continue;
        covered += 1.0f;
        const SurfacePoint point = MakeSurfacePoint(pass.tile, *hit, -v);
        normal_sum += point.front ? point.normal : -point.normal;
        if (!point.front) continue;  // the inside of a yarn: opaque and black

        const YarnBrdf& brdf = pass.brdfs[point.material];
        if (indirect) pass.indirect.Interpolate(pass.tile.mesh, *hit, scratch.irradiance.data());
        for (size_t light = 0; light < pass.light_count; ++light) {
          const glm::vec3 l = samples.light_directions[pass.first_light + light];
          glm::vec3 radiance = indirect ? brdf.diffuse() * scratch.irradiance[light] : glm::vec3(0.0f);
          radiance += DirectYarnRadiance(pass.scene, pass.tile, point, brdf, l, v, rays);
          scratch.sum[light] += radiance;
        }
      }
    }
    samples.alpha[samples.AlphaIndex(texel, view)] = covered / static_cast<float>(s * s);
    for (size_t light = 0; light < pass.light_count; ++light) {
      const glm::vec3 mean = covered > 0.0f ? scratch.sum[light] / covered : glm::vec3(0.0f);
      samples.radiance[samples.RadianceIndex(texel, view, pass.first_light + light)] = Finite(mean, replaced);
    }
  }
  return normal_sum;
}

}  // namespace

RadianceSamples Acquire(const FabricTile& tile, const v1::PrecomputeSettings& requested,
                        const AcquireProgress& progress, AcquireStats* stats, const AcquireOptions& options,
                        LightSide side) {
  ThrowIfAny(Validate(requested));
  ThrowIfAny(ValidateTile(tile));
  const Stopwatch stopwatch;
  const v1::PrecomputeSettings settings = WithDefaults(requested);
  const unsigned threads = ResolveThreadCount(options.threads);

  std::vector<glm::vec3> light_directions = HemisphereGridDirections(settings.light_directions());
  if (side == LightSide::kBack) light_directions = MirroredThroughTheSurface(std::move(light_directions));
  RadianceSamples samples(settings.spatial_resolution(), HemisphereGridDirections(settings.view_directions()),
                          std::move(light_directions));
  const size_t texels = samples.texel_count();
  const size_t views = samples.view_count();
  const size_t lights = samples.light_count();
  const uint32_t s = settings.supersampling();
  // Volumetric yarn has no inter-reflection (core/acquire/volume_radiance.h).
  const uint32_t bounces = tile.volume ? 0 : settings.indirect_bounces();
  const size_t vertices = tile.mesh.positions.size();

  // Batches of lights whose indirect irradiance (3 arrays while it is computed)
  // fits the memory budget.
  const size_t per_light = 3 * sizeof(glm::vec3) * std::max<size_t>(vertices, 1);
  const size_t batch = bounces == 0 ? lights : std::clamp<size_t>(options.indirect_memory_bytes / per_light, 1, lights);
  const size_t batches = (lights + batch - 1) / batch;

  // Progress weights: the rays each stage casts (estimated before casting).
  const double gather_rays = bounces > 0 ? double(vertices) * IndirectLight::kGatherStrata * IndirectLight::kGatherStrata : 0;
  auto vertex_rays = [&](size_t count) { return bounces > 0 ? double(vertices) * count : 0.0; };
  auto texel_rays = [&](size_t count) { return double(texels) * views * s * s * (1.0 + count); };
  const bool view_depth = settings.sampling_plane() == v1::SAMPLING_PLANE_VIEW_DEPTH;
  // Volumetric yarn: each light's transmittance grid, its columns marched like rays.
  std::vector<LightTransmittance> transmittance;
  if (tile.volume) {
    for (const glm::vec3& l : samples.light_directions) transmittance.emplace_back(*tile.volume, l);
  }
  const double column_rays = transmittance.empty() ? 0.0 : double(transmittance[0].column_count()) * lights;
  ProgressTracker tracker(progress, gather_rays + vertex_rays(lights) + texel_rays(lights) + (batches - 1) * texel_rays(0) +
                                        (view_depth ? texel_rays(0) : 0.0) + column_rays);

  // The slab of geometry a ray crosses; the repeated scene covers the sideways
  // travel across it at the most grazing view (from the top face down) and the
  // most grazing light (from the bottom of the geometry up).
  tracker.Begin("building the repeated scene", 0);
  const float top = tile.z_max + kTopFaceOffset;
  const float depth = top - tile.z_min + 2 * kRayOffset;
  const float reach = depth * std::max(MaxTangent(samples.view_directions), MaxTangent(samples.light_directions));
  const PeriodicScene scene(tile.mesh, reach);

  PerWorkerCount rays(threads), replaced(threads);
  if (view_depth) {
    tracker.Begin("sampling planes", texel_rays(0));
    samples.view_heights = ViewDepthHeights(scene, samples, s, settings.seed(), top, threads, rays[0], tracker.Stage());
  } else {
    samples.view_heights.assign(views, top);
  }

  if (!transmittance.empty()) {
    tracker.Begin("volume: light transmittance", column_rays);
    constexpr size_t kColumnsPerItem = 256;
    const size_t per_light = (transmittance[0].column_count() + kColumnsPerItem - 1) / kColumnsPerItem;
    ParallelFor(
        lights * per_light, threads,
        [&](size_t item, unsigned) {
          transmittance[item / per_light].MarchColumns(*tile.volume, (item % per_light) * kColumnsPerItem, kColumnsPerItem);
        },
        [&](size_t done) { tracker.Report(static_cast<double>(done) / static_cast<double>(lights * per_light)); });
    rays[0] += static_cast<uint64_t>(column_rays);
  }

  std::vector<YarnBrdf> brdfs(tile.materials.begin(), tile.materials.end());
  std::optional<IndirectLight> indirect;
  if (bounces > 0) {
    tracker.Begin("indirect light: gathering", gather_rays);
    indirect.emplace(tile, scene, bounces, settings.seed(), threads, tracker.Stage());
  }

  std::vector<TexelScratch> scratch(threads);
  std::vector<glm::vec3> normal_sums(texels);
  for (size_t first = 0; first < lights; first += batch) {
    const size_t count = std::min(batch, lights - first);
    const std::string range = Cat("lights ", first + 1, "-", first + count, " of ", lights);
    VertexIrradiance irradiance;
    if (indirect) {
      tracker.Begin("indirect light: " + range, vertex_rays(count));
      const auto batch_begin = samples.light_directions.begin() + static_cast<std::ptrdiff_t>(first);
      irradiance = indirect->Irradiance(std::vector<glm::vec3>(batch_begin, batch_begin + static_cast<std::ptrdiff_t>(count)),
                                        threads, tracker.Stage());
      rays[0] += irradiance.rays;
    }
    tracker.Begin("radiance: " + range, texel_rays(count));
    const TexelPass pass{tile, scene, brdfs, irradiance, s, settings.seed(), top, first, count, transmittance};
    // Every batch recasts the primary rays and rewrites alpha and the normal sums
    // with the same values: cheaper than keeping hit points between batches.
    ParallelFor(
        texels, threads,
        [&](size_t texel, unsigned worker) {
          normal_sums[texel] = AcquireTexel(pass, samples, texel, scratch[worker], rays[worker], replaced[worker]);
        },
        [&](size_t done) { tracker.Report(static_cast<double>(done) / static_cast<double>(texels)); });
  }

  for (size_t texel = 0; texel < texels; ++texel) {
    samples.normals[texel] = SafeNormalize(normal_sums[texel], glm::vec3(0, 0, 1));
    samples.tangents[texel] = TexelTangent(samples.normals[texel]);
    double hits = 0.0;  // over every view
    for (size_t view = 0; view < views; ++view) hits += double{samples.alpha[samples.AlphaIndex(texel, view)]} * s * s;
    samples.normal_lengths[texel] =
        hits > 0.0 ? static_cast<float>(std::min(1.0, glm::length(glm::dvec3(normal_sums[texel])) / hits)) : 0.0f;
  }
  tracker.Begin("done", 0);

  if (stats) {
    stats->seconds = stopwatch.Seconds();
    stats->rays = rays.Total() + (indirect ? indirect->gather_rays() : 0);
    stats->threads = threads;
    stats->tiles_x = scene.grid_size().x;
    stats->tiles_y = scene.grid_size().y;
    stats->light_batches = static_cast<uint32_t>(batches);
    stats->non_finite_values = replaced.Total();
  }
  return samples;
}

}  // namespace loom
