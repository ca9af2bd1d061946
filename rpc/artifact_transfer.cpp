#include "rpc/artifact_transfer.h"

#include <algorithm>

#include "core/util/error.h"
#include "core/util/sha256.h"
#include "rpc/channel.h"

namespace loom::rpc {
v1::ArtifactRef MakeArtifactRef(std::string name, std::string_view bytes) {
  v1::ArtifactRef artifact;
  artifact.set_name(std::move(name));
  artifact.set_size(bytes.size());
  artifact.set_sha256(Sha256Hex(bytes));
  return artifact;
}

void WriteUpload(grpc::ClientWriterInterface<v1::UploadArtifactRequest>& writer,
                 const v1::UploadArtifactRequest::Header& header, std::string_view bytes) {
  v1::UploadArtifactRequest message;
  *message.mutable_header() = header;
  bool open = writer.Write(message);
  for (size_t offset = 0; open && offset < bytes.size(); offset += kChunkBytes) {
    message.set_chunk(std::string(bytes.substr(offset, kChunkBytes)));
    open = writer.Write(message);
  }
  // A closed stream means the server answered early; Finish says why.
  writer.WritesDone();
}

DownloadReceiver::DownloadReceiver(std::string sha256, std::function<void(std::string_view)> consume)
    : sha256_(std::move(sha256)), consume_(std::move(consume)) {}

void DownloadReceiver::Receive(const v1::ArtifactChunk& message) {
  if (first_) {
    announced_ = message.artifact();
    if (announced_.sha256() != sha256_) {
      throw Error(ErrorCode::kInternal, "DownloadArtifact: asked for " + sha256_ + ", the server sent " +
                                            announced_.sha256());
    }
  }
  first_ = false;
  if (bytes_ + message.chunk().size() > announced_.size()) {
    throw Error(ErrorCode::kInternal, "downloaded artifact " + sha256_ + ": more than the " +
                                                 std::to_string(announced_.size()) + " bytes announced");
  }
  bytes_ += message.chunk().size();
  hasher_.Update(message.chunk());
  consume_(message.chunk());
}

void DownloadReceiver::Finish() {
  if (first_) throw Error(ErrorCode::kInternal, "downloaded artifact " + sha256_ + ": the stream was empty");
  if (bytes_ != announced_.size()) {
    throw Error(ErrorCode::kInternal, "downloaded artifact " + sha256_ + ": received " +
                                                 std::to_string(bytes_) + " bytes, header says " +
                                                 std::to_string(announced_.size()));
  }
  const std::string actual = hasher_.FinishHex();
  if (actual != sha256_) {
    throw Error(ErrorCode::kInternal, "downloaded artifact " + sha256_ + ": SHA-256 " + actual +
                                                 " does not match");
  }
}

ArtifactSender::ArtifactSender(grpc::ServerWriterInterface<v1::ArtifactChunk>& writer,
                               const v1::ArtifactRef& artifact)
    : writer_(writer) {
  *message_.mutable_artifact() = artifact;
}

void ArtifactSender::Write(std::string_view chunk) {
  message_.set_chunk(std::string(chunk));
  if (!writer_.Write(message_)) throw Error(ErrorCode::kUnavailable, "DownloadArtifact: the client went away");
  message_.clear_artifact();
  first_ = false;
}

void ArtifactSender::Send(std::string_view bytes) {
  for (size_t offset = 0; offset < bytes.size(); offset += kChunkBytes) Write(bytes.substr(offset, kChunkBytes));
}

void ArtifactSender::Finish() {
  if (first_) Write({});  // an empty artifact: the header alone
}

}  // namespace loom::rpc
