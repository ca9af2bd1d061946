#include "core/acquire/periodic_scene.h"

#include <embree3/rtcore.h>

#include <algorithm>
#include <cmath>
#include <limits>

#include "core/acquire/embree_mesh.h"
#include "core/util/error.h"

namespace loom {
namespace {

constexpr float kInfinity = std::numeric_limits<float>::infinity();
// Slack around the geometry's z range, in tile units, so that rays starting just
// above the top face or on a surface are inside the slab.
constexpr float kSlabMargin = 1e-3f;

// The point's copy in the central tile: x and y modulo the period.
glm::vec3 Wrap(glm::vec3 p) { return {p.x - std::floor(p.x), p.y - std::floor(p.y), p.z}; }

}  // namespace

struct PeriodicScene::Impl {
  RTCDevice device = nullptr;
  RTCScene tile = nullptr;   // the mesh once
  RTCScene world = nullptr;  // instances of `tile`
  float reach = 1.0f;
  float slab_low = 0.0f, slab_high = 0.0f;
  glm::ivec2 grid{0, 0};

  ~Impl() {
    if (world) rtcReleaseScene(world);
    if (tile) rtcReleaseScene(tile);
    if (device) rtcReleaseDevice(device);
  }

  // Walks the ray segment by segment (see the header); `cast(origin, tfar)` casts
  // one segment and returns true when it is done (hit or blocked).
  template <typename Cast>
  bool Walk(glm::vec3 origin, glm::vec3 direction, Cast cast) const {
    const float horizontal = std::hypot(direction.x, direction.y);
    const float t_wrap = horizontal > 0.0f ? reach / horizontal : kInfinity;
    glm::vec3 o = Wrap(origin);
    for (int segment = 0; segment <= kMaxContinuations; ++segment) {
      float t_exit = kInfinity;
      if (direction.z > 0.0f) t_exit = (slab_high - o.z) / direction.z;
      if (direction.z < 0.0f) t_exit = (slab_low - o.z) / direction.z;
      if (direction.z == 0.0f && (o.z < slab_low || o.z > slab_high)) t_exit = 0.0f;
      const float tfar = std::min(t_exit, t_wrap);
      if (!(tfar > 0.0f)) return false;
      if (cast(o, tfar)) return true;
      if (t_exit <= t_wrap) return false;
      o = Wrap(o + direction * t_wrap);
    }
    return false;
  }
};

PeriodicScene::PeriodicScene(const TriangleMesh& mesh, float reach) : impl_(std::make_unique<Impl>()) {
  Impl& s = *impl_;
  s.reach = std::clamp(reach, 1.0f, kMaxReach);
  s.device = rtcNewDevice(nullptr);
  if (s.device == nullptr) throw Error(ErrorCode::kInternal, "Embree: cannot create a device");
  s.world = rtcNewScene(s.device);
  // Robust traversal: no ray may slip through the shared edge of two triangles,
  // or a closed yarn surface would show false holes (alpha < 1).
  rtcSetSceneFlags(s.world, RTC_SCENE_FLAG_ROBUST);

  const size_t triangles = mesh.triangle_count();
  if (triangles > 0) {
    Bounds bounds;
    bounds.Add(mesh.positions);
    s.slab_low = bounds.low.z - kSlabMargin;
    s.slab_high = bounds.high.z + kSlabMargin;

    s.tile = rtcNewScene(s.device);
    rtcSetSceneFlags(s.tile, RTC_SCENE_FLAG_ROBUST);
    rtcSetSceneBuildQuality(s.tile, RTC_BUILD_QUALITY_HIGH);
    AttachTriangleMesh(s.device, s.tile, mesh, 0);
    rtcCommitScene(s.tile);
    CheckEmbree(s.device, "building the tile's BVH");

    // Copy (i, j) holds the mesh translated by (i, j); it is needed when its
    // bounds [i + bounds.low.x, i + bounds.high.x] reach into [−reach, 1 + reach], and alike in y.
    const glm::ivec2 first(glm::ceil(-s.reach - glm::vec2(bounds.high)));
    const glm::ivec2 last(glm::floor(1.0f + s.reach - glm::vec2(bounds.low)));
    s.grid = last - first + 1;
    for (int j = first.y; j <= last.y; ++j) {
      for (int i = first.x; i <= last.x; ++i) {
        RTCGeometry instance = rtcNewGeometry(s.device, RTC_GEOMETRY_TYPE_INSTANCE);
        rtcSetGeometryInstancedScene(instance, s.tile);
        const float transform[12] = {1, 0, 0, 0, 1, 0, 0, 0, 1, static_cast<float>(i), static_cast<float>(j), 0};
        rtcSetGeometryTransform(instance, 0, RTC_FORMAT_FLOAT3X4_COLUMN_MAJOR, transform);
        rtcCommitGeometry(instance);
        rtcAttachGeometry(s.world, instance);
        rtcReleaseGeometry(instance);
      }
    }
  }
  rtcCommitScene(s.world);
  CheckEmbree(s.device, "building the repeated scene");
}

PeriodicScene::~PeriodicScene() = default;

glm::ivec2 PeriodicScene::grid_size() const { return impl_->grid; }

std::optional<RayHit> PeriodicScene::Intersect(glm::vec3 origin, glm::vec3 direction) const {
  std::optional<RayHit> result;
  impl_->Walk(origin, direction, [&](glm::vec3 o, float tfar) {
    RTCIntersectContext context;
    rtcInitIntersectContext(&context);
    RTCRayHit ray{};
    ray.ray.org_x = o.x, ray.ray.org_y = o.y, ray.ray.org_z = o.z;
    ray.ray.dir_x = direction.x, ray.ray.dir_y = direction.y, ray.ray.dir_z = direction.z;
    ray.ray.tnear = 0.0f;
    ray.ray.tfar = tfar;
    ray.ray.mask = ~0u;
    ray.hit.geomID = RTC_INVALID_GEOMETRY_ID;
    ray.hit.instID[0] = RTC_INVALID_GEOMETRY_ID;
    rtcIntersect1(impl_->world, &context, &ray);
    if (ray.hit.geomID == RTC_INVALID_GEOMETRY_ID) return false;
    result = RayHit{ray.hit.primID, {ray.hit.u, ray.hit.v}, o + direction * ray.ray.tfar};
    return true;
  });
  return result;
}

bool PeriodicScene::Occluded(glm::vec3 origin, glm::vec3 direction) const {
  return impl_->Walk(origin, direction, [&](glm::vec3 o, float tfar) {
    RTCIntersectContext context;
    rtcInitIntersectContext(&context);
    RTCRay ray{};
    ray.org_x = o.x, ray.org_y = o.y, ray.org_z = o.z;
    ray.dir_x = direction.x, ray.dir_y = direction.y, ray.dir_z = direction.z;
    ray.tnear = 0.0f;
    ray.tfar = tfar;
    ray.mask = ~0u;
    rtcOccluded1(impl_->world, &context, &ray);
    return ray.tfar < 0.0f;  // Embree sets tfar to −∞ on a hit
  });
}

}  // namespace loom
