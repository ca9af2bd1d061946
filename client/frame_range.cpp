#include "client/frame_range.h"

#include <charconv>

#include "core/spec/limits.h"
#include "core/util/error.h"

namespace loom::client {
namespace {

uint32_t ParseFrame(std::string_view text, const std::string& whole) {
  uint64_t frame = 0;
  const auto [end, error] = std::from_chars(text.data(), text.data() + text.size(), frame);
  if (text.empty() || error != std::errc() || end != text.data() + text.size()) {
    throw Error(ErrorCode::kInvalidArgument, "--frames: " + whole + " is not A..B or A (frame numbers from 0)");
  }
  if (frame > kMaxAnimationFrames) {
    throw Error(ErrorCode::kInvalidArgument, "--frames: frame " + std::string(text) + " is past the last frame a " +
                                                 "sequence may have (" + std::to_string(kMaxAnimationFrames) + ")");
  }
  return static_cast<uint32_t>(frame);
}

// The pattern split around its one conversion: prefix, zero-padded width, suffix
// (literal %% already made %).
struct FramePattern {
  std::string prefix, suffix;
  int width = 0;
};

FramePattern SplitPattern(const std::string& pattern) {
  FramePattern split;
  bool found = false;
  for (size_t i = 0; i < pattern.size(); ++i) {
    std::string& out = found ? split.suffix : split.prefix;
    if (pattern[i] != '%') {
      out += pattern[i];
      continue;
    }
    if (i + 1 < pattern.size() && pattern[i + 1] == '%') {
      out += '%';
      ++i;
      continue;
    }
    // "%d" or "%0Nd"
    const std::string_view rest = std::string_view(pattern).substr(i + 1);
    const bool plain = rest.starts_with("d");
    const bool padded = rest.size() >= 3 && rest[0] == '0' && rest[1] >= '1' && rest[1] <= '9' && rest[2] == 'd';
    if (found || !(plain || padded)) {
      throw Error(ErrorCode::kInvalidArgument,
                  "--out: " + pattern + " needs exactly one frame number conversion, %d or %0Nd (N from 1 to 9)");
    }
    split.width = padded ? rest[1] - '0' : 0;
    i += padded ? 3 : 1;
    found = true;
  }
  if (!found) {
    throw Error(ErrorCode::kInvalidArgument,
                "--out: " + pattern + " has no frame number conversion (%d or %0Nd, as frame_%04d.png) for --frames");
  }
  return split;
}

}  // namespace

FrameRange ParseFrameRange(const std::string& text) {
  const size_t dots = text.find("..");
  FrameRange range;
  range.first = ParseFrame(std::string_view(text).substr(0, dots), text);
  range.last = dots == std::string::npos ? range.first : ParseFrame(std::string_view(text).substr(dots + 2), text);
  if (range.last < range.first) {
    throw Error(ErrorCode::kInvalidArgument, "--frames: " + text + " ends before it begins");
  }
  return range;
}

void CheckFramePattern(const std::string& pattern) { SplitPattern(pattern); }

std::string FramePath(const std::string& pattern, uint32_t frame) {
  const FramePattern split = SplitPattern(pattern);
  std::string number = std::to_string(frame);
  if (number.size() < static_cast<size_t>(split.width)) number.insert(0, split.width - number.size(), '0');
  return split.prefix + number + split.suffix;
}

std::vector<int> SequenceObjects(const v1::SceneSpec& scene) {
  std::vector<int> objects;
  for (int i = 0; i < scene.objects_size(); ++i) {
    if (scene.objects(i).mesh().source_case() == v1::MeshRef::kGltfPath) objects.push_back(i);
  }
  if (objects.empty()) {
    throw Error(ErrorCode::kInvalidArgument,
                "--frames: the scene has no glTF mesh (objects[].mesh.gltf_path) to take frames from");
  }
  return objects;
}

std::vector<v1::SubmitJobResponse> SubmitFrameRange(JobClient& client, const v1::SubmitJobRequest& request,
                                                    const std::vector<int>& sequence_objects, FrameRange range) {
  std::vector<v1::SubmitJobResponse> responses(range.size());
  auto submit = [&](uint32_t frame) {
    v1::SubmitJobRequest framed = request;
    v1::SceneSpec& scene = *framed.mutable_render()->mutable_scene();
    for (const int object : sequence_objects) scene.mutable_objects(object)->mutable_mesh()->set_frame(frame);
    if (!request.client_request_id().empty()) {
      framed.set_client_request_id(request.client_request_id() + "/frame-" + std::to_string(frame));
    }
    responses[frame - range.first] = client.Submit(framed);
  };
  submit(range.last);
  for (uint32_t frame = range.first; frame < range.last; ++frame) submit(frame);
  return responses;
}

}  // namespace loom::client
