#include "core/methods/fabric_method.h"

#include <array>

#include <nlohmann/json.hpp>

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

}  // namespace

void FabricSurface::Set(const gl::ShaderProgram& program, int views_unit, glm::vec2 repeat) const {
  program.Set("u_fabric_views", views_unit);
  program.Set("u_fabric_levels", levels);
  program.Set("u_fabric_resolution", resolution);
  program.Set("u_fabric_view_side", view_side);
  program.Set("u_fabric_light_side", light_side);
  program.Set("u_fabric_repeat", repeat);
  program.Set("u_fabric_sampling_height", sampling_height);
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

std::unique_ptr<FabricAsset> ReadAnyFabricAsset(const std::filesystem::path& directory) {
  const std::filesystem::path manifest_path = directory / "manifest.json";
  std::string name = "svbrdf";
  try {
    const nlohmann::json manifest = nlohmann::json::parse(ReadFile(manifest_path));
    if (manifest.contains("method")) name = manifest.at("method").get<std::string>();
  } catch (const nlohmann::json::exception& e) {
    throw Error(ErrorCode::kInvalidArgument, manifest_path.string() + " is not a valid manifest: " + e.what());
  }
  const FabricMethod* method = MethodNamed(name);
  if (method == nullptr) {
    throw Error(ErrorCode::kInvalidArgument, manifest_path.string() + ": method '" + name + "' is not one this engine has");
  }
  return method->Read(directory);
}

}  // namespace loom
