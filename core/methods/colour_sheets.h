#pragma once
// Colour components: colours applied when the cloth is drawn, not fitted (the neural
// woven paper's §4.1 eq. 8; docs/colour_components.md). With direct light only, a
// fabric's radiance is linear in each yarn's diffuse albedo k_d and specular albedo k_s,
//
//   L = Σ_y k_d,y ⊙ C_y + k_s,y ⊙ S_y,
//
// C_y (S_y) the radiance of the fabric with yarn y's diffuse (specular) albedo 1 and
// every other albedo 0. With PrecomputeSettings.colour_components a method's asset
// holds these components three to a sheet (a sheet's R, G and B are three
// components), and the renderer maps each sheet's channels to RGB by a 3×3 matrix
// whose columns are the albedos of the yarns the channels belong to.

#include <array>
#include <cstdint>
#include <functional>
#include <glm/glm.hpp>
#include <nlohmann/json.hpp>
#include <optional>
#include <string>
#include <vector>

#include "core/fabric/fabric_tile.h"
#include "core/util/error.h"
#include "loom/v1/fabric.pb.h"

namespace loom {

struct ColourComponent {
  enum class Kind { kDiffuse, kSpecular };
  Kind kind = Kind::kDiffuse;
  uint32_t yarn = 0;
  bool operator==(const ColourComponent&) const = default;
};

// What a sheet's R, G and B carry; an empty channel is always zero.
using SheetChannels = std::array<std::optional<ColourComponent>, 3>;

// The sheets of a fabric with `yarns` yarns: the diffuse components of yarns 0 … n−1,
// then their specular ones, three to a sheet (⌈2n/3⌉ sheets).
std::vector<SheetChannels> ColourSheetChannels(size_t yarns);

// `tile` with every yarn's albedos 0 but those of the sheet's components, which are 1
// in their channel: its acquisition is the sheet's samples. Material m is yarn m
// (BuildFabricTile).
FabricTile ComponentTile(FabricTile tile, const SheetChannels& channels);

// The matrix taking a sheet's channels to RGB for `fabric` (defaults applied): column
// c is the albedo of channel c's component, zero for an empty channel.
// Error(kInvalidArgument) for a component of a yarn the fabric does not have.
glm::mat3 SheetColours(const v1::FabricSpec& fabric, const SheetChannels& channels);

// The sheets as JSON ([["diffuse 0", "diffuse 1", "specular 0"], ["specular 1", "", ""]]),
// and back: anything else is invalid(what) thrown.
nlohmann::json ColourSheetsJson(const std::vector<SheetChannels>& sheets);
std::vector<SheetChannels> ParseColourSheets(const nlohmann::json& json,
                                             const std::function<Error(const std::string&)>& invalid);

}  // namespace loom
