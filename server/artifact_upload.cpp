#include "server/artifact_upload.h"

#include <string>

#include "core/util/error.h"

namespace loom::server {

v1::ArtifactRef ReceiveUpload(grpc::ServerReaderInterface<v1::UploadArtifactRequest>& reader,
                              ArtifactStore& artifacts, uint64_t max_bytes, const UploadHeaderCheck& check_header) {
  v1::UploadArtifactRequest message;
  if (!reader.Read(&message) || !message.has_header()) {
    throw Error(ErrorCode::kInvalidArgument, "UploadArtifact: the first message must be the header");
  }
  const v1::ArtifactRef artifact = message.header().artifact();
  CheckArtifactHash(artifact.sha256(), "header.artifact.sha256");
  if (artifact.size() > max_bytes) {
    throw Error(ErrorCode::kInvalidArgument, "header.artifact.size: " + std::to_string(artifact.size()) +
                                                 " bytes exceed " + std::to_string(max_bytes));
  }
  check_header(message.header());
  ArtifactWriter writer = artifacts.NewWriter();
  while (reader.Read(&message)) {
    if (message.has_header()) throw Error(ErrorCode::kInvalidArgument, "UploadArtifact: a second header");
    if (message.chunk().size() > kMaxUploadChunkBytes) {
      throw Error(ErrorCode::kInvalidArgument, "UploadArtifact chunk: " + std::to_string(message.chunk().size()) +
                                                   " bytes exceed " + std::to_string(kMaxUploadChunkBytes));
    }
    if (writer.bytes() + message.chunk().size() > artifact.size()) {
      throw Error(ErrorCode::kInvalidArgument, "UploadArtifact '" + artifact.name() +
                                                   "': more bytes than the header's size " +
                                                   std::to_string(artifact.size()));
    }
    writer.Append(message.chunk());
  }
  if (writer.bytes() != artifact.size()) {
    throw Error(ErrorCode::kInvalidArgument, "UploadArtifact '" + artifact.name() + "': received " +
                                                 std::to_string(writer.bytes()) + " of " +
                                                 std::to_string(artifact.size()) + " bytes");
  }
  writer.Commit(artifact.sha256());
  return artifact;
}

}  // namespace loom::server
