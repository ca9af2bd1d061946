// The fabric asset readers (core/methods/fabric_method.h ReadAnyFabricAsset), as a
// worker reads an asset from the cache: manifest.json and the images of the method the
// manifest names (svbrdf: parameters.exr, lut.exr; tabulated: table.exr, views.exr;
// factored: view_terms.exr, light_terms.exr, views.exr; neural: latents.exr, views.exr;
// a manifest naming no known method gets svbrdf's). The input is the files in a
// container: u16 manifest length, the manifest, then each image but the last as u32
// length and bytes, the last image the rest. The manifest records each image's size and
// SHA-256, which a mutated image would fail at once; so for most inputs (first byte
// even) the harness writes the images' true size and hash into the manifest, when it is
// a JSON object, and the EXR decoding behind the check is reached.

#include <unistd.h>

#include <cstddef>
#include <cstdint>
#include <cstring>
#include <filesystem>
#include <nlohmann/json.hpp>
#include <string>
#include <string_view>
#include <vector>

#include "core/methods/fabric_method.h"
#include "core/methods/svbrdf/svbrdf_method.h"
#include "core/util/error.h"
#include "core/util/file_io.h"
#include "core/util/sha256.h"
#include "fuzz/quiet_logs.h"

namespace {

std::string_view Take(std::string_view& rest, size_t length) {
  const std::string_view part = rest.substr(0, std::min(length, rest.size()));
  rest.remove_prefix(part.size());
  return part;
}

template <typename T>
T Length(std::string_view& rest) {
  T value = 0;
  const std::string_view bytes = Take(rest, sizeof value);
  std::memcpy(&value, bytes.data(), bytes.size());
  return value;
}

const std::filesystem::path& Directory() {
  static const std::filesystem::path directory = [] {
    const std::filesystem::path base = std::filesystem::exists("/dev/shm") ? "/dev/shm" : "/tmp";
    std::filesystem::path path = base / ("loom-asset-fuzzer-" + std::to_string(::getpid()));
    std::filesystem::create_directories(path);
    return path;
  }();
  return directory;
}

}  // namespace

extern "C" int LLVMFuzzerTestOneInput(const uint8_t* data, size_t size) {
  loom::fuzz::QuietLogs();
  if (size == 0) return 0;
  const bool fix_checksums = data[0] % 2 == 0;
  std::string_view rest(reinterpret_cast<const char*>(data) + 1, size - 1);
  std::string manifest(Take(rest, Length<uint16_t>(rest)));
  nlohmann::json json = nlohmann::json::parse(manifest, nullptr, false);
  const std::string method = json.is_object() && json.contains("method") && json["method"].is_string()
                                 ? json["method"].get<std::string>()
                                 : "svbrdf";
  std::vector<const char*> names = {"parameters.exr", "lut.exr"};
  if (method == "tabulated") names = {"table.exr", "views.exr"};
  if (method == "factored") names = {"view_terms.exr", "light_terms.exr", "views.exr"};
  if (method == "neural") names = {"latents.exr", "views.exr"};
  std::vector<std::string_view> images;
  for (size_t i = 0; i + 1 < names.size(); ++i) images.push_back(Take(rest, Length<uint32_t>(rest)));
  images.push_back(rest);
  if (fix_checksums && json.is_object()) {
    for (size_t i = 0; i < names.size(); ++i) {
      json["files"][names[i]] = {{"bytes", images[i].size()}, {"sha256", loom::Sha256Hex(images[i])}};
    }
    manifest = json.dump();
  }
  loom::WriteFileAtomic(Directory() / "manifest.json", manifest);
  for (size_t i = 0; i < names.size(); ++i) loom::WriteFileAtomic(Directory() / names[i], images[i]);
  try {
    const std::unique_ptr<loom::FabricAsset> asset = loom::ReadAnyFabricAsset(Directory());
    // Every promise of a read svbrdf asset, as the renderer relies on them.
    if (const auto* svbrdf = dynamic_cast<const loom::SvbrdfAsset*>(asset.get())) {
      const loom::FittedFabric& fabric = svbrdf->fit();
      for (const loom::FittedLevel& level : fabric.levels) {
        if (level.brdfs.size() != size_t{level.resolution} * level.resolution ||
            level.lut.size() != level.brdfs.size() * fabric.view_directions.size()) {
          __builtin_trap();
        }
      }
    }
  } catch (const loom::Error&) {
  }
  return 0;
}
