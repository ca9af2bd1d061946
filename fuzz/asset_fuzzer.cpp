// The fabric asset reader (core/fit/fabric_asset.h): manifest.json, parameters.exr
// and lut.exr, as a worker reads them from the cache. The input is the three files
// in a container: u16 manifest length, the manifest, u32 parameters length, the
// parameters image, the LUT image (the rest). The manifest records each image's
// size and SHA-256, which a mutated image would fail at once; so for most inputs
// (first byte even) the harness writes the images' true size and hash into the
// manifest, when it is a JSON object, and the EXR decoding behind the check is
// reached.

#include <unistd.h>

#include <cstddef>
#include <cstdint>
#include <cstring>
#include <filesystem>
#include <nlohmann/json.hpp>
#include <string>
#include <string_view>

#include "core/fit/fabric_asset.h"
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
  const std::string_view parameters = Take(rest, Length<uint32_t>(rest));
  const std::string_view lut = rest;
  if (fix_checksums) {
    nlohmann::json json = nlohmann::json::parse(manifest, nullptr, false);
    if (json.is_object()) {
      json["files"]["parameters.exr"] = {{"bytes", parameters.size()}, {"sha256", loom::Sha256Hex(parameters)}};
      json["files"]["lut.exr"] = {{"bytes", lut.size()}, {"sha256", loom::Sha256Hex(lut)}};
      manifest = json.dump();
    }
  }
  loom::WriteFileAtomic(Directory() / "manifest.json", manifest);
  loom::WriteFileAtomic(Directory() / "parameters.exr", parameters);
  loom::WriteFileAtomic(Directory() / "lut.exr", lut);
  try {
    const loom::FittedFabric fabric = loom::ReadFabricAsset(Directory());
    // Every promise of a read asset, as the renderer relies on them.
    for (const loom::FittedLevel& level : fabric.levels) {
      if (level.brdfs.size() != size_t{level.resolution} * level.resolution ||
          level.lut.size() != level.brdfs.size() * fabric.view_directions.size()) {
        __builtin_trap();
      }
    }
  } catch (const loom::Error&) {
  }
  return 0;
}
