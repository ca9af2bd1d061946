#pragma once
// Whole-file reads and atomic writes (temp name, then rename).

#include <filesystem>
#include <string>
#include <string_view>

namespace loom {

// Throws Error(kNotFound) naming the path and the system's reason.
std::string ReadFile(const std::filesystem::path& path);

// Writes to "<path>.tmp-<pid>" and renames over `path`, so a reader never sees a
// half-written file. Creates missing parent directories.
void WriteFileAtomic(const std::filesystem::path& path, std::string_view bytes);

}  // namespace loom
