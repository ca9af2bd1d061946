#include "rpc/auth.h"

#include <openssl/crypto.h>

#include "core/util/error.h"
#include "core/util/file_io.h"

namespace loom::rpc {

std::string ReadTokenFile(const std::filesystem::path& path) {
  const std::string text = ReadFile(path);
  const size_t end_of_line = text.find('\n');
  std::string token = text.substr(0, end_of_line);
  const char* blanks = " \t\r";
  token.erase(0, token.find_first_not_of(blanks));
  const size_t last = token.find_last_not_of(blanks);
  token.erase(last == std::string::npos ? 0 : last + 1);
  if (token.empty()) throw Error(ErrorCode::kInvalidArgument, path.string() + ": the token file is empty");
  return token;
}

std::string BearerHeader(std::string_view token) { return "Bearer " + std::string(token); }

bool HasBearerToken(const grpc::ServerContext& context, std::string_view token) {
  const auto& metadata = context.client_metadata();
  const auto found = metadata.find(kAuthorizationKey);
  if (found == metadata.end()) return false;
  const std::string expected = BearerHeader(token);
  const grpc::string_ref& given = found->second;
  return given.size() == expected.size() && CRYPTO_memcmp(given.data(), expected.data(), expected.size()) == 0;
}

}  // namespace loom::rpc
