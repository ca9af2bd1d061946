#pragma once
// A TriangleMesh uploaded to the GPU: one VAO with attribute locations
// 0 = position, 1 = normal, 2 = uv, 3 = tangent (absent attributes read as zero).

#include <GL/glcorearb.h>

#include "core/scene/triangle_mesh.h"

namespace loom::gl {

class MeshBuffer {
 public:
  explicit MeshBuffer(const TriangleMesh& mesh);
  ~MeshBuffer();
  MeshBuffer(const MeshBuffer&) = delete;
  MeshBuffer& operator=(const MeshBuffer&) = delete;

  void Draw() const;

 private:
  GLuint vao_ = 0;
  GLuint buffers_[5] = {};  // four attributes + indices
  GLsizei index_count_ = 0;
};

}  // namespace loom::gl
