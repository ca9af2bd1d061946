// GET /metrics (server/metrics_endpoint.h) on a real server: its calls and its
// queue as Prometheus reads them, nothing but /metrics served, bad addresses refused
// naming the flag.

#include <gmock/gmock.h>

#include "core/util/error.h"
#include "tests/server/metrics_samples.h"
#include "tests/server/service_fixture.h"

// Last: it includes <resolv.h>, whose _res macro breaks Eigen's headers.
#include <httplib.h>

namespace loom::server {
namespace {

class MetricsEndpointTest : public ServiceTest {
 protected:
  void Start() {
    ServerOptions options;
    options.local_workers = 0;
    options.client_token = "metrics-client-token";
    options.worker_token = "metrics-worker-token";
    options.metrics_listen = "127.0.0.1:0";
    StartServer(options);
    ASSERT_GT(server_->metrics_port(), 0);
  }

  std::string Scrape() {
    httplib::Client http("127.0.0.1", server_->metrics_port());
    const httplib::Result result = http.Get("/metrics");
    if (!result || result->status != 200) {
      ADD_FAILURE() << "GET /metrics: " << (result ? std::to_string(result->status) : "no answer");
      return "";
    }
    EXPECT_EQ(result->get_header_value("Content-Type"), "text/plain; version=0.0.4; charset=utf-8");
    return result->body;
  }
};

TEST_F(MetricsEndpointTest, ServesTheCallsAndTheQueueWithoutAToken) {
  Start();
  // Two refused calls and one that succeeds.
  for (const char* token : {"", "wrong"}) {
    v1::ServerInfo info;
    grpc::ClientContext context;
    EXPECT_EQ(RawStub(*server_, token)->GetServerInfo(&context, {}, &info).error_code(),
              grpc::StatusCode::UNAUTHENTICATED);
  }
  client::JobClient client = Client("metrics-client-token");
  client.ServerInfo();
  const v1::Job job = client.Submit(RenderRequest(TinyScene())).job();

  const std::string text = Scrape();
  EXPECT_EQ(Sample(text, R"(loom_rpc_duration_seconds_count{code="UNAUTHENTICATED",method="GetServerInfo",)"
                         R"(service="LoomService"})"),
            2);
  EXPECT_EQ(Sample(text, R"(loom_rpc_duration_seconds_count{code="OK",method="GetServerInfo",service="LoomService"})"),
            1);
  EXPECT_EQ(Sample(text, R"(loom_rpc_duration_seconds_count{code="OK",method="SubmitJob",service="LoomService"})"), 1);
  // The render waits for its fabric's precompute: two jobs queued, one ready.
  EXPECT_EQ(Sample(text, R"(loom_jobs{kind="render",state="queued"})"), 1);
  EXPECT_EQ(Sample(text, R"(loom_jobs{kind="precompute",state="queued"})"), 1);
  EXPECT_EQ(Sample(text, R"(loom_jobs_ready{kind="precompute"})"), 1);
  EXPECT_EQ(Sample(text, R"(loom_jobs_ready{kind="render"})"), 0);
  EXPECT_EQ(PromtoolProblems(text), "");
  EXPECT_FALSE(job.id().empty());

  // Nothing else is served there.
  httplib::Client http("127.0.0.1", server_->metrics_port());
  EXPECT_EQ(http.Get("/")->status, 404);
  EXPECT_EQ(http.Get("/api/v1/ListJobs")->status, 404);
  EXPECT_EQ(http.Post("/metrics", "", "text/plain")->status, 404);
}

TEST_F(MetricsEndpointTest, ABadAddressIsRefusedNamingTheFlag) {
  ServerOptions options;
  options.local_workers = 0;
  options.metrics_listen = "localhost";
  try {
    StartServer(options);
    FAIL() << "a server started with --metrics localhost";
  } catch (const Error& error) {
    EXPECT_EQ(error.code(), ErrorCode::kInvalidArgument);
    EXPECT_STREQ(error.what(), "--metrics localhost: not host:port");
  }
  Start();
  options.data_dir = data_dir_.string() + "-second";
  options.listen = "127.0.0.1:0";
  options.metrics_listen = "127.0.0.1:" + std::to_string(server_->metrics_port());
  try {
    LoomServer second(options);
    FAIL() << "a second server took the metrics port in use";
  } catch (const Error& error) {
    EXPECT_EQ(error.code(), ErrorCode::kUnavailable);
    EXPECT_THAT(error.what(), ::testing::HasSubstr("--metrics " + options.metrics_listen + ": cannot listen"));
  }
}

}  // namespace
}  // namespace loom::server
