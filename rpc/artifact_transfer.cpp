#include "rpc/artifact_transfer.h"

#include <algorithm>

#include "core/util/error.h"
#include "core/util/sha256.h"
#include "rpc/channel.h"

namespace loom::rpc {
namespace {

void CheckContent(const v1::ArtifactRef& expected, std::string_view bytes, std::string_view what) {
  if (bytes.size() != expected.size()) {
    throw Error(ErrorCode::kInvalidArgument, std::string(what) + " '" + expected.name() + "': received " +
                                                 std::to_string(bytes.size()) + " bytes, header says " +
                                                 std::to_string(expected.size()));
  }
  const std::string actual = Sha256Hex(bytes);
  if (actual != expected.sha256()) {
    throw Error(ErrorCode::kInvalidArgument, std::string(what) + " '" + expected.name() + "': SHA-256 " + actual +
                                                 " does not match the header's " + expected.sha256());
  }
}

}  // namespace

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

Download ReadDownload(grpc::ClientReaderInterface<v1::ArtifactChunk>& reader) {
  Download download;
  v1::ArtifactChunk chunk;
  bool first = true;
  while (reader.Read(&chunk)) {
    if (first) download.artifact = chunk.artifact();
    first = false;
    if (download.bytes.size() + chunk.chunk().size() > download.artifact.size()) {
      throw Error(ErrorCode::kInternal, "DownloadArtifact: the server sent more than the " +
                                            std::to_string(download.artifact.size()) + " bytes it announced");
    }
    download.bytes += chunk.chunk();
  }
  return download;
}

void VerifyDownload(const Download& download, std::string_view sha256) {
  if (download.artifact.sha256() != sha256) {
    throw Error(ErrorCode::kInternal, "DownloadArtifact: asked for " + std::string(sha256) + ", the server sent " +
                                          download.artifact.sha256());
  }
  CheckContent(download.artifact, download.bytes, "downloaded artifact");
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
