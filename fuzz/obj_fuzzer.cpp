// The OBJ loader (core/scene/obj_loader.h) fed in pieces, then mesh preparation,
// as BuildSceneGeometry does for an uploaded mesh. Caps far below the server's, so
// that an input cannot make one run slow; the checks are the same code.

#include <cstddef>
#include <cstdint>
#include <string_view>

#include "core/scene/mesh_preparation.h"
#include "core/scene/obj_loader.h"
#include "core/util/error.h"
#include "fuzz/quiet_logs.h"

extern "C" int LLVMFuzzerTestOneInput(const uint8_t* data, size_t size) {
  loom::fuzz::QuietLogs();
  if (size == 0) return 0;
  // The first byte picks the piece size the text arrives in.
  const size_t piece = 1 + data[0] % 64;
  const std::string_view text(reinterpret_cast<const char*>(data) + 1, size - 1);
  loom::MeshLimits limits;
  limits.triangles = 20'000;
  limits.vertices = 20'000;
  try {
    loom::ObjParser parser("fuzz.obj", limits);
    for (size_t offset = 0; offset < text.size(); offset += piece) parser.Feed(text.substr(offset, piece));
    loom::TriangleMesh mesh = parser.Finish();
    loom::PrepareMesh(mesh, "fuzz.obj");
  } catch (const loom::Error&) {
  }
  return 0;
}
