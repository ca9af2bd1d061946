#pragma once
// Fuzz targets run millions of inputs: warnings about each would drown the
// fuzzer's own output.

#include <spdlog/spdlog.h>

namespace loom::fuzz {

inline void QuietLogs() {
  static const bool quiet = [] {
    spdlog::set_level(spdlog::level::off);
    return true;
  }();
  (void)quiet;
}

}  // namespace loom::fuzz
