#pragma once
// A check of an OpenEXR file's header before OpenEXR reads it. Debian's OpenEXR
// 3.1 allocates what a header field says before reading what follows (a small file
// whose string attribute claims gigabytes is read as gigabytes: found by
// fuzz/asset_fuzzer, docs/operations.md "Fuzzing"), so EXR bytes from another machine
// are checked first.
// Accepted: a single-part scanline or tiled image whose data window is exactly the
// `width`×`height` the caller expects, every attribute within the file, vectors
// and previews consistent with their own sizes, tiles of 16 to 65536 pixels a
// side and no larger than the image (or 64 pixels; OpenImageIO allocates a whole
// tile, however small the image: found by fuzz/asset_fuzzer). Anything else is
// Error(kInvalidArgument) naming `source` and the field.

#include <string>
#include <string_view>

namespace loom {

void CheckExrHeader(std::string_view bytes, int width, int height, const std::string& source);

}  // namespace loom
