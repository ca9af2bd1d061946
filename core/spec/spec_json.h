#pragma once
// Spec files are JSON through protobuf's JSON mapping (DESIGN.md "Schema").
// Parsing is strict: an unknown field, a wrong type or an unknown enum name is an
// Error(kInvalidArgument) whose message names the field path, e.g.
//   "fabric.knit.ribKnitt: unknown field".
// Parsing checks syntax only; ranges are checked by core/spec/validate.h.

#include <google/protobuf/message.h>

#include <filesystem>
#include <string>
#include <string_view>

namespace loom {

// `root` names the spec in messages ("fabric", "precompute", "scene").
void ParseSpecJson(std::string_view json, std::string_view root, google::protobuf::Message* out);

template <typename Spec>
Spec ParseSpecJson(std::string_view json, std::string_view root) {
  Spec spec;
  ParseSpecJson(json, root, &spec);
  return spec;
}

// Reads and parses a spec file; errors name the file too.
template <typename Spec>
Spec LoadSpecFile(const std::filesystem::path& path, std::string_view root);

// Protobuf JSON with proto field names (snake_case), the form spec files are
// documented in. `pretty` indents; otherwise one line.
std::string SpecToJson(const google::protobuf::Message& spec, bool pretty = true);

}  // namespace loom
