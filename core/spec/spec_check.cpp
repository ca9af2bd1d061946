#include "core/spec/spec_check.h"

#include "core/spec/defaults.h"
#include "core/spec/spec_json.h"
#include "core/util/error.h"

namespace loom {
namespace {

template <typename Spec>
SpecCheck Check(const std::filesystem::path& path, const char* root) {
  const Spec spec = LoadSpecFile<Spec>(path, root);
  return SpecCheck{Validate(spec, root), SpecToJson(WithDefaults(spec))};
}

}  // namespace

SpecKind ParseSpecKind(std::string_view name) {
  if (name == "fabric") return SpecKind::kFabric;
  if (name == "precompute") return SpecKind::kPrecompute;
  if (name == "scene") return SpecKind::kScene;
  if (name == "animation") return SpecKind::kAnimation;
  throw Error(ErrorCode::kInvalidArgument,
              "spec kind '" + std::string(name) + "' is not one of fabric, precompute, scene, animation");
}

const char* SpecKindName(SpecKind kind) {
  switch (kind) {
    case SpecKind::kFabric: return "fabric";
    case SpecKind::kPrecompute: return "precompute";
    case SpecKind::kScene: return "scene";
    case SpecKind::kAnimation: return "animation";
  }
  return "?";
}

SpecCheck CheckSpecFile(SpecKind kind, const std::filesystem::path& path) {
  switch (kind) {
    case SpecKind::kFabric: return Check<v1::FabricSpec>(path, "fabric");
    case SpecKind::kPrecompute: return Check<v1::PrecomputeSettings>(path, "precompute");
    case SpecKind::kScene: return Check<v1::SceneSpec>(path, "scene");
    case SpecKind::kAnimation: return Check<v1::AnimationSpec>(path, "animation");
  }
  throw Error(ErrorCode::kInternal, "unknown spec kind");
}

nlohmann::json SpecCheckJson(const std::string& file, const SpecCheck& check) {
  nlohmann::json issues = nlohmann::json::array();
  for (const ValidationIssue& issue : check.issues) issues.push_back({{"path", issue.path}, {"message", issue.message}});
  return {{"file", file}, {"valid", check.issues.empty()}, {"issues", issues}};
}

std::string SpecCheckText(const std::string& file, SpecKind kind, const SpecCheck& check) {
  if (check.issues.empty()) return file + ": valid " + SpecKindName(kind) + " spec\n";
  std::string text;
  for (const ValidationIssue& issue : check.issues) text += file + ": " + issue.ToString() + "\n";
  return text;
}

}  // namespace loom
