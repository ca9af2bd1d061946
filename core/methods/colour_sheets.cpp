#include "core/methods/colour_sheets.h"

#include "core/spec/limits.h"

namespace loom {
namespace {

std::string ComponentName(const std::optional<ColourComponent>& component) {
  if (!component) return {};
  return (component->kind == ColourComponent::Kind::kDiffuse ? "diffuse " : "specular ") +
         std::to_string(component->yarn);
}

glm::vec3 Albedo(const v1::Rgb& rgb) { return {rgb.r(), rgb.g(), rgb.b()}; }

}  // namespace

std::vector<SheetChannels> ColourSheetChannels(size_t yarns) {
  std::vector<SheetChannels> sheets;
  size_t channel = 0;
  for (const ColourComponent::Kind kind : {ColourComponent::Kind::kDiffuse, ColourComponent::Kind::kSpecular}) {
    for (size_t yarn = 0; yarn < yarns; ++yarn, ++channel) {
      if (channel % 3 == 0) sheets.emplace_back();
      sheets.back()[channel % 3] = ColourComponent{kind, static_cast<uint32_t>(yarn)};
    }
  }
  return sheets;
}

FabricTile ComponentTile(FabricTile tile, const SheetChannels& channels) {
  for (YarnMaterial& material : tile.materials) {
    material.diffuse_albedo = glm::vec3(0.0f);
    material.specular_albedo = glm::vec3(0.0f);
  }
  for (int c = 0; c < 3; ++c) {
    if (!channels[c]) continue;
    if (channels[c]->yarn >= tile.materials.size()) {
      throw Error(ErrorCode::kInvalidArgument, "colour sheet: yarn " + std::to_string(channels[c]->yarn) +
                                                   " of a tile with " + std::to_string(tile.materials.size()) +
                                                   " yarn materials");
    }
    YarnMaterial& material = tile.materials[channels[c]->yarn];
    (channels[c]->kind == ColourComponent::Kind::kDiffuse ? material.diffuse_albedo : material.specular_albedo)[c] = 1.0f;
  }
  return tile;
}

glm::mat3 SheetColours(const v1::FabricSpec& fabric, const SheetChannels& channels) {
  glm::mat3 colours(0.0f);
  for (int c = 0; c < 3; ++c) {
    if (!channels[c]) continue;
    const uint32_t yarn = channels[c]->yarn;
    if (yarn >= static_cast<uint32_t>(fabric.yarns_size())) {
      throw Error(ErrorCode::kInvalidArgument, "colour components of yarn " + std::to_string(yarn) +
                                                   " for a fabric with " + std::to_string(fabric.yarns_size()) +
                                                   " yarns");
    }
    const v1::YarnSpec& spec = fabric.yarns(static_cast<int>(yarn));
    colours[c] = Albedo(channels[c]->kind == ColourComponent::Kind::kDiffuse ? spec.diffuse_albedo()
                                                                              : spec.specular_albedo());
  }
  return colours;
}

nlohmann::json ColourSheetsJson(const std::vector<SheetChannels>& sheets) {
  nlohmann::json json = nlohmann::json::array();
  for (const SheetChannels& sheet : sheets) {
    json.push_back({ComponentName(sheet[0]), ComponentName(sheet[1]), ComponentName(sheet[2])});
  }
  return json;
}

std::vector<SheetChannels> ParseColourSheets(const nlohmann::json& json,
                                             const std::function<Error(const std::string&)>& invalid) {
  if (!json.is_array() || json.empty() || json.size() > size_t{kMaxYarns}) {
    throw invalid("colour sheets: 1 to " + std::to_string(kMaxYarns) + " sheets of three channels expected");
  }
  std::vector<SheetChannels> sheets;
  for (const nlohmann::json& sheet : json) {
    if (!sheet.is_array() || sheet.size() != 3) throw invalid("colour sheets: a sheet is three channel names");
    SheetChannels& channels = sheets.emplace_back();
    for (int c = 0; c < 3; ++c) {
      if (!sheet[c].is_string()) throw invalid("colour sheets: a channel name is a string");
      const std::string name = sheet[c].get<std::string>();
      if (name.empty()) continue;
      for (const auto kind : {ColourComponent::Kind::kDiffuse, ColourComponent::Kind::kSpecular}) {
        for (uint32_t yarn = 0; yarn < uint32_t{kMaxYarns} && !channels[c]; ++yarn) {
          if (ComponentName(ColourComponent{kind, yarn}) == name) channels[c] = ColourComponent{kind, yarn};
        }
      }
      if (!channels[c]) throw invalid("colour sheets: '" + name + "' is not a colour component");
    }
  }
  return sheets;
}

}  // namespace loom
