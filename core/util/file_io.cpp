#include "core/util/file_io.h"

#include <unistd.h>

#include <cerrno>
#include <cstring>
#include <fstream>
#include <sstream>

#include "core/util/error.h"

namespace loom {

std::string ReadFile(const std::filesystem::path& path) {
  std::ifstream in(path, std::ios::binary);
  if (!in) {
    throw Error(ErrorCode::kNotFound, "cannot read " + path.string() + ": " + std::strerror(errno));
  }
  std::ostringstream contents;
  contents << in.rdbuf();
  return contents.str();
}

void ReadFileInPieces(const std::filesystem::path& path, const std::function<void(std::string_view)>& consume,
                      size_t piece_bytes) {
  std::ifstream in(path, std::ios::binary);
  if (!in) {
    throw Error(ErrorCode::kNotFound, "cannot read " + path.string() + ": " + std::strerror(errno));
  }
  std::string piece(piece_bytes, '\0');
  while (in) {
    in.read(piece.data(), static_cast<std::streamsize>(piece.size()));
    const auto count = static_cast<size_t>(in.gcount());
    if (count > 0) consume(std::string_view(piece.data(), count));
  }
  if (in.bad()) throw Error(ErrorCode::kNotFound, "cannot read " + path.string() + ": " + std::strerror(errno));
}

void WriteFileAtomic(const std::filesystem::path& path, std::string_view bytes) {
  if (path.has_parent_path()) std::filesystem::create_directories(path.parent_path());
  std::filesystem::path temp = path;
  temp += ".tmp-" + std::to_string(::getpid());
  {
    std::ofstream out(temp, std::ios::binary | std::ios::trunc);
    out.write(bytes.data(), static_cast<std::streamsize>(bytes.size()));
    out.flush();
    if (!out) {
      std::error_code ignored;
      std::filesystem::remove(temp, ignored);
      throw Error(ErrorCode::kUnavailable, "cannot write " + temp.string() + ": " + std::strerror(errno));
    }
  }
  std::filesystem::rename(temp, path);
}

}  // namespace loom
