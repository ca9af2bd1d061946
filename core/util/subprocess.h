#pragma once
// Running the helper programs Loom's tools hand work to (gnuplot for charts,
// ffmpeg for videos): found on PATH, started without a shell (arguments pass
// as they are), waited for.

#include <string>
#include <vector>

namespace loom {

// The path of `program` on PATH; empty if absent.
std::string FindOnPath(const std::string& program);

// Runs `program` (found on PATH) with `arguments` and waits for it; its output
// goes where the caller's goes. Error(kUnavailable) naming `install_hint` when
// the program is not on PATH, Error(kInternal) when it fails.
void RunProgram(const std::string& program, const std::vector<std::string>& arguments,
                const std::string& install_hint);

}  // namespace loom
