#pragma once
// The two steps every Embree scene of Loom's takes: copying a TriangleMesh into a
// triangle geometry, and turning Embree's device error into a loom::Error.
// (An internal header of the ray casters: Embree types stay out of public ones.)

#include <embree3/rtcore.h>

#include "core/scene/triangle_mesh.h"

namespace loom {

// Throws Error(kInternal) naming `what` if Embree reports an error on `device`.
void CheckEmbree(RTCDevice device, const char* what);

// Attaches `mesh`'s triangles (positions copied) to `scene` as geometry `id`.
void AttachTriangleMesh(RTCDevice device, RTCScene scene, const TriangleMesh& mesh, unsigned id);

}  // namespace loom
