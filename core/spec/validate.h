#pragma once
// One validation function per spec. Each returns every problem it finds (not only
// the first), each with the field path and the allowed range, e.g.
//   {"precompute.view_directions", "5000 exceeds 4096"}
// The caps in core/spec/limits.h bound everything that drives memory or time.
// Validation applies WithDefaults first, so zero-means-default values pass.

#include <string>
#include <vector>

#include "loom/v1/animation.pb.h"
#include "loom/v1/fabric.pb.h"
#include "loom/v1/precompute.pb.h"
#include "loom/v1/scene.pb.h"

namespace loom {

struct ValidationIssue {
  std::string path;     // e.g. "fabric.yarns[1].radius"
  std::string message;  // e.g. "0.7 exceeds 0.5"
  std::string ToString() const { return path + ": " + message; }
};

using ValidationIssues = std::vector<ValidationIssue>;

// `root` prefixes every path ("fabric" for a fabric file; a scene passes
// "scene.objects[0].fabric.fabric").
ValidationIssues Validate(const v1::FabricSpec& fabric, const std::string& root = "fabric");
ValidationIssues Validate(const v1::PrecomputeSettings& settings, const std::string& root = "precompute");
// A fabric and the settings it is precomputed with: both specs' issues.
ValidationIssues Validate(const v1::FabricSpec& fabric, const v1::PrecomputeSettings& settings);
ValidationIssues Validate(const v1::RenderSettings& settings, const std::string& root = "render");
ValidationIssues Validate(const v1::SceneSpec& scene, const std::string& root = "scene");
ValidationIssues Validate(const v1::AnimationSpec& animation, const std::string& root = "animation");

// One line per issue.
std::string FormatIssues(const ValidationIssues& issues);

// Throws Error(kInvalidArgument) with FormatIssues as the message if there are any.
void ThrowIfAny(const ValidationIssues& issues);

template <typename Spec>
void ValidateOrThrow(const Spec& spec) {
  ThrowIfAny(Validate(spec));
}

}  // namespace loom
