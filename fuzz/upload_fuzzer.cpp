// The artifact upload stream (server/artifact_upload.h) as UploadArtifact receives
// it: a header, then chunks, into a real artifact store. The input is a sequence of
// messages, each a u16 length and the serialized UploadArtifactRequest. Flags in
// the first byte: bit 0 writes the chunks' true size and SHA-256 into the first
// header (so that an upload can commit, and is then read back and compared), bit 1
// makes the header check refuse (a stale lease).

#include <cstddef>
#include <cstdint>
#include <cstring>
#include <filesystem>
#include <string>
#include <string_view>
#include <unistd.h>
#include <vector>

#include "core/util/error.h"
#include "core/util/sha256.h"
#include "fuzz/quiet_logs.h"
#include "server/artifact_upload.h"

namespace {

class FakeReader final : public grpc::ServerReaderInterface<loom::v1::UploadArtifactRequest> {
 public:
  explicit FakeReader(std::vector<loom::v1::UploadArtifactRequest> messages) : messages_(std::move(messages)) {}
  void SendInitialMetadata() override {}
  bool NextMessageSize(uint32_t* size) override {
    if (next_ == messages_.size()) return false;
    *size = static_cast<uint32_t>(messages_[next_].ByteSizeLong());
    return true;
  }
  bool Read(loom::v1::UploadArtifactRequest* message) override {
    if (next_ == messages_.size()) return false;
    *message = messages_[next_++];
    return true;
  }

 private:
  std::vector<loom::v1::UploadArtifactRequest> messages_;
  size_t next_ = 0;
};

loom::server::ArtifactStore& Store() {
  static loom::server::ArtifactStore store(std::filesystem::temp_directory_path() /
                                           ("loom-upload-fuzzer-" + std::to_string(::getpid())));
  return store;
}

}  // namespace

extern "C" int LLVMFuzzerTestOneInput(const uint8_t* data, size_t size) {
  loom::fuzz::QuietLogs();
  if (size == 0) return 0;
  const uint8_t flags = data[0];
  std::string_view rest(reinterpret_cast<const char*>(data) + 1, size - 1);
  std::vector<loom::v1::UploadArtifactRequest> messages;
  std::string chunks;
  while (rest.size() >= 2) {
    uint16_t length = 0;
    std::memcpy(&length, rest.data(), 2);
    rest.remove_prefix(2);
    const std::string_view bytes = rest.substr(0, std::min<size_t>(length, rest.size()));
    rest.remove_prefix(bytes.size());
    loom::v1::UploadArtifactRequest& message = messages.emplace_back();
    if (!message.ParseFromArray(bytes.data(), static_cast<int>(bytes.size()))) message.Clear();
    if (message.has_chunk()) chunks += message.chunk();
  }
  if ((flags & 1) && !messages.empty() && messages.front().has_header()) {
    loom::v1::ArtifactRef& artifact = *messages.front().mutable_header()->mutable_artifact();
    artifact.set_size(chunks.size());
    artifact.set_sha256(loom::Sha256Hex(chunks));
  }
  FakeReader reader(std::move(messages));
  try {
    const loom::v1::ArtifactRef stored = loom::server::ReceiveUpload(
        reader, Store(), 64 << 10, [flags](const loom::v1::UploadArtifactRequest::Header&) {
          if (flags & 2) throw loom::Error(loom::ErrorCode::kFailedPrecondition, "stale lease");
        });
    // What was committed is exactly what was sent.
    if (Store().Read(stored.sha256()) != chunks) __builtin_trap();
  } catch (const loom::Error&) {
  }
  return 0;
}
