#pragma once
// Checking a spec file the way the server will: strict parse, then validation.
// Shared by `loom spec check` and `loom-lab validate`.

#include <nlohmann/json.hpp>

#include <filesystem>
#include <string>
#include <string_view>

#include "core/spec/validate.h"

namespace loom {

enum class SpecKind { kFabric, kPrecompute, kScene, kAnimation };

// "fabric", "precompute", "scene" or "animation"; throws Error(kInvalidArgument) otherwise.
SpecKind ParseSpecKind(std::string_view name);
const char* SpecKindName(SpecKind kind);

struct SpecCheck {
  ValidationIssues issues;
  // The spec with every default explicit, as protobuf JSON.
  std::string normalized_json;
};

// Parse errors throw Error(kInvalidArgument) naming the file and field; range
// problems come back in `issues`.
SpecCheck CheckSpecFile(SpecKind kind, const std::filesystem::path& path);

// {"file", "valid", "issues": [{"path", "message"}...]}, the --json report of a check.
nlohmann::json SpecCheckJson(const std::string& file, const SpecCheck& check);
// The plain report: "FILE: valid KIND spec", or one "FILE: field: problem" line per
// issue; each line ends with a newline.
std::string SpecCheckText(const std::string& file, SpecKind kind, const SpecCheck& check);

}  // namespace loom
