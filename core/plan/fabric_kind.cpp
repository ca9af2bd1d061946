#include "core/plan/fabric_kind.h"

#include <algorithm>

#include "core/spec/defaults.h"

namespace loom {

FabricKind ClassifyFabric(const v1::FabricSpec& fabric) {
  const v1::FabricSpec full = WithDefaults(fabric);
  const bool glossy = std::any_of(full.yarns().begin(), full.yarns().end(), [](const v1::YarnSpec& yarn) {
    const v1::Rgb& s = yarn.specular_albedo();
    return std::max({s.r(), s.g(), s.b()}) >= kGlossySpecularAlbedo;
  });
  if (full.has_knit()) return glossy ? FabricKind::kKnitGlossy : FabricKind::kKnitMatte;
  return glossy ? FabricKind::kWovenGlossy : FabricKind::kWovenMatte;
}

const char* FabricKindName(FabricKind kind) {
  switch (kind) {
    case FabricKind::kKnitMatte: return "knit-matte";
    case FabricKind::kKnitGlossy: return "knit-glossy";
    case FabricKind::kWovenMatte: return "woven-matte";
    case FabricKind::kWovenGlossy: return "woven-glossy";
  }
  return "?";
}

std::optional<FabricKind> ParseFabricKind(std::string_view name) {
  for (const FabricKind kind :
       {FabricKind::kKnitMatte, FabricKind::kKnitGlossy, FabricKind::kWovenMatte, FabricKind::kWovenGlossy}) {
    if (name == FabricKindName(kind)) return kind;
  }
  return std::nullopt;
}

}  // namespace loom
