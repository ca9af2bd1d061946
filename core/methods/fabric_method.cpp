#include "core/methods/fabric_method.h"

#include <array>

#include <nlohmann/json.hpp>

#include "core/methods/svbrdf/svbrdf_method.h"
#include "core/methods/tabulated/tabulated_method.h"
#include "core/util/error.h"
#include "core/util/file_io.h"

namespace loom {
namespace {

// Every method, the default first.
std::array<const FabricMethod*, 2> Methods() { return {&SvbrdfMethod(), &TabulatedMethod()}; }

}  // namespace

const FabricMethod& MethodOf(v1::FabricMethod id) {
  if (id == v1::FABRIC_METHOD_UNSPECIFIED) return *Methods().front();
  for (const FabricMethod* method : Methods()) {
    if (method->id() == id) return *method;
  }
  throw Error(ErrorCode::kInvalidArgument, "fabric method " + std::to_string(id) + " is not one this engine has");
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
  for (const FabricMethod* method : Methods()) {
    if (method->name() == name) return method->Read(directory);
  }
  throw Error(ErrorCode::kInvalidArgument, manifest_path.string() + ": method '" + name + "' is not one this engine has");
}

}  // namespace loom
