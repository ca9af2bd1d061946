#include "server/http_gateway.h"

#include <google/protobuf/util/json_util.h>
#include <httplib.h>
#include <spdlog/spdlog.h>

#include <nlohmann/json.hpp>

#include <functional>
#include <map>
#include <string_view>

#include "core/util/error.h"
#include "loom/v1/service.grpc.pb.h"
#include "rpc/auth.h"
#include "rpc/channel.h"
#include "rpc/status.h"
#include "server/http_serving.h"

namespace loom::server {
namespace {

using Stub = v1::LoomService::Stub;
// A call's request body (JSON) in, its reply (JSON) out.
using Call = std::function<grpc::Status(Stub&, grpc::ClientContext&, const std::string& body, std::string* reply)>;

constexpr char kTokenCookie[] = "loom_token";
constexpr auto kCallTimeout = std::chrono::seconds(30);
// Request bodies are small JSON messages (a list of job ids at most).
constexpr size_t kMaxBodyBytes = 1 << 20;
// Browsers keep a few connections open per page, each holding a thread while it
// idles: threads enough for tens of pages, idle connections closed soon.
constexpr size_t kThreads = 64;
constexpr time_t kKeepAliveSeconds = 2;

template <typename Request, typename Response>
Call Unary(grpc::Status (Stub::*method)(grpc::ClientContext*, const Request&, Response*)) {
  return [method](Stub& stub, grpc::ClientContext& context, const std::string& body, std::string* reply) {
    Request request;
    if (!body.empty()) {
      google::protobuf::util::JsonParseOptions parse;
      const auto parsed = google::protobuf::util::JsonStringToMessage(body, &request, parse);
      if (!parsed.ok()) {
        return grpc::Status(grpc::StatusCode::INVALID_ARGUMENT,
                            "request body: not a " + Request::descriptor()->full_name() + ": " +
                                std::string(parsed.message()));
      }
    }
    Response response;
    const grpc::Status status = (stub.*method)(&context, request, &response);
    if (status.ok()) {
      google::protobuf::util::JsonPrintOptions print;
      print.always_print_primitive_fields = true;
      google::protobuf::util::MessageToJsonString(response, reply, print);
    }
    return status;
  };
}

// What the dashboard may call: LoomService without submission and uploads (the
// CLI's business).
std::map<std::string, Call, std::less<>> Calls() {
  return {
      {"GetServerInfo", Unary(&Stub::GetServerInfo)}, {"ListWorkers", Unary(&Stub::ListWorkers)},
      {"ListJobs", Unary(&Stub::ListJobs)},           {"GetJob", Unary(&Stub::GetJob)},
      {"GetJobLog", Unary(&Stub::GetJobLog)},         {"CancelJob", Unary(&Stub::CancelJob)},
      {"SetJobPriority", Unary(&Stub::SetJobPriority)}, {"RetryJobs", Unary(&Stub::RetryJobs)},
      {"DeleteJobs", Unary(&Stub::DeleteJobs)},       {"ListFabrics", Unary(&Stub::ListFabrics)},
      {"GetFabric", Unary(&Stub::GetFabric)},         {"PinFabric", Unary(&Stub::PinFabric)},
      {"DeleteFabric", Unary(&Stub::DeleteFabric)},
  };
}

int HttpStatus(grpc::StatusCode code) {
  switch (code) {
    case grpc::StatusCode::OK: return 200;
    case grpc::StatusCode::INVALID_ARGUMENT:
    case grpc::StatusCode::OUT_OF_RANGE: return 400;
    case grpc::StatusCode::UNAUTHENTICATED: return 401;
    case grpc::StatusCode::PERMISSION_DENIED: return 403;
    case grpc::StatusCode::NOT_FOUND: return 404;
    case grpc::StatusCode::FAILED_PRECONDITION:
    case grpc::StatusCode::ALREADY_EXISTS:
    case grpc::StatusCode::ABORTED: return 409;
    case grpc::StatusCode::RESOURCE_EXHAUSTED: return 429;
    case grpc::StatusCode::UNAVAILABLE: return 503;
    case grpc::StatusCode::DEADLINE_EXCEEDED: return 504;
    default: return 500;
  }
}

// The codes the dashboard names; any other reads INTERNAL.
std::string CodeName(grpc::StatusCode code) {
  switch (code) {
    case grpc::StatusCode::INVALID_ARGUMENT:
    case grpc::StatusCode::UNAUTHENTICATED:
    case grpc::StatusCode::NOT_FOUND:
    case grpc::StatusCode::FAILED_PRECONDITION:
    case grpc::StatusCode::UNAVAILABLE:
    case grpc::StatusCode::DEADLINE_EXCEEDED:
    case grpc::StatusCode::RESOURCE_EXHAUSTED:
    case grpc::StatusCode::OUT_OF_RANGE: return std::string(rpc::StatusCodeName(code));
    default: return "INTERNAL";
  }
}

void SendError(httplib::Response& res, int http_status, const std::string& code, const std::string& message) {
  nlohmann::json body = {{"code", code}, {"message", message}};
  res.status = http_status;
  res.set_content(body.dump(), "application/json");
}

void SendStatus(httplib::Response& res, const grpc::Status& status) {
  SendError(res, HttpStatus(status.error_code()), CodeName(status.error_code()), status.error_message());
}

// The bearer token of "Authorization: Bearer <token>", else the login cookie's.
std::string CallerToken(const httplib::Request& req) {
  constexpr std::string_view kBearer = "Bearer ";
  const std::string authorization = req.get_header_value("Authorization");
  if (authorization.starts_with(kBearer)) return authorization.substr(kBearer.size());
  const std::string cookies = req.get_header_value("Cookie");
  for (size_t at = 0; at < cookies.size();) {
    size_t end = cookies.find(';', at);
    if (end == std::string::npos) end = cookies.size();
    std::string_view pair(cookies.data() + at, end - at);
    while (pair.starts_with(' ')) pair.remove_prefix(1);
    const size_t equals = pair.find('=');
    if (equals != std::string_view::npos && pair.substr(0, equals) == kTokenCookie) {
      return std::string(pair.substr(equals + 1));
    }
    at = end + 1;
  }
  return {};
}

void PrepareContext(grpc::ClientContext& context, const std::string& token) {
  if (!token.empty()) context.AddMetadata(rpc::kAuthorizationKey, rpc::BearerHeader(token));
  context.set_deadline(rpc::DeadlineIn(kCallTimeout));
}

// A cookie value may hold neither separators nor whitespace (RFC 6265 cookie-octet).
bool IsCookieValue(std::string_view value) {
  for (const char c : value) {
    if (c <= 0x20 || c >= 0x7f || c == '"' || c == ',' || c == ';' || c == '\\') return false;
  }
  return !value.empty();
}

// The content type of an artifact by its first bytes: what a job's frames are.
std::string GuessContentType(std::string_view bytes) {
  if (bytes.starts_with("\x89PNG")) return "image/png";
  if (bytes.starts_with("v/1\x01")) return "image/x-exr";
  if (bytes.starts_with("glTF")) return "model/gltf-binary";
  if (bytes.starts_with("{")) return "application/json";
  return "application/octet-stream";
}

bool IsJsonRequest(const httplib::Request& req) {
  return req.get_header_value("Content-Type").starts_with("application/json");
}

}  // namespace

struct HttpGateway::Routes {
  std::unique_ptr<Stub> stub;
  std::map<std::string, Call, std::less<>> calls = Calls();
  bool secure = false;

  void Api(const httplib::Request& req, httplib::Response& res) const {
    const auto call = calls.find(req.matches[1].str());
    if (call == calls.end()) {
      SendError(res, 404, "NOT_FOUND", "no call " + req.matches[1].str() + " in /api/v1");
      return;
    }
    if (!IsJsonRequest(req)) {
      SendError(res, 415, "INVALID_ARGUMENT", "Content-Type: must be application/json");
      return;
    }
    grpc::ClientContext context;
    PrepareContext(context, CallerToken(req));
    std::string reply;
    const grpc::Status status = call->second(*stub, context, req.body, &reply);
    if (!status.ok()) return SendStatus(res, status);
    res.set_content(reply, "application/json");
  }

  void Login(const httplib::Request& req, httplib::Response& res) const {
    if (!IsJsonRequest(req)) return SendError(res, 415, "INVALID_ARGUMENT", "Content-Type: must be application/json");
    const nlohmann::json body = nlohmann::json::parse(req.body, nullptr, false);
    if (!body.is_object() || !body.contains("token") || !body["token"].is_string()) {
      return SendError(res, 400, "INVALID_ARGUMENT", "token: a string is required");
    }
    const std::string token = body["token"];
    if (!IsCookieValue(token)) {
      return SendError(res, 400, "INVALID_ARGUMENT",
                       "token: holds characters a cookie cannot carry (send it as Authorization: Bearer)");
    }
    grpc::ClientContext context;
    PrepareContext(context, token);
    v1::ServerInfo info;
    const grpc::Status status = stub->GetServerInfo(&context, v1::GetServerInfoRequest(), &info);
    if (!status.ok()) return SendStatus(res, status);
    res.set_header("Set-Cookie", std::string(kTokenCookie) + "=" + token + "; Path=/; HttpOnly; SameSite=Strict" +
                                     (secure ? "; Secure" : ""));
    res.set_content("{}", "application/json");
  }

  void Artifact(const httplib::Request& req, httplib::Response& res) const {
    grpc::ClientContext context;
    PrepareContext(context, CallerToken(req));
    v1::DownloadArtifactRequest request;
    request.set_sha256(req.matches[1].str());
    std::unique_ptr<grpc::ClientReader<v1::ArtifactChunk>> reader = stub->DownloadArtifact(&context, request);
    std::string bytes;
    v1::ArtifactChunk chunk;
    while (reader->Read(&chunk)) bytes += chunk.chunk();
    const grpc::Status status = reader->Finish();
    if (!status.ok()) return SendStatus(res, status);
    // Content-addressed: a hash always names the same bytes.
    res.set_header("Cache-Control", "private, max-age=31536000, immutable");
    const std::string type = GuessContentType(bytes);
    res.set_content(std::move(bytes), type);
  }
};

HttpGateway::HttpGateway(HttpOptions options, std::shared_ptr<grpc::Channel> channel)
    : routes_(std::make_unique<Routes>()) {
  if (!std::filesystem::is_regular_file(options.web_root / "index.html")) {
    throw Error(ErrorCode::kInvalidArgument, "--web-root " + options.web_root.string() +
                                                 ": no index.html (build the dashboard: scripts/setup.sh)");
  }
  const HostPort address = ParseHostPort("--http", options.listen);

  routes_->stub = v1::LoomService::NewStub(std::move(channel));
  routes_->secure = !options.tls_cert_file.empty();
  if (routes_->secure) {
    server_ = std::make_unique<httplib::SSLServer>(options.tls_cert_file.c_str(), options.tls_key_file.c_str());
  } else {
    server_ = std::make_unique<httplib::Server>();
  }
  httplib::Server& server = *server_;
  if (!server.is_valid()) {
    throw Error(ErrorCode::kInvalidArgument, "--tls-cert " + options.tls_cert_file + ", --tls-key " +
                                                 options.tls_key_file + ": not a PEM certificate and its key");
  }
  server.set_payload_max_length(kMaxBodyBytes);
  server.new_task_queue = [] { return new httplib::ThreadPool(kThreads); };
  server.set_keep_alive_timeout(kKeepAliveSeconds);
  server.set_default_headers({{"X-Content-Type-Options", "nosniff"},
                              {"X-Frame-Options", "DENY"},
                              {"Content-Security-Policy", "default-src 'self'; img-src 'self' data:"}});
  Routes& routes = *routes_;
  using Request = const httplib::Request&;
  using Response = httplib::Response&;
  server.Post("/api/v1/login", [&routes](Request req, Response res) { routes.Login(req, res); });
  server.Post("/api/v1/logout", [secure = routes_->secure](Request, Response res) {
    res.set_header("Set-Cookie", std::string(kTokenCookie) + "=; Path=/; HttpOnly; SameSite=Strict; Max-Age=0" +
                                     (secure ? "; Secure" : ""));
    res.set_content("{}", "application/json");
  });
  server.Post(R"(/api/v1/(\w+))", [&routes](Request req, Response res) { routes.Api(req, res); });
  server.Get(R"(/api/v1/artifacts/([0-9a-f]{64}))",
             [&routes](Request req, Response res) { routes.Artifact(req, res); });
  server.set_exception_handler([](Request req, Response res, std::exception_ptr error) {
    const std::string what = ExceptionText(error);
    spdlog::error("http {} {}: internal error: {}", req.method, req.path, what);
    SendError(res, 500, "INTERNAL", "internal error: " + what);
  });
  if (!server.set_mount_point("/", options.web_root.string())) {
    throw Error(ErrorCode::kInvalidArgument, "--web-root " + options.web_root.string() + ": not a directory");
  }
  serving_ = std::make_unique<HttpServing>(server, "--http", address);
  spdlog::info("dashboard on http{}://{}:{}/ (files from {})", routes_->secure ? "s" : "", address.host, port(),
               options.web_root.string());
}

HttpGateway::~HttpGateway() { Stop(); }

void HttpGateway::Stop() { serving_->Stop(); }

int HttpGateway::port() const { return serving_->port(); }

}  // namespace loom::server
