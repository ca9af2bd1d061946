#include "core/spec/fabric_key.h"

#include <google/protobuf/util/json_util.h>

#include <nlohmann/json.hpp>

#include "core/acquire/volume_radiance.h"
#include "core/fabric/yarn_volume.h"
#include "core/methods/fabric_method.h"
#include "core/spec/defaults.h"
#include "core/util/error.h"
#include "core/util/sha256.h"

namespace loom {
namespace {

nlohmann::json FullJson(const google::protobuf::Message& message) {
  google::protobuf::util::JsonPrintOptions options;
  options.always_print_primitive_fields = true;
  options.always_print_enums_as_ints = false;
  options.preserve_proto_field_names = true;
  std::string json;
  const auto status = google::protobuf::util::MessageToJsonString(message, &json, options);
  if (!status.ok()) throw Error(ErrorCode::kInternal, "cannot print spec: " + std::string(status.message()));
  return nlohmann::json::parse(json);
}

}  // namespace

std::string CanonicalFabricJson(const v1::FabricSpec& fabric, const v1::PrecomputeSettings& settings) {
  v1::FabricSpec canonical_fabric = WithDefaults(fabric);
  canonical_fabric.clear_name();
  const v1::PrecomputeSettings full = WithDefaults(settings);
  // An asset of colour components holds no colour: fabrics that differ only in their
  // yarns' albedos share it (core/methods/colour_sheets.h).
  for (auto& yarn : *canonical_fabric.mutable_yarns()) {
    yarn.clear_name();
    if (full.colour_components()) {
      yarn.clear_diffuse_albedo();
      yarn.clear_specular_albedo();
    }
  }

  // nlohmann::json keeps object keys in a std::map: dump() is sorted.
  nlohmann::json canonical;
  const FabricMethod& method = MethodOf(full.method());
  v1::PrecomputeSettings keyed = method.KeySettings(full);
  // Only when true: other fabrics keep their keys.
  if (!keyed.colour_components()) keyed.clear_colour_components();
  // Resolved, and only when true: fabrics without a back sheet keep their keys.
  if (AcquiresTransmission(canonical_fabric, full)) {
    keyed.set_transmission(true);
  } else {
    keyed.clear_transmission();
  }
  canonical["asset_format_version"] = method.asset_format_version();
  if (HasYarnVolume(canonical_fabric)) canonical["volume_light_model"] = kVolumeLightModelVersion;
  canonical["fabric"] = FullJson(canonical_fabric);
  canonical["precompute"] = FullJson(keyed);
  // A method keyed without its method field (svbrdf, whose keys predate methods).
  if (keyed.method() == v1::FABRIC_METHOD_UNSPECIFIED) canonical["precompute"].erase("method");
  return canonical.dump();
}

std::string FabricKey(const v1::FabricSpec& fabric, const v1::PrecomputeSettings& settings) {
  return Sha256Hex(CanonicalFabricJson(fabric, settings));
}

}  // namespace loom
