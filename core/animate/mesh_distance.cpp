#include "core/animate/mesh_distance.h"

#include <embree3/rtcore.h>

#include <algorithm>
#include <cmath>
#include <limits>
#include <map>
#include <unordered_map>
#include <utility>

#include "core/acquire/embree_mesh.h"
#include "core/animate/closest_point.h"
#include "core/spec/limits.h"
#include "core/util/error.h"

namespace loom::animate {

struct MeshDistance::Bvh {
  RTCDevice device = nullptr;
  RTCScene scene = nullptr;

  ~Bvh() {
    if (scene) rtcReleaseScene(scene);
    if (device) rtcReleaseDevice(device);
  }
};

namespace {

// The nearest point found so far by one query.
struct Query {
  const TriangleMesh* mesh;
  glm::vec3 p;
  uint32_t triangle = 0;
  TrianglePoint nearest{};
  float distance = std::numeric_limits<float>::infinity();
};

bool VisitTriangle(RTCPointQueryFunctionArguments* args) {
  Query& q = *static_cast<Query*>(args->userPtr);
  const std::vector<uint32_t>& indices = q.mesh->indices;
  const std::vector<glm::vec3>& x = q.mesh->positions;
  const uint32_t t = args->primID;
  const TrianglePoint nearest =
      ClosestPointOnTriangle(q.p, x[indices[3 * t]], x[indices[3 * t + 1]], x[indices[3 * t + 2]]);
  const float distance = glm::distance(q.p, nearest.point);
  if (distance >= q.distance) return false;
  q.distance = distance, q.nearest = nearest, q.triangle = t;
  args->query->radius = distance;  // only nearer triangles from now on
  return true;
}

}  // namespace

MeshDistance::MeshDistance(const TriangleMesh& mesh, const std::string& name) : bvh_(std::make_unique<Bvh>()) {
  const auto fail = [&](const std::string& what) {
    throw Error(ErrorCode::kInvalidArgument, "mesh collider " + name + ": " + what);
  };
  if (mesh.triangle_count() > static_cast<size_t>(kMaxMeshTriangles)) fail("too many triangles");
  // Corners within a millionth of the mesh's size of each other are one vertex
  // (a mesh's uv seams split them, and a seam's two sides may differ in the last
  // bits); triangles without area are left out. A grid of cells that size finds
  // them: a point's match lies in its cell or a neighbouring one.
  Bounds bounds;
  bounds.Add(mesh.positions);
  const float weld = 1e-6f * std::max(bounds.diagonal(), 1e-30f);
  std::unordered_map<uint64_t, std::vector<uint32_t>> cells;
  const auto cell_key = [&](glm::ivec3 cell) {
    return (uint64_t(uint32_t(cell.x) & 0x1fffff) << 42) | (uint64_t(uint32_t(cell.y) & 0x1fffff) << 21) |
           uint64_t(uint32_t(cell.z) & 0x1fffff);
  };
  std::vector<uint32_t> vertex(mesh.positions.size());
  for (size_t v = 0; v < mesh.positions.size(); ++v) {
    const glm::vec3 p = mesh.positions[v];
    const glm::ivec3 cell = glm::ivec3(glm::floor((p - bounds.low) / weld));
    uint32_t found = UINT32_MAX;
    for (int dz = -1; dz <= 1 && found == UINT32_MAX; ++dz) {
      for (int dy = -1; dy <= 1 && found == UINT32_MAX; ++dy) {
        for (int dx = -1; dx <= 1 && found == UINT32_MAX; ++dx) {
          const auto near = cells.find(cell_key(cell + glm::ivec3(dx, dy, dz)));
          if (near == cells.end()) continue;
          for (const uint32_t candidate : near->second) {
            if (glm::distance(mesh_.positions[candidate], p) <= weld) found = candidate;
          }
        }
      }
    }
    if (found == UINT32_MAX) {
      found = static_cast<uint32_t>(mesh_.positions.size());
      mesh_.positions.push_back(p);
      cells[cell_key(cell)].push_back(found);
    }
    vertex[v] = found;
  }
  for (size_t t = 0; t < mesh.triangle_count(); ++t) {
    const glm::uvec3 corner(vertex[mesh.indices[3 * t]], vertex[mesh.indices[3 * t + 1]],
                            vertex[mesh.indices[3 * t + 2]]);
    const glm::vec3 a = mesh_.positions[corner.x], b = mesh_.positions[corner.y], c = mesh_.positions[corner.z];
    const glm::vec3 normal = glm::cross(b - a, c - a);
    if (!(glm::length(normal) > 0.0f)) continue;
    mesh_.indices.insert(mesh_.indices.end(), {corner.x, corner.y, corner.z});
    face_normals_.push_back(glm::normalize(normal));
  }
  const size_t triangles = mesh_.triangle_count();
  if (triangles == 0) fail("no triangles with an area");
  // Faces wound inwards (a negative enclosed volume) are turned round.
  double volume = 0.0;
  for (size_t t = 0; t < triangles; ++t) {
    const uint32_t* corner = &mesh_.indices[3 * t];
    volume += glm::dot(mesh_.positions[corner[0]] - bounds.low,
                       glm::cross(mesh_.positions[corner[1]] - bounds.low, mesh_.positions[corner[2]] - bounds.low));
  }
  if (volume < 0.0) {
    for (size_t t = 0; t < triangles; ++t) {
      std::swap(mesh_.indices[3 * t + 1], mesh_.indices[3 * t + 2]);
      face_normals_[t] = -face_normals_[t];
    }
  }
  corner_normals_.assign(mesh_.positions.size(), glm::vec3(0.0f));
  edge_normals_.resize(3 * triangles);
  std::map<std::pair<uint32_t, uint32_t>, std::vector<uint32_t>> edges;  // (low, high) corner → its edge slots
  for (size_t t = 0; t < triangles; ++t) {
    const uint32_t* corner = &mesh_.indices[3 * t];
    for (int k = 0; k < 3; ++k) {
      const glm::vec3 here = mesh_.positions[corner[k]];
      const glm::vec3 next = mesh_.positions[corner[(k + 1) % 3]], previous = mesh_.positions[corner[(k + 2) % 3]];
      const float angle = std::acos(glm::clamp(glm::dot(glm::normalize(next - here), glm::normalize(previous - here)),
                                               -1.0f, 1.0f));
      corner_normals_[corner[k]] += angle * face_normals_[t];
      edges[std::minmax(corner[k], corner[(k + 1) % 3])].push_back(static_cast<uint32_t>(3 * t + k));
    }
  }
  for (const auto& [edge, slots] : edges) {
    if (slots.size() != 2) {
      fail("not closed: the edge between vertices " + std::to_string(edge.first) + " and " +
           std::to_string(edge.second) + " has " + std::to_string(slots.size()) + " triangle(s), not 2");
    }
    // Consistently wound neighbours run along their shared edge in opposite directions.
    if (mesh_.indices[slots[0]] == mesh_.indices[slots[1]]) {
      fail("its faces are not wound alike: the triangles on the edge between vertices " + std::to_string(edge.first) +
           " and " + std::to_string(edge.second) + " face opposite ways");
    }
    const glm::vec3 normal = face_normals_[slots[0] / 3] + face_normals_[slots[1] / 3];
    edge_normals_[slots[0]] = edge_normals_[slots[1]] = normal;
  }
  Bvh& bvh = *bvh_;
  bvh.device = rtcNewDevice(nullptr);
  if (!bvh.device) throw Error(ErrorCode::kInternal, "Embree: creating a device failed");
  bvh.scene = rtcNewScene(bvh.device);
  AttachTriangleMesh(bvh.device, bvh.scene, mesh_, 0);
  rtcCommitScene(bvh.scene);
  CheckEmbree(bvh.device, "building a mesh collider's BVH");
}

MeshDistance::~MeshDistance() = default;

Contact MeshDistance::Nearest(glm::vec3 p) const {
  Query query{&mesh_, p};
  RTC_ALIGN(16) RTCPointQuery sphere;
  sphere.x = p.x, sphere.y = p.y, sphere.z = p.z;
  sphere.radius = std::numeric_limits<float>::infinity();
  sphere.time = 0.0f;
  RTCPointQueryContext context;
  rtcInitPointQueryContext(&context);
  rtcPointQuery(bvh_->scene, &sphere, &context, VisitTriangle, &query);
  // The nearest feature by the weights that are 0: a corner (two), an edge (one)
  // or the face.
  const glm::vec3 w = query.nearest.weights;
  const uint32_t t = query.triangle;
  glm::vec3 pseudo = face_normals_[t];
  const int zeros = (w.x == 0.0f) + (w.y == 0.0f) + (w.z == 0.0f);
  if (zeros == 2) {
    pseudo = corner_normals_[mesh_.indices[3 * t + (w.x > 0.0f ? 0 : w.y > 0.0f ? 1 : 2)]];
  } else if (zeros == 1) {
    // Edge k joins corners k and k + 1: the edge opposite the corner of weight 0.
    pseudo = edge_normals_[3 * t + (w.x == 0.0f ? 1 : w.y == 0.0f ? 2 : 0)];
  }
  const glm::vec3 offset = p - query.nearest.point;
  const float sign = glm::dot(offset, pseudo) < 0.0f ? -1.0f : 1.0f;
  if (!(query.distance > 0.0f)) return {0.0f, face_normals_[t]};
  return {sign * query.distance, sign * offset / query.distance};
}

}  // namespace loom::animate
