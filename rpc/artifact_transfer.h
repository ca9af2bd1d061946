#pragma once
// Artifacts over gRPC streams: a header (name, size, SHA-256) then kChunkBytes
// pieces. The receiver hashes what arrives and refuses a transfer whose size or
// hash differs from the header, so a truncated or corrupted file is never stored or
// used (the server's receiving side streams into its artifact store:
// server/artifact_upload.h). Client and worker stubs share the message types, so
// one template serves both.

#include <grpcpp/client_context.h>
#include <grpcpp/support/sync_stream.h>

#include <cstdint>
#include <functional>
#include <string>
#include <string_view>

#include "core/util/sha256.h"
#include "loom/v1/service.pb.h"
#include "rpc/status.h"

namespace loom::rpc {

// name, size and SHA-256 of `bytes`.
v1::ArtifactRef MakeArtifactRef(std::string name, std::string_view bytes);

// Sender side of an upload: the header, then the chunks, then WritesDone.
void WriteUpload(grpc::ClientWriterInterface<v1::UploadArtifactRequest>& writer,
                 const v1::UploadArtifactRequest::Header& header, std::string_view bytes);

// Receiver side of a download: each message's bytes handed on as they arrive,
// hashed and counted against the first message's size and SHA-256, which Finish
// (after the stream's Finish succeeded) checks against the hash asked for. More
// bytes than announced end it at once. A damaged transfer, or a server that sent
// another artifact, is Error(kInternal): worth a retry, unlike bad input.
class DownloadReceiver {
 public:
  DownloadReceiver(std::string sha256, std::function<void(std::string_view)> consume);
  void Receive(const v1::ArtifactChunk& message);
  void Finish();

 private:
  const std::string sha256_;
  const std::function<void(std::string_view)> consume_;
  v1::ArtifactRef announced_;
  bool first_ = true;
  uint64_t bytes_ = 0;
  Sha256 hasher_;
};

// Server side of a download: the bytes as they are read, in kChunkBytes messages,
// the first carrying `artifact`. Send throws Error(kUnavailable) once the client
// has gone away; Finish after the last piece.
class ArtifactSender {
 public:
  ArtifactSender(grpc::ServerWriterInterface<v1::ArtifactChunk>& writer, const v1::ArtifactRef& artifact);
  void Send(std::string_view bytes);
  void Finish();

 private:
  void Write(std::string_view chunk);
  grpc::ServerWriterInterface<v1::ArtifactChunk>& writer_;
  v1::ArtifactChunk message_;
  bool first_ = true;
};

// Uploads `bytes` through `stub` (LoomService or WorkerService).
template <typename Stub>
v1::ArtifactRef UploadArtifact(Stub& stub, const v1::UploadArtifactRequest::Header& header, std::string_view bytes) {
  grpc::ClientContext context;
  v1::UploadArtifactResponse response;
  const auto writer = stub.UploadArtifact(&context, &response);
  WriteUpload(*writer, header, bytes);
  ThrowIfFailed(writer->Finish(), "UploadArtifact " + header.artifact().name());
  return response.artifact();
}

// Downloads the artifact with this hash through `stub`, handing its bytes to
// `consume` as they arrive; verified at the end (act on the bytes only once it
// returned).
template <typename Stub>
void DownloadArtifactInPieces(Stub& stub, const std::string& sha256,
                              const std::function<void(std::string_view)>& consume) {
  grpc::ClientContext context;
  v1::DownloadArtifactRequest request;
  request.set_sha256(sha256);
  const auto reader = stub.DownloadArtifact(&context, request);
  DownloadReceiver receiver(sha256, consume);
  v1::ArtifactChunk message;
  try {
    while (reader->Read(&message)) receiver.Receive(message);
  } catch (...) {
    context.TryCancel();
    reader->Finish();
    throw;
  }
  ThrowIfFailed(reader->Finish(), "DownloadArtifact " + sha256);
  receiver.Finish();
}

// The whole artifact in memory, verified.
template <typename Stub>
std::string DownloadArtifact(Stub& stub, const std::string& sha256) {
  std::string bytes;
  DownloadArtifactInPieces(stub, sha256, [&bytes](std::string_view piece) { bytes.append(piece); });
  return bytes;
}

}  // namespace loom::rpc
