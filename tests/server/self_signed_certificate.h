#pragma once
// A TLS certificate and key made at test time (OpenSSL), so that no key is
// committed and none expires: a self-signed P-256 certificate for "localhost" and
// 127.0.0.1, valid from an hour ago for a day, usable as its own CA.

#include <string>

namespace loom::server {

struct PemCertificate {
  std::string certificate_pem;
  std::string private_key_pem;
};

// `common_name` tells two certificates apart in handshake errors.
PemCertificate MakeSelfSignedCertificate(const std::string& common_name);

}  // namespace loom::server
