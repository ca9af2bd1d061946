#include "core/spec/spec_json.h"

#include <google/protobuf/util/json_util.h>

#include <algorithm>
#include <regex>
#include <vector>

#include "core/util/error.h"
#include "core/util/file_io.h"
#include "loom/v1/animation.pb.h"
#include "loom/v1/fabric.pb.h"
#include "loom/v1/precompute.pb.h"
#include "loom/v1/scene.pb.h"

namespace loom {
namespace {

std::string JoinPath(std::string_view root, std::string_view path) {
  std::string joined(root);
  if (!root.empty() && !path.empty()) joined.append(".");
  return joined.append(path);
}

// Protobuf 3.21 reports "(knit) ribKnitt: Cannot find field." (no parenthesis at
// the top level) and
// "(knit.pattern): invalid value ...". Rewrite both as "<root>.<path>: <what>".
// The fields of the oneof named `oneof` that holds field `field`, in `type` or a
// message type it contains.
std::vector<std::string> OneofFields(const google::protobuf::Descriptor& type, const std::string& oneof,
                                     const std::string& field,
                                     std::vector<const google::protobuf::Descriptor*>& seen) {
  if (std::find(seen.begin(), seen.end(), &type) != seen.end()) return {};
  seen.push_back(&type);
  for (int i = 0; i < type.oneof_decl_count(); ++i) {
    const google::protobuf::OneofDescriptor& decl = *type.oneof_decl(i);
    if (decl.name() != oneof) continue;
    std::vector<std::string> names;
    for (int f = 0; f < decl.field_count(); ++f) names.push_back(decl.field(f)->name());
    if (std::find(names.begin(), names.end(), field) != names.end()) return names;
  }
  for (int i = 0; i < type.field_count(); ++i) {
    if (const google::protobuf::Descriptor* nested = type.field(i)->message_type()) {
      if (auto names = OneofFields(*nested, oneof, field, seen); !names.empty()) return names;
    }
  }
  return {};
}

// Protobuf says "oneof field 'structure' is already set. Cannot set 'woven'";
// name both fields instead.
std::string DescribeOneofError(const std::string& path, const google::protobuf::Descriptor& type,
                               const std::string& oneof, const std::string& second) {
  std::vector<const google::protobuf::Descriptor*> seen;
  const std::vector<std::string> fields = OneofFields(type, oneof, second, seen);
  if (fields.size() == 2) {
    return path + ": " + fields[0] + " and " + fields[1] + " are both set; give only one (oneof " + oneof + ")";
  }
  std::string others;
  for (const std::string& name : fields) others += (others.empty() ? "" : ", ") + name;
  return path + ": " + second + " and another of " + oneof + " (" + others + ") are both set; give only one";
}

std::string DescribeParseError(std::string_view root, const std::string& message,
                               const google::protobuf::Descriptor& type) {
  // At the top level protobuf leaves out the "(path) " prefix.
  static const std::regex kUnknownField(R"(^(?:\(([^)]*)\) )?([^:]+): Cannot find field\.?)");
  static const std::regex kAtPath(R"(^\(([^)]*)\): (.*)$)");
  static const std::regex kOneof(R"(^(?:\(([^)]*)\))?:? ?invalid value oneof field '(\w+)' is already set\. Cannot set '(\w+)')");
  std::smatch match;
  if (std::regex_search(message, match, kOneof)) {
    return DescribeOneofError(JoinPath(root, match[1].str()), type, match[2].str(), match[3].str());
  }
  if (std::regex_search(message, match, kUnknownField)) {
    return JoinPath(root, JoinPath(match[1].str(), match[2].str())) + ": unknown field";
  }
  if (std::regex_search(message, match, kAtPath)) {
    return JoinPath(root, match[1].str()) + ": " + match[2].str();
  }
  return std::string(root) + ": " + (message.empty() ? "not valid JSON" : message);
}

}  // namespace

void ParseSpecJson(std::string_view json, std::string_view root, google::protobuf::Message* out) {
  google::protobuf::util::JsonParseOptions options;
  options.ignore_unknown_fields = false;
  out->Clear();
  const auto status = google::protobuf::util::JsonStringToMessage(
      google::protobuf::StringPiece(json.data(), json.size()), out, options);
  if (!status.ok()) {
    throw Error(ErrorCode::kInvalidArgument,
                DescribeParseError(root, std::string(status.message()), *out->GetDescriptor()));
  }
}

template <typename Spec>
Spec LoadSpecFile(const std::filesystem::path& path, std::string_view root) {
  const std::string text = ReadFile(path);
  try {
    return ParseSpecJson<Spec>(text, root);
  } catch (const Error& error) {
    throw Error(error.code(), path.string() + ": " + error.what());
  }
}

template v1::FabricSpec LoadSpecFile<v1::FabricSpec>(const std::filesystem::path&, std::string_view);
template v1::PrecomputeSettings LoadSpecFile<v1::PrecomputeSettings>(const std::filesystem::path&,
                                                                     std::string_view);
template v1::SceneSpec LoadSpecFile<v1::SceneSpec>(const std::filesystem::path&, std::string_view);
template v1::AnimationSpec LoadSpecFile<v1::AnimationSpec>(const std::filesystem::path&, std::string_view);

std::string SpecToJson(const google::protobuf::Message& spec, bool pretty) {
  google::protobuf::util::JsonPrintOptions options;
  options.add_whitespace = pretty;
  options.preserve_proto_field_names = true;
  std::string json;
  const auto status = google::protobuf::util::MessageToJsonString(spec, &json, options);
  if (!status.ok()) throw Error(ErrorCode::kInternal, "cannot print spec: " + std::string(status.message()));
  return json;
}

}  // namespace loom
