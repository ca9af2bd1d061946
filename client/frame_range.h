#pragma once
// Rendering a frame range of a scene's glTF mesh sequences (`loom render
// --frames A..B`): one render job per frame, so the workers share the range and
// the queue retries a failed frame alone; the client gathers the frames in order.

#include <cstdint>
#include <string>
#include <vector>

#include "client/job_client.h"
#include "loom/v1/service.pb.h"

namespace loom::client {

struct FrameRange {
  uint32_t first = 0, last = 0;  // inclusive
  uint32_t size() const { return last - first + 1; }
};

// "A..B" (A ≤ B) or "A", each at most the last frame a sequence may have
// (core/spec/limits.h); Error(kInvalidArgument) naming --frames otherwise.
FrameRange ParseFrameRange(const std::string& text);

// An output file name pattern with one integer conversion, as ffmpeg reads them:
// "%d" or "%0Nd" (N ≤ 9); "%%" is a literal %. Error(kInvalidArgument) naming
// --out for any other pattern.
void CheckFramePattern(const std::string& pattern);
// The pattern's file name for `frame`.
std::string FramePath(const std::string& pattern, uint32_t frame);

// The objects of `scene` whose meshes are glTF sequences (gltf_path): found
// before JobClient::UploadMeshes makes every path an artifact. Error(kInvalidArgument)
// naming --frames when there is none to take frames from.
std::vector<int> SequenceObjects(const v1::SceneSpec& scene);

// Submits `request` (a render) once per frame of `range`, with the meshes of
// `sequence_objects` at that frame, the last frame first: a range past the
// sequence's end is refused before anything is queued. With a client_request_id
// R, frame N's job carries "R/frame-N", so submitting the range again answers with
// the same jobs. Returns the responses in frame order.
std::vector<v1::SubmitJobResponse> SubmitFrameRange(JobClient& client, const v1::SubmitJobRequest& request,
                                                    const std::vector<int>& sequence_objects, FrameRange range);

}  // namespace loom::client
