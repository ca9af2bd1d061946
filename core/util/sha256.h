#pragma once
// SHA-256 content hashes (fabric cache keys, artifact checksums), as lowercase hex.

#include <memory>
#include <string>
#include <string_view>

struct evp_md_ctx_st;  // OpenSSL's EVP_MD_CTX, kept out of this header

namespace loom {

std::string Sha256Hex(std::string_view bytes);

// Incremental form, for data that arrives in pieces (streamed artifact uploads):
// Update any number of times, then FinishHex once.
class Sha256 {
 public:
  Sha256();
  void Update(std::string_view bytes);
  std::string FinishHex();

 private:
  struct FreeContext {
    void operator()(evp_md_ctx_st* context) const;
  };
  std::unique_ptr<evp_md_ctx_st, FreeContext> context_;
};

}  // namespace loom
