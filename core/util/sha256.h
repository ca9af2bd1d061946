#pragma once
// SHA-256 content hashes (fabric cache keys, artifact checksums), as lowercase hex.

#include <string>
#include <string_view>

namespace loom {

std::string Sha256Hex(std::string_view bytes);

}  // namespace loom
