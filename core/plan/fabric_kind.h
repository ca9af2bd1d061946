#pragma once
// What kind of fabric a measurement of the sweep applies to, for the planner
// (core/plan/precompute_plan.h): knitted or woven, glossy or matte. The sweep found
// that cheaper settings cost different fabrics very differently: one lobe cannot
// hold a shiny satin's sheen but loses nothing on matte yarns, and the knits'
// loops lose more than flat weaves when the resolution drops far away. So the
// measurements are kept per kind and a fabric is planned from its own kind's.

#include <optional>
#include <string_view>

#include "loom/v1/fabric.pb.h"

namespace loom {

enum class FabricKind { kKnitMatte, kKnitGlossy, kWovenMatte, kWovenGlossy };

// A fabric is glossy when any yarn's specular albedo reaches this in some channel:
// 2.5× the default 0.04 (wool, cotton). Below it the fibre lobe carries at most a
// tenth of the reflected light, and the fit's second lobe has little to hold.
inline constexpr float kGlossySpecularAlbedo = 0.1f;

FabricKind ClassifyFabric(const v1::FabricSpec& fabric);
const char* FabricKindName(FabricKind kind);  // "knit-matte", "knit-glossy", "woven-matte", "woven-glossy"
std::optional<FabricKind> ParseFabricKind(std::string_view name);

}  // namespace loom
