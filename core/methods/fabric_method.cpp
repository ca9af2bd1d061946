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

void FabricAsset::Write(const v1::PrecomputeSettings& settings, const std::string& fabric_key,
                        const std::filesystem::path& directory) const {
  // The manifests say whether there is a back sheet, whatever `settings` left unset.
  v1::PrecomputeSettings recorded = settings;
  if (back_) {
    recorded.set_transmission(true);
  } else {
    recorded.clear_transmission();
  }
  if (back_) back_->WriteSheet(recorded, fabric_key, AssetSheet(directory, kBackSheetPrefix));
  WriteSheet(recorded, fabric_key, directory);
}

RadianceSamples MirroredLights(RadianceSamples samples) {
  samples.light_directions = MirroredThroughTheSurface(std::move(samples.light_directions));
  return samples;
}

std::unique_ptr<FabricAsset> ReadAnyFabricAsset(const std::filesystem::path& directory) {
  const std::filesystem::path manifest_path = directory / "manifest.json";
  std::string name = "svbrdf";
  bool transmission = false;
  try {
    const nlohmann::json manifest = nlohmann::json::parse(ReadFile(manifest_path));
    if (manifest.contains("method")) name = manifest.at("method").get<std::string>();
    if (manifest.contains("settings") && manifest.at("settings").contains("transmission")) {
      transmission = manifest.at("settings").at("transmission").get<bool>();
    }
  } catch (const nlohmann::json::exception& e) {
    throw Error(ErrorCode::kInvalidArgument, manifest_path.string() + " is not a valid manifest: " + e.what());
  }
  const FabricMethod* method = MethodNamed(name);
  if (method == nullptr) {
    throw Error(ErrorCode::kInvalidArgument, manifest_path.string() + ": method '" + name + "' is not one this engine has");
  }
  std::unique_ptr<FabricAsset> asset = method->Read(directory);
  if (transmission) asset->set_back(method->Read(AssetSheet(directory, kBackSheetPrefix)));
  return asset;
}

}  // namespace loom
