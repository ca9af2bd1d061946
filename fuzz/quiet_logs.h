#pragma once
// Fuzz targets run millions of inputs: warnings about each (Loom's and
// protobuf's) would drown the fuzzer's own output.

#include <google/protobuf/stubs/logging.h>
#include <spdlog/spdlog.h>

namespace loom::fuzz {

inline void QuietLogs() {
  static const bool quiet = [] {
    spdlog::set_level(spdlog::level::off);
    // Protobuf's own complaints (invalid UTF-8 in a string field) too.
    google::protobuf::SetLogHandler(nullptr);
    return true;
  }();
  (void)quiet;
}

}  // namespace loom::fuzz
