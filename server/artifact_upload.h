#pragma once
// The server's side of UploadArtifact (both services): the header first, checked by
// the caller (a worker's lease, a client's mesh cap), then the chunks streamed
// straight into the artifact store, committed only when size and SHA-256 match the
// header (ArtifactWriter::Commit), so a truncated or corrupted upload stores nothing.

#include <grpcpp/support/sync_stream.h>

#include <cstdint>
#include <functional>

#include "loom/v1/service.pb.h"
#include "server/store/artifact_store.h"

namespace loom::server {

using UploadHeaderCheck = std::function<void(const v1::UploadArtifactRequest::Header& header)>;

// Chunks are at most this (service.proto); the message cap is larger only for specs.
inline constexpr size_t kMaxUploadChunkBytes = size_t{4} << 20;

// Error(kInvalidArgument) when the header is missing or repeated, a chunk exceeds
// kMaxUploadChunkBytes, the size exceeds `max_bytes`, or the bytes differ from the
// header. Returns the stored artifact.
v1::ArtifactRef ReceiveUpload(grpc::ServerReaderInterface<v1::UploadArtifactRequest>& reader,
                              ArtifactStore& artifacts, uint64_t max_bytes, const UploadHeaderCheck& check_header);

}  // namespace loom::server
