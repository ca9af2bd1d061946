#include "server/metrics_endpoint.h"

#include <httplib.h>
#include <spdlog/spdlog.h>

#include <exception>

#include "server/http_serving.h"
#include "server/service_state.h"

namespace loom::server {

MetricsEndpoint::MetricsEndpoint(const std::string& listen, const ServiceState& state)
    : server_(std::make_unique<httplib::Server>()) {
  const HostPort address = ParseHostPort("--metrics", listen);
  server_->new_task_queue = [] { return new httplib::ThreadPool(2); };
  server_->Get("/metrics", [&state](const httplib::Request&, httplib::Response& res) {
    res.set_content(state.metrics.Scrape(state), "text/plain; version=0.0.4; charset=utf-8");
  });
  server_->set_exception_handler([](const httplib::Request&, httplib::Response& res, std::exception_ptr error) {
    const std::string what = ExceptionText(error);
    spdlog::error("metrics: {}", what);
    res.status = 500;
    res.set_content("internal error: " + what + "\n", "text/plain");
  });
  serving_ = std::make_unique<HttpServing>(*server_, "--metrics", address);
  spdlog::info("metrics on http://{}:{}/metrics", address.host, serving_->port());
}

MetricsEndpoint::~MetricsEndpoint() { Stop(); }

int MetricsEndpoint::port() const { return serving_->port(); }

void MetricsEndpoint::Stop() { serving_->Stop(); }

}  // namespace loom::server
