// The dashboard's HTTP side (server/http_gateway.h) against a real server: no token,
// no data; its calls are the gRPC service's (what one does the other sees); bad
// requests are refused naming the field and lose nothing; frames are served with
// their type; HTTPS with the server's certificate. And the worker registry the
// workers page shows, on a fake clock.

#include <nlohmann/json.hpp>

#include "core/util/error.h"
#include "core/util/file_io.h"
#include "server/service_state.h"
#include "tests/server/self_signed_certificate.h"
#include "tests/server/service_fixture.h"

// Last: it includes <resolv.h>, whose _res macro breaks Eigen's headers.
#include <httplib.h>

namespace loom::server {
namespace {

constexpr char kClientToken[] = "gateway-client-token";
constexpr char kJson[] = "application/json";

class HttpGatewayTest : public ServiceTest {
 protected:
  void SetUp() override {
    files_ = std::filesystem::temp_directory_path() / ("loom-http-test-" + std::to_string(::getpid()));
    std::filesystem::create_directories(files_ / "web");
    WriteFileAtomic(files_ / "web" / "index.html", "<!doctype html><title>Loom</title>");
  }
  void TearDown() override {
    ServiceTest::TearDown();
    std::filesystem::remove_all(files_);
  }

  void Start(int local_workers, bool tls = false) {
    ServerOptions options;
    options.local_workers = local_workers;
    options.client_token = kClientToken;
    options.worker_token = "gateway-worker-token";
    options.http_listen = "127.0.0.1:0";
    options.web_root = files_ / "web";
    options.local_worker.gl.software_only = true;
    if (tls) {
      const PemCertificate certificate = MakeSelfSignedCertificate("loom-gateway-test");
      WriteFileAtomic(files_ / "server.pem", certificate.certificate_pem);
      WriteFileAtomic(files_ / "server.key", certificate.private_key_pem);
      options.tls_cert_file = (files_ / "server.pem").string();
      options.tls_key_file = (files_ / "server.key").string();
    }
    StartServer(options);
    ASSERT_GT(server_->http_port(), 0);
  }

  httplib::Client Http() const { return httplib::Client("127.0.0.1", server_->http_port()); }

  // POST /api/v1/<call> with `body` and the token as a bearer header ("" none).
  httplib::Result Call(const std::string& call, const std::string& body, const std::string& token = kClientToken) {
    httplib::Headers headers;
    if (!token.empty()) headers.emplace("Authorization", "Bearer " + token);
    return Http().Post(("/api/v1/" + call).c_str(), headers, body, kJson);
  }

  std::filesystem::path files_;
};

nlohmann::json Json(const httplib::Result& result) { return nlohmann::json::parse(result->body); }

TEST_F(HttpGatewayTest, WithoutTheTokenNothingIsShown) {
  Start(0);
  Client(kClientToken).Submit(PrecomputeRequest());

  for (const char* call : {"ListJobs", "GetJob", "ListFabrics", "ListWorkers", "GetServerInfo", "GetJobLog"}) {
    for (const std::string& token : {std::string(), std::string("wrong-token")}) {
      const httplib::Result result = Call(call, "{}", token);
      ASSERT_TRUE(result) << call;
      EXPECT_EQ(result->status, 401) << call << " with token '" << token << "'";
      EXPECT_EQ(Json(result)["code"], "UNAUTHENTICATED");
      EXPECT_EQ(result->body.find("job-1"), std::string::npos);
    }
  }
  httplib::Client http = Http();
  EXPECT_EQ(http.Get(("/api/v1/artifacts/" + std::string(64, '0')).c_str())->status, 401);
  // The page itself holds no data and loads for the login.
  const httplib::Result page = http.Get("/");
  ASSERT_TRUE(page);
  EXPECT_EQ(page->status, 200);
  EXPECT_NE(page->body.find("<title>Loom</title>"), std::string::npos);

  // A wrong token is refused at the login and sets no cookie.
  const httplib::Result refused = http.Post("/api/v1/login", R"({"token": "wrong-token"})", kJson);
  EXPECT_EQ(refused->status, 401);
  EXPECT_FALSE(refused->has_header("Set-Cookie"));
  const httplib::Result login = http.Post("/api/v1/login", std::string(R"({"token": ")") + kClientToken + "\"}", kJson);
  ASSERT_EQ(login->status, 200) << login->body;
  const std::string cookie = login->get_header_value("Set-Cookie");
  EXPECT_NE(cookie.find("HttpOnly"), std::string::npos) << cookie;
  EXPECT_NE(cookie.find("SameSite=Strict"), std::string::npos) << cookie;
  EXPECT_EQ(cookie.find("Secure"), std::string::npos) << cookie;  // plain HTTP
  const httplib::Result jobs =
      http.Post("/api/v1/ListJobs", {{"Cookie", "theme=dark; " + cookie.substr(0, cookie.find(';'))}}, "{}", kJson);
  ASSERT_EQ(jobs->status, 200) << jobs->body;
  EXPECT_EQ(Json(jobs)["jobs"][0]["id"], "job-1");
  EXPECT_EQ(Json(jobs)["jobs"][0]["state"], "JOB_STATE_QUEUED");
}

TEST_F(HttpGatewayTest, ItsCallsAreTheServicesOwn) {
  Start(0);
  client::JobClient client = Client(kClientToken);
  v1::SubmitJobRequest named = PrecomputeRequest();
  named.mutable_precompute()->mutable_fabric()->set_name("gateway knit");
  const std::string id = client.Submit(named).job().id();

  // A summary list leaves the specs out and keeps their names.
  const nlohmann::json summary = Json(Call("ListJobs", R"({"summary": true})"))["jobs"][0];
  EXPECT_EQ(summary["name"], "gateway knit");
  EXPECT_FALSE(summary.contains("precompute"));
  const nlohmann::json whole = Json(Call("ListJobs", "{}"))["jobs"][0];
  EXPECT_EQ(whole["precompute"]["fabric"]["name"], "gateway knit");

  // A poll sends the last list's version: nothing comes back until a job changes.
  const std::string listed = Json(Call("ListJobs", "{}"))["version"];
  const nlohmann::json same = Json(Call("ListJobs", R"({"unlessVersion": ")" + listed + "\"}"));
  EXPECT_TRUE(same["unchanged"].get<bool>());
  EXPECT_TRUE(same["jobs"].empty());
  const httplib::Result priority = Call("SetJobPriority", R"({"jobId": ")" + id + R"(", "priority": 7})");
  const nlohmann::json changed = Json(Call("ListJobs", R"({"unlessVersion": ")" + listed + "\"}"));
  EXPECT_FALSE(changed["unchanged"].get<bool>());
  EXPECT_EQ(changed["jobs"][0]["priority"], 7);
  EXPECT_NE(changed["version"], listed);
  ASSERT_EQ(priority->status, 200) << priority->body;
  EXPECT_EQ(Json(priority)["priority"], 7);
  EXPECT_EQ(client.Get(id).priority(), 7);

  const httplib::Result cancel = Call("CancelJob", R"({"jobId": ")" + id + R"("})");
  ASSERT_EQ(cancel->status, 200) << cancel->body;
  EXPECT_EQ(client.Get(id).state(), v1::JOB_STATE_CANCELLED);
  // The service's own refusal, with its status: a cancelled job's priority is final.
  const httplib::Result late = Call("SetJobPriority", R"({"jobId": ")" + id + R"(", "priority": 1})");
  EXPECT_EQ(late->status, 409) << late->body;
  EXPECT_EQ(Json(late)["code"], "FAILED_PRECONDITION");

  const httplib::Result retry = Call("RetryJobs", R"({"jobIds": [")" + id + R"("]})");
  ASSERT_EQ(retry->status, 200) << retry->body;
  EXPECT_EQ(client.Get(id).state(), v1::JOB_STATE_QUEUED);
  const httplib::Result missing = Call("GetJob", R"({"jobId": "job-99"})");
  EXPECT_EQ(missing->status, 404);
  EXPECT_NE(Json(missing)["message"].get<std::string>().find("job-99"), std::string::npos);
}

TEST_F(HttpGatewayTest, BadRequestsAreRefusedNamingTheFieldAndLoseNothing) {
  Start(0);
  client::JobClient client = Client(kClientToken);
  const std::string id = client.Submit(PrecomputeRequest()).job().id();

  struct Case {
    std::string call, body;
    int status;
    std::string names;
  };
  const std::vector<Case> cases = {
      {"ListJobs", "{not json", 400, "request body"},
      {"ListJobs", R"({"pageSize": "many"})", 400, "page_size"},
      {"ListJobs", R"({"pageSize": 10, "colour": 1})", 400, "colour"},
      {"ListJobs", R"({"states": ["JOB_STATE_SOMETIMES"]})", 400, "states"},
      {"SetJobPriority", R"({"jobId": ")" + id + R"(", "priority": 3000000000})", 400, "priority"},  // past int32
      {"SubmitJob", "{}", 404, "SubmitJob"},  // submission is the CLI's
      {"DeleteFabric", R"({"fabricKey": "zz"})", 400, "fabric_key"},
  };
  for (const Case& c : cases) {
    const httplib::Result result = Call(c.call, c.body);
    ASSERT_TRUE(result) << c.body;
    EXPECT_EQ(result->status, c.status) << c.call << " " << c.body << ": " << result->body;
    EXPECT_NE(Json(result)["message"].get<std::string>().find(c.names), std::string::npos)
        << c.call << " " << c.body << ": " << result->body;
  }
  httplib::Client http = Http();
  const httplib::Headers auth = {{"Authorization", std::string("Bearer ") + kClientToken}};
  const httplib::Result form = http.Post("/api/v1/CancelJob", auth, "jobId=" + id, "application/x-www-form-urlencoded");
  EXPECT_EQ(form->status, 415);
  EXPECT_NE(Json(form)["message"].get<std::string>().find("Content-Type"), std::string::npos);
  const httplib::Result huge = Call("ListJobs", R"({"pageToken": ")" + std::string(2 << 20, 'a') + "\"}");
  ASSERT_TRUE(huge);
  EXPECT_EQ(huge->status, 413);

  const v1::Job after = client.Get(id);
  EXPECT_EQ(after.state(), v1::JOB_STATE_QUEUED);
  EXPECT_EQ(after.priority(), 0);  // nothing the refused calls asked for happened
  EXPECT_EQ(JobCount(client), 1);
}

TEST_F(HttpGatewayTest, AFramesArtifactIsServedAsThePngItIs) {
  Start(1);
  client::JobClient client = Client(kClientToken);
  v1::SceneSpec scene = TinyScene(40, 24);
  scene.mutable_render()->set_format(v1::IMAGE_FORMAT_PNG);
  const std::string id = client.Submit(RenderRequest(scene)).job().id();
  const v1::Job done = client.Watch(id, [](const v1::JobEvent&) {});
  ASSERT_EQ(done.state(), v1::JOB_STATE_SUCCEEDED) << done.error();
  ASSERT_EQ(done.result_artifacts_size(), 1);

  httplib::Client http = Http();
  const httplib::Headers auth = {{"Authorization", std::string("Bearer ") + kClientToken}};
  const httplib::Result frame = http.Get(("/api/v1/artifacts/" + done.result_artifacts(0)).c_str(), auth);
  ASSERT_EQ(frame->status, 200);
  EXPECT_EQ(frame->get_header_value("Content-Type"), "image/png");
  EXPECT_EQ(frame->body, client.Download(done.result_artifacts(0)));
  const Image image = ReadImageBytes(frame->body, ".png");
  EXPECT_EQ(image.width, 40);
  EXPECT_EQ(image.height, 24);
  EXPECT_EQ(http.Get(("/api/v1/artifacts/" + std::string(64, 'a')).c_str(), auth)->status, 404);

  // The workers page's call: the local worker ran both jobs (the precompute the render waited for).
  const httplib::Result workers = Call("ListWorkers", "{}");
  ASSERT_EQ(workers->status, 200);
  const nlohmann::json worker = Json(workers)["workers"][0];
  EXPECT_EQ(worker["jobsSucceeded"], 2);
  EXPECT_EQ(worker["jobsFailed"], 0);
  EXPECT_TRUE(worker["capabilities"]["softwareGl"].get<bool>());
}

TEST_F(HttpGatewayTest, WithTheServersCertificateItServesHttpsOnly) {
  Start(0, true);
  httplib::SSLClient https("127.0.0.1", server_->http_port());
  https.set_ca_cert_path((files_ / "server.pem").c_str());
  https.enable_server_certificate_verification(true);
  const std::string body = std::string(R"({"token": ")") + kClientToken + "\"}";
  const httplib::Result login = https.Post("/api/v1/login", body, kJson);
  ASSERT_TRUE(login) << httplib::to_string(login.error());
  EXPECT_EQ(login->status, 200);
  EXPECT_NE(login->get_header_value("Set-Cookie").find("; Secure"), std::string::npos);
  // Plain HTTP gets no answer.
  EXPECT_FALSE(Http().Get("/"));
}

TEST_F(HttpGatewayTest, BadDashboardOptionsAreRefusedNamingTheFlag) {
  const auto refusal = [&](ServerOptions options) -> std::string {
    options.local_workers = 0;
    try {
      StartServer(options);
    } catch (const Error& error) {
      EXPECT_EQ(error.code(), ErrorCode::kInvalidArgument);
      return error.what();
    }
    return "started";
  };
  ServerOptions open;
  open.http_listen = "0.0.0.0:0";
  open.web_root = files_ / "web";
  EXPECT_NE(refusal(open).find("--http 0.0.0.0:0: without token files"), std::string::npos);
  ServerOptions no_port = open;
  no_port.http_listen = "127.0.0.1";
  EXPECT_NE(refusal(no_port).find("--http 127.0.0.1: not host:port"), std::string::npos);
  ServerOptions empty_root = open;
  empty_root.http_listen = "127.0.0.1:0";
  empty_root.web_root = files_;
  EXPECT_NE(refusal(empty_root).find("--web-root " + files_.string() + ": no index.html"), std::string::npos);
}

TEST(WorkerRegistry, AWorkersStateFollowsItsCalls) {
  FakeClock clock;
  WorkerRegistry registry(clock);
  v1::WorkerCapabilities capabilities;
  capabilities.set_gl_renderer("llvmpipe");
  const std::string first = registry.Register(capabilities);
  clock.Advance(10);
  const std::string second = registry.Register(capabilities);
  constexpr int64_t kLiveMs = 3000;

  registry.Seen(first, "job-1");
  std::vector<v1::WorkerInfo> list = registry.List(kLiveMs);
  ASSERT_EQ(list.size(), 2u);
  EXPECT_EQ(list[0].worker_id(), second);  // the newest first
  EXPECT_EQ(list[0].state(), "idle");
  EXPECT_EQ(list[1].state(), "busy");
  EXPECT_EQ(list[1].current_job_id(), "job-1");
  EXPECT_EQ(list[1].capabilities().gl_renderer(), "llvmpipe");

  clock.Advance(kLiveMs);
  registry.Ended(first, true);
  list = registry.List(kLiveMs);
  EXPECT_EQ(list[1].state(), "idle");
  EXPECT_EQ(list[1].current_job_id(), "");
  EXPECT_EQ(list[1].jobs_succeeded(), 1u);
  EXPECT_EQ(list[0].state(), "idle");  // heard from exactly kLiveMs ago
  clock.Advance(1);
  registry.Ended(first, false);
  list = registry.List(kLiveMs);
  EXPECT_EQ(list[0].state(), "lost");
  EXPECT_EQ(list[1].jobs_failed(), 1u);
  EXPECT_EQ(list[1].last_seen_ms(), clock.NowMs());
  registry.Seen("w-unknown", "job-2");  // ignored
  EXPECT_EQ(registry.List(kLiveMs).size(), 2u);
}

}  // namespace
}  // namespace loom::server
