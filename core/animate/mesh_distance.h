#pragma once
// The signed distance from a point to a closed triangle mesh with outward
// faces, and the outward normal at its nearest point: what a mesh collider is to
// the knit simulation. An Embree BVH answers the nearest-point query; the sign is
// that of the offset along the angle-weighted pseudo-normal of the nearest
// feature (a face, an edge or a corner; Bærentzen and Aanæs 2005), which is
// right for every point of a closed mesh (docs/animation.md "Mesh colliders").

#include <glm/glm.hpp>
#include <memory>
#include <string>
#include <vector>

#include "core/animate/contact.h"
#include "core/scene/triangle_mesh.h"

namespace loom::animate {

class MeshDistance {
 public:
  // Corners at one place (within 10⁻⁶ of the mesh's size) are welded and
  // triangles without area left out, and faces wound inwards turned round; then
  // Error(kInvalidArgument) naming `name` for a mesh with no triangle left, an
  // edge not shared by exactly two triangles (not closed) or two neighbours wound
  // unlike, or past the caps of core/spec/limits.h.
  MeshDistance(const TriangleMesh& mesh, const std::string& name);
  ~MeshDistance();
  MeshDistance(const MeshDistance&) = delete;
  MeshDistance& operator=(const MeshDistance&) = delete;

  Contact Nearest(glm::vec3 p) const;
  const TriangleMesh& mesh() const { return mesh_; }

 private:
  struct Bvh;  // the Embree device and scene
  std::unique_ptr<Bvh> bvh_;
  TriangleMesh mesh_;  // positions and indices
  std::vector<glm::vec3> face_normals_, corner_normals_;
  // Each triangle's edges' pseudo-normals: edge k joins corners k and k + 1.
  std::vector<glm::vec3> edge_normals_;
};

}  // namespace loom::animate
