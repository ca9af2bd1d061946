#include "core/animate/self_contact.h"

#include <embree3/rtcore.h>

#include <algorithm>
#include <string>

#include "core/acquire/embree_mesh.h"
#include "core/animate/closest_point.h"
#include "core/util/error.h"
#include "core/util/parallel_for.h"

namespace loom::animate {

struct SelfContactPairs::Bvh {
  RTCDevice device = nullptr;
  RTCScene scene = nullptr;
  RTCGeometry geometry = nullptr;
  // Embree reads vertices 16 bytes at a time: one float of padding at the end.
  std::vector<float> vertices;

  ~Bvh() {
    if (geometry) rtcReleaseGeometry(geometry);
    if (scene) rtcReleaseScene(scene);
    if (device) rtcReleaseDevice(device);
  }
};

namespace {

// One point's query: the pairs it finds go to `found`.
struct Query {
  const KnitCloth* cloth;
  const std::vector<glm::uvec3>* triangles;
  const std::vector<glm::vec3>* x;
  int exclusion;
  float radius;
  uint32_t point;
  std::vector<PointTriangle>* found;
};

bool VisitTriangle(RTCPointQueryFunctionArguments* args) {
  const Query& q = *static_cast<const Query*>(args->userPtr);
  const uint32_t t = args->primID;
  if (q.cloth->Adjacent(q.point, t, q.exclusion)) return false;
  const glm::uvec3 corners = (*q.triangles)[t];
  const std::vector<glm::vec3>& x = *q.x;
  const glm::vec3 p = x[q.point];
  if (glm::distance(p, ClosestPointOnTriangle(p, x[corners.x], x[corners.y], x[corners.z]).point) < q.radius) {
    q.found->push_back({q.point, t});
  }
  return false;  // the query's radius stays
}

}  // namespace

SelfContactPairs::SelfContactPairs(const KnitCloth& cloth, float reach, float skin, int exclusion, unsigned threads)
    : bvh_(std::make_unique<Bvh>()),
      cloth_(cloth),
      triangles_(cloth.Triangles()),
      reach_(reach),
      skin_(skin),
      exclusion_(exclusion),
      threads_(ResolveThreadCount(threads)) {
  if (!(reach > 0.0f) || !(skin > 0.0f) || exclusion < 0) {
    throw Error(ErrorCode::kInvalidArgument, "self-contact: reach and skin must be > 0 and exclusion ≥ 0");
  }
  cloth_.positions.clear();
  Bvh& bvh = *bvh_;
  bvh.device = rtcNewDevice(nullptr);
  if (!bvh.device) throw Error(ErrorCode::kInternal, "Embree: creating a device failed");
  bvh.scene = rtcNewScene(bvh.device);
  rtcSetSceneFlags(bvh.scene, RTC_SCENE_FLAG_DYNAMIC);
  rtcSetSceneBuildQuality(bvh.scene, RTC_BUILD_QUALITY_LOW);
  bvh.geometry = rtcNewGeometry(bvh.device, RTC_GEOMETRY_TYPE_TRIANGLE);
  bvh.vertices.assign(3 * cloth.size() + 1, 0.0f);
  rtcSetSharedGeometryBuffer(bvh.geometry, RTC_BUFFER_TYPE_VERTEX, 0, RTC_FORMAT_FLOAT3, bvh.vertices.data(), 0,
                             3 * sizeof(float), cloth.size());
  rtcSetSharedGeometryBuffer(bvh.geometry, RTC_BUFFER_TYPE_INDEX, 0, RTC_FORMAT_UINT3, triangles_.data(), 0,
                             sizeof(glm::uvec3), triangles_.size());
  rtcSetGeometryBuildQuality(bvh.geometry, RTC_BUILD_QUALITY_LOW);
  rtcCommitGeometry(bvh.geometry);
  rtcAttachGeometryByID(bvh.scene, bvh.geometry, 0);
  CheckEmbree(bvh.device, "building the cloth's triangle geometry");
}

SelfContactPairs::~SelfContactPairs() = default;
SelfContactPairs::SelfContactPairs(SelfContactPairs&&) noexcept = default;
SelfContactPairs& SelfContactPairs::operator=(SelfContactPairs&&) noexcept = default;

void SelfContactPairs::Update(const std::vector<glm::vec3>& x) {
  const size_t points = static_cast<size_t>(cloth_.across) * cloth_.along;
  if (x.size() != points) {
    throw Error(ErrorCode::kInvalidArgument, "self-contact: " + std::to_string(x.size()) +
                                                 " positions for a cloth of " + std::to_string(points) + " points");
  }
  bool moved = searched_at_.size() != x.size();
  const float limit2 = 0.25f * skin_ * skin_;
  for (size_t p = 0; !moved && p < x.size(); ++p) {
    const glm::vec3 d = x[p] - searched_at_[p];
    moved = glm::dot(d, d) > limit2;
  }
  if (moved) Search(x);
}

void SelfContactPairs::Search(const std::vector<glm::vec3>& x) {
  Bvh& bvh = *bvh_;
  std::copy(&x[0].x, &x[0].x + 3 * x.size(), bvh.vertices.begin());
  rtcUpdateGeometryBuffer(bvh.geometry, RTC_BUFFER_TYPE_VERTEX, 0);
  rtcCommitGeometry(bvh.geometry);
  rtcCommitScene(bvh.scene);
  CheckEmbree(bvh.device, "building the cloth's BVH");

  std::vector<std::vector<PointTriangle>> found(threads_);
  const float radius = reach_ + skin_;
  ParallelFor(x.size(), threads_, [&](size_t p, unsigned worker) {
    Query query{&cloth_, &triangles_, &x, exclusion_, radius, static_cast<uint32_t>(p), &found[worker]};
    RTC_ALIGN(16) RTCPointQuery sphere;
    sphere.x = x[p].x, sphere.y = x[p].y, sphere.z = x[p].z;
    sphere.radius = radius;
    sphere.time = 0.0f;
    RTCPointQueryContext context;
    rtcInitPointQueryContext(&context);
    rtcPointQuery(bvh.scene, &sphere, &context, VisitTriangle, &query);
  });
  pairs_.clear();
  for (const auto& list : found) pairs_.insert(pairs_.end(), list.begin(), list.end());
  std::sort(pairs_.begin(), pairs_.end(), [](const PointTriangle& a, const PointTriangle& b) {
    return a.point != b.point ? a.point < b.point : a.triangle < b.triangle;
  });
  searched_at_ = x;
  ++searches_;
}

}  // namespace loom::animate
