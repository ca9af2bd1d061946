#pragma once
// Whole-file reads and atomic writes (temp name, then rename).

#include <cstddef>
#include <filesystem>
#include <functional>
#include <string>
#include <string_view>

namespace loom {

// Throws Error(kNotFound) naming the path and the system's reason.
std::string ReadFile(const std::filesystem::path& path);

// Calls `consume` with the file's bytes in order, `piece_bytes` at a time (the
// last piece shorter), holding only one piece in memory. Errors as ReadFile.
void ReadFileInPieces(const std::filesystem::path& path, const std::function<void(std::string_view)>& consume,
                      size_t piece_bytes = size_t{1} << 20);

// Writes to "<path>.tmp-<pid>" and renames over `path`, so a reader never sees a
// half-written file. Creates missing parent directories.
void WriteFileAtomic(const std::filesystem::path& path, std::string_view bytes);

}  // namespace loom
