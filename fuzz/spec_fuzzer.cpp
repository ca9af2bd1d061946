// The spec JSON parsers (core/spec/spec_json.h) and what every front end does next
// with a spec that parses: validation, defaults, the fabric cache key. Built three
// times, LOOM_FUZZ_SPEC naming the root message: fabric, precompute, scene.

#include <cstddef>
#include <cstdint>
#include <string_view>

#include "core/render/scene_render.h"
#include "core/spec/defaults.h"
#include "core/spec/fabric_key.h"
#include "core/spec/spec_json.h"
#include "core/spec/validate.h"
#include "core/util/error.h"
#include "fuzz/quiet_logs.h"

namespace loom {
namespace {

void Use(const v1::FabricSpec& fabric) {
  if (!Validate(fabric).empty()) return;
  const v1::FabricSpec full = WithDefaults(fabric);
  FabricKey(full, WithDefaults(v1::PrecomputeSettings()));
  SpecToJson(full);
}

void Use(const v1::PrecomputeSettings& settings) {
  if (!Validate(settings).empty()) return;
  FabricKey(WithDefaults(v1::FabricSpec()), WithDefaults(settings));
}

void Use(const v1::SceneSpec& scene) {
  if (!Validate(scene).empty()) return;
  const v1::SceneSpec full = WithDefaults(scene);
  if (!Validate(full).empty()) return;
  SceneFabrics(full);
}

}  // namespace
}  // namespace loom

extern "C" int LLVMFuzzerTestOneInput(const uint8_t* data, size_t size) {
  loom::fuzz::QuietLogs();
  const std::string_view json(reinterpret_cast<const char*>(data), size);
  try {
    loom::Use(loom::ParseSpecJson<LOOM_FUZZ_SPEC_TYPE>(json, LOOM_FUZZ_SPEC));
  } catch (const loom::Error&) {
    // Refused with a message: what bad input must get.
  }
  return 0;
}
