// loom-server with --tls-cert/--tls-key: only a client that trusts the server's
// certificate gets through; plaintext and a client trusting another CA cannot
// connect (UNAVAILABLE). Certificates are made at test time.

#include <gtest/gtest.h>

#include <optional>

#include "core/util/error.h"
#include "core/util/file_io.h"
#include "rpc/channel.h"
#include "tests/server/self_signed_certificate.h"
#include "tests/server/service_fixture.h"

namespace loom::server {
namespace {

class TlsTest : public ServiceTest {
 protected:
  void SetUp() override {
    keys_ = std::filesystem::temp_directory_path() / ("loom-tls-test-" + std::to_string(::getpid()));
    std::filesystem::create_directories(keys_);
    const PemCertificate server = MakeSelfSignedCertificate("loom-test-server");
    WriteFileAtomic(keys_ / "server.pem", server.certificate_pem);
    WriteFileAtomic(keys_ / "server.key", server.private_key_pem);
    WriteFileAtomic(keys_ / "other-ca.pem", MakeSelfSignedCertificate("some-other-ca").certificate_pem);
  }
  void TearDown() override {
    ServiceTest::TearDown();
    std::filesystem::remove_all(keys_);
  }

  // GetServerInfo over a channel trusting `ca_file` (empty: plaintext); the error
  // code of the call, nullopt when it succeeded.
  std::optional<ErrorCode> CallWithCa(const std::filesystem::path& ca_file) {
    rpc::ChannelOptions channel;
    channel.address = server_->address();
    channel.tls_ca_file = ca_file.string();
    try {
      const v1::ServerInfo info = client::JobClient(rpc::MakeChannel(channel)).ServerInfo();
      EXPECT_TRUE(info.tls());
      return std::nullopt;
    } catch (const Error& error) {
      return error.code();
    }
  }

  std::filesystem::path keys_;
};

TEST_F(TlsTest, OnlyAClientTrustingTheServersCertificateConnects) {
  ServerOptions options;
  options.local_workers = 0;
  options.tls_cert_file = (keys_ / "server.pem").string();
  options.tls_key_file = (keys_ / "server.key").string();
  StartServer(options);

  EXPECT_EQ(CallWithCa(keys_ / "server.pem"), std::nullopt);
  EXPECT_EQ(CallWithCa(""), ErrorCode::kUnavailable);  // plaintext
  EXPECT_EQ(CallWithCa(keys_ / "other-ca.pem"), ErrorCode::kUnavailable);
}

}  // namespace
}  // namespace loom::server
