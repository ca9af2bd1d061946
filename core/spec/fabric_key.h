#pragma once
// The fabric cache key (DESIGN.md "Schema"): a content hash of the canonical
// FabricSpec + PrecomputeSettings + the method's asset-format version, so identical
// requests share one computation.
//
// Canonical form: defaults applied (core/spec/defaults.h), cosmetic names cleared,
// the settings the method ignores cleared (FabricMethod::KeySettings),
// printed as protobuf JSON with every field present, then re-serialised with keys
// sorted and no whitespace. It does not depend on the field order of the input file
// or on which of two equal spellings (omitted vs explicit default) was used.

#include <cstdint>
#include <string>

#include "loom/v1/fabric.pb.h"
#include "loom/v1/precompute.pb.h"

namespace loom {

// svbrdf's asset format (FabricMethod::asset_format_version). Bumped whenever the asset layout or the meaning of a fitted parameter changes
// (2: 32-bit lobe coefficients and frame in half-float assets; the shortened LUT step;
// 3: lobes peaking above ten times the energy-conserving peak are refitted with fewer;
// 4: acquisition's rays on one grid over the tile whatever the resolution, and a mip
// texel pooling its children's samples and hit normals weighted by coverage;
// 5: mip levels fitted coarsest first, a texel starting from its parent's fit, not
// its children's; 6: a sampling plane per view, view_heights in the manifest; 7:
// acquisition shades a facet facing the view even where the shading normal does not):
// it invalidates every cached fabric.
inline constexpr uint32_t kAssetFormatVersion = 7;

std::string CanonicalFabricJson(const v1::FabricSpec& fabric, const v1::PrecomputeSettings& settings);

// Lowercase hex SHA-256 of CanonicalFabricJson.
std::string FabricKey(const v1::FabricSpec& fabric, const v1::PrecomputeSettings& settings);

}  // namespace loom
