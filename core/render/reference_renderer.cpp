#include "core/render/reference_renderer.h"

#include <embree3/rtcore.h>

#include <algorithm>
#include <cmath>
#include <limits>
#include <memory>
#include <optional>

#include "core/acquire/embree_mesh.h"
#include "core/acquire/indirect_light.h"
#include "core/acquire/periodic_scene.h"
#include "core/acquire/random_stream.h"
#include "core/acquire/surface_point.h"
#include "core/acquire/fibre_walk.h"
#include "core/acquire/volume_radiance.h"
#include "core/acquire/yarn_radiance.h"
#include "core/acquire/yarn_shading.h"
#include "core/fabric/fabric_tile.h"
#include "core/fabric/yarn_volume.h"
#include "core/scene/camera.h"
#include "core/scene/scene_light.h"
#include "core/spec/defaults.h"
#include "core/util/error.h"
#include "core/util/parallel_for.h"
#include "core/util/stopwatch.h"
#include "core/util/vector_math.h"

namespace loom {
namespace {

constexpr float kInfinity = std::numeric_limits<float>::infinity();
constexpr float kPi = 3.14159265358979323846f;
// How far above the tile geometry a camera ray enters the shell (tile units), as
// acquisition's sampling grid sits above the tile.
constexpr float kShellTopOffset = 1e-4f;
// Surfaces a camera ray may pass through (holes, then what lies behind) before it
// counts as reaching the background.
constexpr int kMaxSurfaceCrossings = 8;
// A camera ray whose throughput through volumetric yarn falls below this ends there.
constexpr float kMinThroughput = 1e-4f;
// Walks through the repeated tile are continued exactly, so `reach` only sizes the
// instance grid against the number of Embree calls per ray (periodic_scene.h).
constexpr float kTileReach = 4.0f;

// --- The macro scene: every world mesh in one Embree scene ---------------------------

struct MacroHit {
  uint32_t mesh = 0;
  uint32_t triangle = 0;
  glm::vec2 barycentric{};  // weights of the triangle's 2nd and 3rd vertex
  float t = 0.0f;
};

class MacroScene {
 public:
  explicit MacroScene(const std::vector<SceneMesh>& meshes) {
    device_ = rtcNewDevice(nullptr);
    if (device_ == nullptr) throw Error(ErrorCode::kInternal, "Embree: cannot create a device");
    scene_ = rtcNewScene(device_);
    rtcSetSceneFlags(scene_, RTC_SCENE_FLAG_ROBUST);  // no ray slips between two triangles
    for (size_t i = 0; i < meshes.size(); ++i) {
      const TriangleMesh& mesh = meshes[i].mesh;
      if (mesh.triangle_count() == 0) continue;
      AttachTriangleMesh(device_, scene_, mesh, static_cast<unsigned>(i));
    }
    rtcCommitScene(scene_);
    CheckEmbree(device_, "building the scene's BVH");
  }
  ~MacroScene() {
    rtcReleaseScene(scene_);
    rtcReleaseDevice(device_);
  }
  MacroScene(const MacroScene&) = delete;
  MacroScene& operator=(const MacroScene&) = delete;

  std::optional<MacroHit> Intersect(glm::vec3 origin, glm::vec3 direction, float tnear, float tfar) const {
    RTCIntersectContext context;
    rtcInitIntersectContext(&context);
    RTCRayHit ray{};
    SetRay(ray.ray, origin, direction, tnear, tfar);
    ray.hit.geomID = RTC_INVALID_GEOMETRY_ID;
    ray.hit.instID[0] = RTC_INVALID_GEOMETRY_ID;
    rtcIntersect1(scene_, &context, &ray);
    if (ray.hit.geomID == RTC_INVALID_GEOMETRY_ID) return std::nullopt;
    return MacroHit{ray.hit.geomID, ray.hit.primID, {ray.hit.u, ray.hit.v}, ray.ray.tfar};
  }

  bool Occluded(glm::vec3 origin, glm::vec3 direction, float tnear) const {
    RTCIntersectContext context;
    rtcInitIntersectContext(&context);
    RTCRay ray{};
    SetRay(ray, origin, direction, tnear, kInfinity);
    rtcOccluded1(scene_, &context, &ray);
    return ray.tfar < 0.0f;  // Embree sets tfar to −∞ on a hit
  }

 private:
  static void SetRay(RTCRay& ray, glm::vec3 origin, glm::vec3 direction, float tnear, float tfar) {
    ray.org_x = origin.x, ray.org_y = origin.y, ray.org_z = origin.z;
    ray.dir_x = direction.x, ray.dir_y = direction.y, ray.dir_z = direction.z;
    ray.tnear = tnear;
    ray.tfar = tfar;
    ray.mask = ~0u;
  }
  RTCDevice device_ = nullptr;
  RTCScene scene_ = nullptr;
};

// --- The surface frame and the tile ↔ world map --------------------------------------

// The affine map of the header: tile vectors → world vectors through the columns
// s_u·t, s_v·b, s_u·n, with t, b, n orthonormal.
struct SurfaceFrame {
  glm::vec3 t{1, 0, 0}, b{0, 1, 0}, n{0, 0, 1};
  float scale_u = 1.0f, scale_v = 1.0f;

  glm::vec3 ToTile(glm::vec3 w) const { return {glm::dot(t, w) / scale_u, glm::dot(b, w) / scale_v, glm::dot(n, w) / scale_u}; }
  glm::vec3 ToWorld(glm::vec3 v) const { return t * (scale_u * v.x) + b * (scale_v * v.y) + n * (scale_u * v.z); }
};

// |∂P/∂u| and |∂P/∂v| of one triangle (pbrt's dpdu, dpdv); zero when the triangle's
// uvs are degenerate.
glm::vec2 UvJacobianScale(const TriangleMesh& mesh, uint32_t triangle) {
  const uint32_t* corner = &mesh.indices[3 * size_t{triangle}];
  const glm::vec3 dp1 = mesh.positions[corner[1]] - mesh.positions[corner[0]];
  const glm::vec3 dp2 = mesh.positions[corner[2]] - mesh.positions[corner[0]];
  const glm::vec2 duv1 = mesh.uvs[corner[1]] - mesh.uvs[corner[0]];
  const glm::vec2 duv2 = mesh.uvs[corner[2]] - mesh.uvs[corner[0]];
  const float determinant = duv1.x * duv2.y - duv1.y * duv2.x;
  if (!(std::abs(determinant) > 0.0f)) return glm::vec2(0.0f);
  const glm::vec3 dpdu = (duv2.y * dp1 - duv1.y * dp2) / determinant;
  const glm::vec3 dpdv = (duv1.x * dp2 - duv2.x * dp1) / determinant;
  return {glm::length(dpdu), glm::length(dpdv)};
}

// The hit's shading frame (svbrdf's: interpolated normal turned towards the viewer,
// tangent along +u, bitangent by handedness), its position and its uv.
struct MacroSurface {
  glm::vec3 position{};
  glm::vec3 geometric_normal{};  // unit, on the viewer's side
  glm::vec2 uv{};
  SurfaceFrame frame;
  bool back = false;  // seen from behind: the frame was turned
};

MacroSurface MakeMacroSurface(const TriangleMesh& mesh, const MacroHit& hit, glm::vec3 origin, glm::vec3 direction,
                              glm::vec2 repeat) {
  const uint32_t* corner = &mesh.indices[3 * size_t{hit.triangle}];
  const float w1 = hit.barycentric.x, w2 = hit.barycentric.y, w0 = 1.0f - w1 - w2;
  auto interpolate = [&](const auto& attribute) {
    return w0 * attribute[corner[0]] + w1 * attribute[corner[1]] + w2 * attribute[corner[2]];
  };
  MacroSurface surface;
  surface.position = origin + direction * hit.t;
  const glm::vec3 p0 = mesh.positions[corner[0]];
  glm::vec3 face = SafeNormalize(glm::cross(mesh.positions[corner[1]] - p0, mesh.positions[corner[2]] - p0), -direction);
  glm::vec3 n = SafeNormalize(interpolate(mesh.normals), face);
  if (glm::dot(face, n) < 0.0f) face = -face;
  // Seen from behind, the frame turns towards the viewer (cloth.glsl's gl_FrontFacing).
  const float side = glm::dot(face, direction) > 0.0f ? -1.0f : 1.0f;
  surface.geometric_normal = face * side;
  surface.back = side < 0.0f;
  n *= side;
  const glm::vec4 tangent = interpolate(mesh.tangents);
  glm::vec3 t = glm::vec3(tangent) - n * glm::dot(n, glm::vec3(tangent));
  t = SafeNormalize(t, std::abs(n.x) < 0.9f ? SafeNormalize(glm::cross(n, glm::vec3(1, 0, 0)), glm::vec3(0, 1, 0))
                                             : SafeNormalize(glm::cross(n, glm::vec3(0, 1, 0)), glm::vec3(1, 0, 0)));
  surface.frame.n = n;
  surface.frame.t = t;
  surface.frame.b = glm::cross(n, t) * (tangent.w < 0.0f ? -1.0f : 1.0f);
  const glm::vec2 jacobian = UvJacobianScale(mesh, hit.triangle);
  surface.frame.scale_u = std::max(jacobian.x / repeat.x, 1e-12f);
  surface.frame.scale_v = std::max(jacobian.y / repeat.y, 1e-12f);
  surface.uv = interpolate(mesh.uvs);
  return surface;
}

// --- Scene objects -----------------------------------------------------------------

// A cloth object's fabric: its tile, the repeated tile for ray casting, the BRDFs,
// and (for constant frames) the indirect irradiance of every directional light.
// Not movable: IndirectLight keeps references to the tile and the scene.
struct ClothFabric {
  FabricTile tile;
  std::unique_ptr<PeriodicScene> scene;
  std::vector<YarnBrdf> brdfs;
  glm::vec2 repeat{1.0f};
  std::optional<IndirectLight> indirect;
  // Directional light i seen from the front at [i], from behind at [lights + i];
  // light_count 0 without indirect light.
  VertexIrradiance irradiance;
  // Index of each scene light among the directional ones, −1 for point lights.
  std::vector<int> directional_index;
  size_t directional_count = 0;
};

// The frame of `mesh` if it is the same at every vertex and triangle (a plane):
// then each directional light has one tile-space direction over the whole object.
std::optional<SurfaceFrame> ConstantFrame(const TriangleMesh& mesh, glm::vec2 repeat) {
  if (mesh.triangle_count() == 0) return std::nullopt;
  constexpr float kTolerance = 1e-5f;
  auto near = [](glm::vec3 a, glm::vec3 b) { return glm::all(glm::lessThanEqual(glm::abs(a - b), glm::vec3(kTolerance))); };
  for (size_t v = 1; v < mesh.positions.size(); ++v) {
    if (!near(mesh.normals[v], mesh.normals[0]) || !near(glm::vec3(mesh.tangents[v]), glm::vec3(mesh.tangents[0])) ||
        (mesh.tangents[v].w < 0.0f) != (mesh.tangents[0].w < 0.0f)) {
      return std::nullopt;
    }
  }
  const glm::vec2 jacobian = UvJacobianScale(mesh, 0);
  for (uint32_t triangle = 1; triangle < mesh.triangle_count(); ++triangle) {
    const glm::vec2 other = UvJacobianScale(mesh, triangle);
    if (glm::any(glm::greaterThan(glm::abs(other - jacobian), kTolerance * glm::max(jacobian, glm::vec2(1e-12f))))) {
      return std::nullopt;
    }
  }
  // The frame of a front-facing hit: a camera ray along −n.
  const MacroSurface surface =
      MakeMacroSurface(mesh, MacroHit{0, 0, glm::vec2(1.0f / 3.0f), 1.0f}, glm::vec3(0.0f), -glm::normalize(mesh.normals[0]), repeat);
  return surface.frame;
}

SurfaceFrame Flipped(SurfaceFrame frame) {
  frame.n = -frame.n;
  frame.b = -frame.b;
  return frame;
}

std::unique_ptr<ClothFabric> MakeClothFabric(const v1::FabricBinding& binding, const TriangleMesh& mesh,
                                             const std::vector<SceneLight>& lights, unsigned threads) {
  auto cloth = std::make_unique<ClothFabric>();
  cloth->tile = BuildFabricTile(binding.fabric());
  cloth->scene = std::make_unique<PeriodicScene>(cloth->tile.mesh, kTileReach);
  cloth->brdfs = std::vector<YarnBrdf>(cloth->tile.materials.begin(), cloth->tile.materials.end());
  cloth->repeat = {binding.repeat_u(), binding.repeat_v()};
  for (const SceneLight& light : lights) {
    cloth->directional_index.push_back(light.directional ? static_cast<int>(cloth->directional_count++) : -1);
  }

  // Acquisition's bounces and seed for this fabric.
  const v1::PrecomputeSettings settings =
      WithDefaults(binding.has_precompute() ? binding.precompute() : v1::PrecomputeSettings());
  const std::optional<SurfaceFrame> frame = ConstantFrame(mesh, cloth->repeat);
  // Volumetric yarn has no inter-reflection (core/acquire/volume_radiance.h).
  if (settings.indirect_bounces() == 0 || !frame || cloth->directional_count == 0 || cloth->tile.volume) return cloth;
  std::vector<glm::vec3> directions(2 * cloth->directional_count);
  for (size_t i = 0; i < lights.size(); ++i) {
    if (cloth->directional_index[i] < 0) continue;
    const size_t slot = static_cast<size_t>(cloth->directional_index[i]);
    directions[slot] = SafeNormalize(frame->ToTile(lights[i].vector), glm::vec3(0, 0, 1));
    directions[cloth->directional_count + slot] = SafeNormalize(Flipped(*frame).ToTile(lights[i].vector), glm::vec3(0, 0, 1));
  }
  cloth->indirect.emplace(cloth->tile, *cloth->scene, settings.indirect_bounces(), settings.seed(), threads,
                          [](double) {});
  cloth->irradiance = cloth->indirect->Irradiance(directions, threads, [](double) {});
  return cloth;
}

// A world ray that met a cloth surface, in tile space: it enters the shell just
// above the tile geometry, `back_up` tile units before it reaches the surface.
struct ShellRay {
  glm::vec3 entry{};
  glm::vec3 direction{};  // unit
  float back_up = 0.0f;
};

// Nothing for a ray that grazes the surface (an interpolated normal leaning away):
// it misses the shell.
std::optional<ShellRay> EnterShell(const ClothFabric& cloth, const MacroSurface& surface, glm::vec3 direction) {
  const glm::vec3 d = SafeNormalize(surface.frame.ToTile(direction), glm::vec3(0.0f));
  if (!(d.z < -1e-6f)) return std::nullopt;
  const float back_up = (cloth.tile.z_max + kShellTopOffset) / -d.z;
  return ShellRay{glm::vec3(surface.uv * cloth.repeat, 0.0f) - d * back_up, d, back_up};
}

// --- Radiance along camera rays ------------------------------------------------------

class Tracer {
 public:
  Tracer(const v1::SceneSpec& scene, const std::vector<SceneMesh>& meshes, const MacroScene& macro,
         const std::vector<std::unique_ptr<ClothFabric>>& cloth, const std::vector<SceneLight>& lights, float epsilon)
      : scene_(scene), meshes_(meshes), macro_(macro), cloth_(cloth), lights_(lights), epsilon_(epsilon) {}

  // Radiance arriving at `origin` along −direction (unit); tfar from the camera's clip range.
  // `jitter` ∈ [0, 1) offsets the steps of marches through volumetric yarn; `walk` draws
  // its fibre walks.
  glm::vec3 Radiance(glm::vec3 origin, glm::vec3 direction, float tfar, float jitter, RandomStream& walk,
                     uint64_t& rays, std::vector<glm::vec3>& scratch) const {
    float tnear = 0.0f;
    glm::vec3 radiance(0.0f);
    float throughput = 1.0f;
    for (int crossing = 0; crossing < kMaxSurfaceCrossings; ++crossing) {
      ++rays;
      const std::optional<MacroHit> hit = macro_.Intersect(origin, direction, tnear, tfar);
      if (!hit) break;
      const SceneMesh& mesh = meshes_[hit->mesh];
      const ClothFabric* cloth = cloth_[hit->mesh].get();
      const MacroSurface surface =
          MakeMacroSurface(mesh.mesh, *hit, origin, direction, cloth ? cloth->repeat : glm::vec2(1.0f));
      if (!cloth) return radiance + throughput * PlainRadiance(*mesh.object, surface, jitter, rays);
      const ClothLight yarn = ClothRadiance(*cloth, surface, direction, jitter, walk, rays, scratch);
      radiance += throughput * yarn.radiance;
      throughput *= yarn.transmittance;
      if (throughput < kMinThroughput) return radiance;
      // Through a hole or the yarn volume: on to what lies behind the surface.
      tnear = hit->t + epsilon_;
    }
    return radiance + throughput * ToGlm(scene_.background());
  }

 private:
  // What reaches `origin` of a light at the macro scale (1 unblocked, 0 in shadow):
  // along the light's direction, or up to a point light. Plain objects block it; cloth
  // blocks it where the light's ray through its shell meets tube yarn, so holes cast
  // light, not shadow; volumetric yarn passes its transmittance.
  float MacroTransmittance(const SceneLight& light, glm::vec3 origin, float jitter, uint64_t& rays) const {
    if (!light.casts_shadows) return 1.0f;
    glm::vec3 direction = light.vector;
    float tfar = kInfinity;
    if (!light.directional) {
      tfar = glm::length(light.vector - origin);
      if (tfar <= epsilon_) return 1.0f;
      direction = (light.vector - origin) / tfar;
      tfar -= epsilon_;
    }
    float tnear = epsilon_;
    float transmittance = 1.0f;
    for (int crossing = 0; crossing < kMaxSurfaceCrossings; ++crossing) {
      ++rays;
      const std::optional<MacroHit> hit = macro_.Intersect(origin, direction, tnear, tfar);
      if (!hit) return transmittance;
      const ClothFabric* cloth = cloth_[hit->mesh].get();
      if (!cloth) return 0.0f;
      const MacroSurface surface = MakeMacroSurface(meshes_[hit->mesh].mesh, *hit, origin, direction, cloth->repeat);
      if (const std::optional<ShellRay> ray = EnterShell(*cloth, surface, direction)) {
        ++rays;
        if (cloth->tile.volume) {
          transmittance *= VolumeTransmittance(*cloth->tile.volume, ray->entry, ray->direction, jitter);
          if (transmittance <= 0.0f) return 0.0f;
        } else if (cloth->scene->Occluded(ray->entry, ray->direction)) {
          return 0.0f;
        }
      }
      tnear = hit->t + epsilon_;
    }
    return transmittance;
  }

  // Lambertian in the base colour, as opaque.frag.
  glm::vec3 PlainRadiance(const v1::SceneObject& object, const MacroSurface& surface, float jitter, uint64_t& rays) const {
    const glm::vec3 albedo = ToGlm(object.base_colour());
    glm::vec3 radiance = ToGlm(scene_.ambient()) * albedo;
    const glm::vec3 shadow_origin = surface.position + surface.geometric_normal * epsilon_;
    for (const SceneLight& light : lights_) {
      glm::vec3 irradiance;
      const glm::vec3 l = light.Direction(surface.position, irradiance);
      const float cosine = glm::dot(surface.frame.n, l);
      if (cosine <= 0.0f) continue;
      radiance += albedo / kPi * irradiance * cosine * MacroTransmittance(light, shadow_origin, jitter, rays);
    }
    return radiance;
  }

  // What the camera ray meets in the shell at `surface`: the light it brings and the
  // share of what lies behind that passes (1 through a hole, 0 on tube yarn).
  struct ClothLight {
    glm::vec3 radiance{0.0f};
    float transmittance = 1.0f;
  };
  ClothLight ClothRadiance(const ClothFabric& cloth, const MacroSurface& surface, glm::vec3 direction, float jitter,
                           RandomStream& walk, uint64_t& rays, std::vector<glm::vec3>& irradiance) const {
    const SurfaceFrame& frame = surface.frame;
    const std::optional<ShellRay> ray = EnterShell(cloth, surface, direction);
    if (!ray) return {};
    if (cloth.tile.volume) return VolumeRadiance(cloth, surface, *ray, jitter, walk, rays);
    const glm::vec3 d = ray->direction;
    ++rays;
    const std::optional<RayHit> hit = cloth.scene->Intersect(ray->entry, d);
    if (!hit) return {};
    const SurfacePoint point = MakeSurfacePoint(cloth.tile, *hit, d);
    if (!point.front) return {glm::vec3(0.0f), 0.0f};  // the inside of a yarn: opaque and black

    // The hit's true tile position (RayHit's is wrapped into the central tile) and world position.
    const float t_tile = (hit->position.z - ray->entry.z) / d.z;
    const glm::vec3 world = surface.position + frame.ToWorld(d * (t_tile - ray->back_up));
    const YarnBrdf& brdf = cloth.brdfs[point.material];
    const glm::vec3 v = -d;
    const bool indirect = cloth.irradiance.light_count > 0;
    if (indirect) {
      irradiance.resize(cloth.irradiance.light_count);
      cloth.irradiance.Interpolate(cloth.tile.mesh, *hit, irradiance.data());
    }
    const size_t half = surface.back ? cloth.directional_count : 0;  // the cache's half for this side

    glm::vec3 radiance = ToGlm(scene_.ambient()) * cloth.tile.materials[point.material].diffuse_albedo;
    for (size_t i = 0; i < lights_.size(); ++i) {
      const SceneLight& light = lights_[i];
      glm::vec3 light_irradiance;
      const glm::vec3 world_l = light.Direction(world, light_irradiance);
      const glm::vec3 l = SafeNormalize(frame.ToTile(world_l), glm::vec3(0.0f));
      glm::vec3 unit = glm::vec3(0.0f);  // radiance under unit irradiance, as acquisition's samples
      if (indirect && cloth.directional_index[i] >= 0) {
        unit += brdf.diffuse() * irradiance[half + static_cast<size_t>(cloth.directional_index[i])];
      }
      glm::vec3 direct = DirectYarnRadiance(*cloth.scene, cloth.tile, point, brdf, l, v, rays);
      if (direct != glm::vec3(0.0f)) direct *= ShellExitTransmittance(cloth, light, frame, world, hit->position.z, l, jitter, rays);
      radiance += (unit + direct) * light_irradiance;
    }
    return {radiance, 0.0f};
  }

  // What of a light reaches a point at tile height z (world position `world`) from
  // outside the shell: leave the shell along the light (tile direction l), through its
  // top face or, for light from behind the surface, its bottom face, then test the
  // world.
  float ShellExitTransmittance(const ClothFabric& cloth, const SceneLight& light, const SurfaceFrame& frame,
                               glm::vec3 world, float z, glm::vec3 l, float jitter, uint64_t& rays) const {
    if (!light.casts_shadows) return 1.0f;
    if (l.z == 0.0f) return 0.0f;
    const float face = l.z > 0.0f ? cloth.tile.z_max + kShellTopOffset : cloth.tile.z_min - kShellTopOffset;
    const glm::vec3 exit = world + frame.ToWorld(l * ((face - z) / l.z));
    return MacroTransmittance(light, exit, jitter, rays);
  }

  // The camera ray through volumetric yarn (core/acquire/volume_radiance.h): each step's
  // fibres lit by every light through the volume and the world, and by the ambient; the
  // light scattered between fibres walked from one step drawn by its weight.
  ClothLight VolumeRadiance(const ClothFabric& cloth, const MacroSurface& surface, const ShellRay& ray, float jitter,
                            RandomStream& walk, uint64_t& rays) const {
    const YarnVolume& volume = *cloth.tile.volume;
    const SurfaceFrame& frame = surface.frame;
    const glm::vec3 v = -ray.direction;
    const glm::vec3 ambient = ToGlm(scene_.ambient());
    // Σ_lights E f T_l at tile point p, f(l) the fibres' scattering towards the light.
    auto lit = [&](glm::vec3 p, auto&& scattering) {
      const glm::vec3 world = surface.position + frame.ToWorld(p - ray.entry - ray.direction * ray.back_up);
      glm::vec3 sum(0.0f);
      for (const SceneLight& light : lights_) {
        glm::vec3 light_irradiance;
        const glm::vec3 world_l = light.Direction(world, light_irradiance);
        const glm::vec3 l = SafeNormalize(frame.ToTile(world_l), glm::vec3(0.0f));
        const glm::vec3 f = scattering(l);
        if (f == glm::vec3(0.0f)) continue;
        ++rays;
        float transmittance = VolumeTransmittance(volume, p, l, jitter);
        if (transmittance > 0.0f) {
          transmittance *= ShellExitTransmittance(cloth, light, frame, world, p.z, l, jitter, rays);
        }
        sum += f * transmittance * light_irradiance;
      }
      return sum;
    };
    ClothLight result;
    WeightedStep walked;
    result.transmittance = MarchVolume(volume, ray.entry, ray.direction, jitter, [&](const VolumeStep& step) {
      const YarnMaterial& material = cloth.tile.materials[step.sample.material];
      const glm::vec3 direct =
          lit(step.position, [&](glm::vec3 l) { return FibreScattering(material, step.sample.fibre, l, v); });
      result.radiance += step.weight * (ambient * material.diffuse_albedo + direct);
      walked.Offer(step, walk);
    });
    if (const std::optional<VolumeStep>& step = walked.chosen()) {
      const std::vector<YarnMaterial>& materials = cloth.tile.materials;
      WalkFibres(TileVolumeMedium{volume}, materials, step->position, step->sample, walk,
                 [&](glm::vec3 q, const VolumeSample& at, glm::vec3 throughput) {
                   const glm::vec3 albedo = FibreAlbedo(materials[at.material].diffuse_albedo);
                   const glm::vec3 source =
                       lit(q, [&](glm::vec3 l) { return FibreDiffuseScattering(albedo, at.fibre, l); });
                   result.radiance += walked.total() * throughput * source;
                 });
    }
    return result;
  }

  const v1::SceneSpec& scene_;
  const std::vector<SceneMesh>& meshes_;
  const MacroScene& macro_;
  const std::vector<std::unique_ptr<ClothFabric>>& cloth_;
  const std::vector<SceneLight>& lights_;
  float epsilon_;
};

}  // namespace

ReferenceRenderer::ReferenceRenderer(unsigned threads) : threads_(ResolveThreadCount(threads)) {}

ReferenceFrame ReferenceRenderer::Render(const v1::SceneSpec& scene, const std::vector<SceneMesh>& meshes,
                                         const ReferenceProgress& progress) const {
  const Stopwatch stopwatch;
  const v1::RenderSettings& settings = scene.render();
  const int width = static_cast<int>(settings.width()), height = static_cast<int>(settings.height());

  std::vector<SceneLight> lights;
  for (const v1::Light& light : scene.lights()) lights.push_back(MakeSceneLight(light));

  // Offsets of continued and shadow rays: relative to the scene's size, far above
  // float rounding of world coordinates and far below any shell thickness.
  const Bounds bounds = SceneGeometryBounds(meshes);
  const float extent = bounds.empty() ? 1.0f : std::max(bounds.diagonal(), 1e-3f);
  const float epsilon = 1e-5f * extent;

  const MacroScene macro(meshes);
  std::vector<std::unique_ptr<ClothFabric>> cloth(meshes.size());
  for (size_t i = 0; i < meshes.size(); ++i) {
    if (meshes[i].object->has_fabric()) cloth[i] = MakeClothFabric(meshes[i].object->fabric(), meshes[i].mesh, lights, threads_);
  }
  const Tracer tracer(scene, meshes, macro, cloth, lights, epsilon);

  const glm::mat4 inverse = [&] {
    const CameraMatrices camera = MakeCameraMatrices(scene.camera(), static_cast<float>(width) / static_cast<float>(height));
    return glm::inverse(camera.projection * camera.view);
  }();
  auto unproject = [&](glm::vec2 ndc, float z) {
    const glm::vec4 p = inverse * glm::vec4(ndc, z, 1.0f);
    return glm::vec3(p) / p.w;
  };

  const uint32_t samples = settings.reference_samples();
  const uint32_t side = static_cast<uint32_t>(std::sqrt(static_cast<double>(samples)));
  ReferenceFrame frame;
  frame.image = Image(width, height, 4);
  PerWorkerCount rays(threads_);
  std::vector<std::vector<glm::vec3>> scratch(threads_);
  ParallelFor(static_cast<size_t>(height), threads_, [&](size_t row, unsigned worker) {
    const int y = static_cast<int>(row);
    for (int x = 0; x < width; ++x) {
      // The jitter stream kind, indexed by pixel: each pixel's samples are its own.
      RandomStream random(settings.seed(), RandomStream::kTexelJitter, static_cast<uint64_t>(y) * width + x);
      RandomStream jitter(settings.seed(), RandomStream::kVolumeJitter, static_cast<uint64_t>(y) * width + x);
      RandomStream walk(settings.seed(), RandomStream::kFibreWalk, static_cast<uint64_t>(y) * width + x);
      glm::vec3 sum(0.0f);
      for (uint32_t i = 0; i < samples; ++i) {
        // s² jittered strata, then uniform samples for the rest.
        glm::vec2 offset(random.Uniform(), random.Uniform());
        if (i < side * side) offset = (glm::vec2(static_cast<float>(i % side), static_cast<float>(i / side)) + offset) / static_cast<float>(side);
        const glm::vec2 ndc(2.0f * (static_cast<float>(x) + offset.x) / static_cast<float>(width) - 1.0f,
                            1.0f - 2.0f * (static_cast<float>(y) + offset.y) / static_cast<float>(height));
        const glm::vec3 near = unproject(ndc, -1.0f), far = unproject(ndc, 1.0f);
        const glm::vec3 direction = glm::normalize(far - near);
        sum += tracer.Radiance(near, direction, glm::length(far - near), jitter.Uniform(), walk, rays[worker],
                               scratch[worker]);
      }
      const glm::vec3 mean = sum / static_cast<float>(samples);
      for (int c = 0; c < 3; ++c) frame.image.at(x, y, c) = mean[c];
      frame.image.at(x, y, 3) = 1.0f;
    }
  }, [&](size_t rows_done) {
    if (progress) progress(static_cast<double>(rows_done) / static_cast<double>(height), "rendering");
  });
  frame.rays = rays.Total();
  frame.cpu_ms = stopwatch.Milliseconds();
  return frame;
}

}  // namespace loom
