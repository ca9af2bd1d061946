#include "core/gl/mesh_buffer.h"

namespace loom::gl {
namespace {

template <typename T>
void UploadAttribute(GLuint vao, GLuint buffer, GLuint location, const std::vector<T>& values) {
  if (values.empty()) return;
  glNamedBufferStorage(buffer, static_cast<GLsizeiptr>(values.size() * sizeof(T)), values.data(), 0);
  glVertexArrayVertexBuffer(vao, location, buffer, 0, sizeof(T));
  glVertexArrayAttribFormat(vao, location, static_cast<GLint>(sizeof(T) / sizeof(float)), GL_FLOAT, GL_FALSE, 0);
  glVertexArrayAttribBinding(vao, location, location);
  glEnableVertexArrayAttrib(vao, location);
}

}  // namespace

MeshBuffer::MeshBuffer(const TriangleMesh& mesh) : index_count_(static_cast<GLsizei>(mesh.indices.size())) {
  glCreateVertexArrays(1, &vao_);
  glCreateBuffers(5, buffers_);
  UploadAttribute(vao_, buffers_[0], 0, mesh.positions);
  UploadAttribute(vao_, buffers_[1], 1, mesh.normals);
  UploadAttribute(vao_, buffers_[2], 2, mesh.uvs);
  UploadAttribute(vao_, buffers_[3], 3, mesh.tangents);
  glNamedBufferStorage(buffers_[4], static_cast<GLsizeiptr>(mesh.indices.size() * sizeof(uint32_t)),
                       mesh.indices.data(), 0);
  glVertexArrayElementBuffer(vao_, buffers_[4]);
}

MeshBuffer::~MeshBuffer() {
  glDeleteBuffers(5, buffers_);
  glDeleteVertexArrays(1, &vao_);
}

void MeshBuffer::Draw() const {
  glBindVertexArray(vao_);
  glDrawElements(GL_TRIANGLES, index_count_, GL_UNSIGNED_INT, nullptr);
  glBindVertexArray(0);
}

}  // namespace loom::gl
