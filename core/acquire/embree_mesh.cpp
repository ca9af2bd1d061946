#include "core/acquire/embree_mesh.h"

#include <cstring>
#include <string>

#include "core/util/error.h"

namespace loom {

void CheckEmbree(RTCDevice device, const char* what) {
  const RTCError error = rtcGetDeviceError(device);
  if (error != RTC_ERROR_NONE) {
    throw Error(ErrorCode::kInternal, std::string("Embree: ") + what + " failed (error " + std::to_string(error) + ")");
  }
}

void AttachTriangleMesh(RTCDevice device, RTCScene scene, const TriangleMesh& mesh, unsigned id) {
  RTCGeometry geometry = rtcNewGeometry(device, RTC_GEOMETRY_TYPE_TRIANGLE);
  auto* vertices = static_cast<float*>(rtcSetNewGeometryBuffer(geometry, RTC_BUFFER_TYPE_VERTEX, 0, RTC_FORMAT_FLOAT3,
                                                               3 * sizeof(float), mesh.positions.size()));
  auto* indices = static_cast<uint32_t*>(rtcSetNewGeometryBuffer(
      geometry, RTC_BUFFER_TYPE_INDEX, 0, RTC_FORMAT_UINT3, 3 * sizeof(uint32_t), mesh.triangle_count()));
  CheckEmbree(device, "allocating the mesh buffers");
  std::memcpy(vertices, mesh.positions.data(), mesh.positions.size() * 3 * sizeof(float));
  std::memcpy(indices, mesh.indices.data(), mesh.triangle_count() * 3 * sizeof(uint32_t));
  rtcCommitGeometry(geometry);
  rtcAttachGeometryByID(scene, geometry, id);
  rtcReleaseGeometry(geometry);
}

}  // namespace loom
