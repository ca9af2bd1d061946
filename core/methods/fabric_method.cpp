#include "core/methods/fabric_method.h"

#include <array>

#include <nlohmann/json.hpp>

#include "core/acquire/hemisphere_directions.h"
#include "core/methods/factored/factored_method.h"
#include "core/methods/neural/neural_method.h"
#include "core/methods/svbrdf/svbrdf_method.h"
#include "core/methods/tabulated/tabulated_method.h"
#include "core/util/error.h"
#include "core/util/file_io.h"

namespace loom {
namespace {

// Every method, the default first.
std::array<const FabricMethod*, 4> Methods() {
  return {&SvbrdfMethod(), &TabulatedMethod(), &FactoredMethod(), &NeuralMethod()};
}

// `view_side`, checked against the count of view heights before any texture is made.
int CheckedViewSide(int view_side, size_t view_heights) {
  if (view_side <= 0 || view_heights != static_cast<size_t>(view_side) * static_cast<size_t>(view_side)) {
    throw Error(ErrorCode::kInvalidArgument, "fabric surface: " + std::to_string(view_heights) +
                                                 " view heights for a " + std::to_string(view_side) + "² view grid");
  }
  return view_side;
}

}  // namespace

FabricSurface::FabricSurface(int levels, int resolution, int view_side, int light_side,
                             const std::vector<float>& view_heights)
    : levels_(levels),
      resolution_(resolution),
      view_side_(view_side),
      light_side_(light_side),
      heights_(1, CheckedViewSide(view_side, view_heights.size()), 1, /*half=*/false) {
  heights_.Upload(0, view_heights.data());
}

void FabricSurface::Bind(const gl::ShaderProgram& program, GLuint views, int first_unit, glm::vec2 repeat) const {
  glBindTextureUnit(static_cast<GLuint>(first_unit), views);
  glBindTextureUnit(static_cast<GLuint>(first_unit + 1), heights_.id());
  program.Set("u_fabric_views", first_unit);
  program.Set("u_fabric_view_heights", first_unit + 1);
  program.Set("u_fabric_levels", levels_);
  program.Set("u_fabric_resolution", resolution_);
  program.Set("u_fabric_view_side", view_side_);
  program.Set("u_fabric_light_side", light_side_);
  program.Set("u_fabric_repeat", repeat);
}

const FabricMethod& MethodOf(v1::FabricMethod id) {
  if (id == v1::FABRIC_METHOD_UNSPECIFIED) return *Methods().front();
  for (const FabricMethod* method : Methods()) {
    if (method->id() == id) return *method;
  }
  throw Error(ErrorCode::kInvalidArgument, "fabric method " + std::to_string(id) + " is not one this engine has");
}

const FabricMethod* MethodNamed(std::string_view name) {
  for (const FabricMethod* method : Methods()) {
    if (method->name() == name) return method;
  }
  return nullptr;
}

std::string MethodNames() {
  std::string names;
  for (const FabricMethod* method : Methods()) names += (names.empty() ? "" : ", ") + std::string(method->name());
  return names;
}

std::string ColourSheetPrefix(size_t index) { return "colour" + std::to_string(index) + "-"; }

void FabricAsset::Write(const v1::PrecomputeSettings& settings, const std::string& fabric_key,
                        const std::filesystem::path& directory) const {
  // The manifests say whether there are back and colour sheets, whatever `settings`
  // left unset.
  v1::PrecomputeSettings recorded = settings;
  if (back_) {
    recorded.set_transmission(true);
  } else {
    recorded.clear_transmission();
  }
  if (!colour_channels_) {
    recorded.clear_colour_components();
  } else {
    recorded.set_colour_components(true);
    std::filesystem::create_directories(directory);
    std::vector<SheetChannels> channels = {*colour_channels_};
    for (size_t i = 0; i < colour_sheets_.size(); ++i) {
      colour_sheets_[i]->WriteSides(recorded, fabric_key, AssetSheet(directory, ColourSheetPrefix(i + 1)));
      channels.push_back(colour_sheets_[i]->colour_channels().value());
    }
    WriteFileAtomic(directory / kColourSheetsFile, ColourSheetsJson(channels).dump());
  }
  WriteSides(recorded, fabric_key, directory);
}

void FabricAsset::WriteSides(const v1::PrecomputeSettings& settings, const std::string& fabric_key,
                             const AssetSheet& sheet) const {
  if (back_) back_->WriteSheet(settings, fabric_key, AssetSheet(sheet.directory, sheet.prefix + kBackSheetPrefix));
  WriteSheet(settings, fabric_key, sheet);
}

std::unique_ptr<GpuFabric> UploadSheets(const FabricAsset& asset, bool half) {
  std::unique_ptr<GpuFabric> uploaded = asset.Upload(half);
  uploaded->colour_channels_ = asset.colour_channels();
  if (asset.back() != nullptr) {
    uploaded->back_ = asset.back()->Upload(half);
    uploaded->back_->colour_channels_ = asset.colour_channels();  // the same components, lit from behind
  }
  for (const auto& sheet : asset.colour_sheets()) uploaded->colour_sheets_.push_back(UploadSheets(*sheet, half));
  return uploaded;
}

RadianceSamples MirroredLights(RadianceSamples samples) {
  samples.light_directions = MirroredThroughTheSurface(std::move(samples.light_directions));
  return samples;
}

std::unique_ptr<FabricAsset> ReadAnyFabricAsset(const std::filesystem::path& directory) {
  const std::filesystem::path manifest_path = directory / "manifest.json";
  std::string name = "svbrdf";
  bool transmission = false, colour_components = false;
  try {
    const nlohmann::json manifest = nlohmann::json::parse(ReadFile(manifest_path));
    if (manifest.contains("method")) name = manifest.at("method").get<std::string>();
    if (manifest.contains("settings")) {
      const nlohmann::json& settings = manifest.at("settings");
      transmission = settings.value("transmission", false);
      colour_components = settings.value("colour_components", false);
    }
  } catch (const nlohmann::json::exception& e) {
    throw Error(ErrorCode::kInvalidArgument, manifest_path.string() + " is not a valid manifest: " + e.what());
  }
  const FabricMethod* method = MethodNamed(name);
  if (method == nullptr) {
    throw Error(ErrorCode::kInvalidArgument, manifest_path.string() + ": method '" + name + "' is not one this engine has");
  }
  const auto read_sides = [&](const AssetSheet& sheet) {
    std::unique_ptr<FabricAsset> asset = method->Read(sheet);
    if (transmission) asset->set_back(method->Read(AssetSheet(sheet.directory, sheet.prefix + kBackSheetPrefix)));
    return asset;
  };
  std::unique_ptr<FabricAsset> asset = read_sides(directory);
  if (colour_components) {
    const std::filesystem::path sheets_path = directory / kColourSheetsFile;
    const auto invalid = [&](const std::string& what) {
      return Error(ErrorCode::kInvalidArgument, sheets_path.string() + ": " + what);
    };
    nlohmann::json json;
    try {
      json = nlohmann::json::parse(ReadFile(sheets_path));
    } catch (const nlohmann::json::exception& e) {
      throw invalid(std::string("not JSON: ") + e.what());
    }
    const std::vector<SheetChannels> sheets = ParseColourSheets(json, invalid);
    asset->set_colour_channels(sheets.front());
    for (size_t i = 1; i < sheets.size(); ++i) {
      std::unique_ptr<FabricAsset> sheet = read_sides(AssetSheet(directory, ColourSheetPrefix(i)));
      sheet->set_colour_channels(sheets[i]);
      asset->add_colour_sheet(std::move(sheet));
    }
  }
  return asset;
}

}  // namespace loom
