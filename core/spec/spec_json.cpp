#include "core/spec/spec_json.h"

#include <google/protobuf/util/json_util.h>

#include <regex>

#include "core/util/error.h"
#include "core/util/file_io.h"
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
std::string DescribeParseError(std::string_view root, const std::string& message) {
  // At the top level protobuf leaves out the "(path) " prefix.
  static const std::regex kUnknownField(R"(^(?:\(([^)]*)\) )?([^:]+): Cannot find field\.?)");
  static const std::regex kAtPath(R"(^\(([^)]*)\): (.*)$)");
  std::smatch match;
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
                DescribeParseError(root, std::string(status.message())));
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
