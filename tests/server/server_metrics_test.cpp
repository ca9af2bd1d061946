#include "server/server_metrics.h"

#include <gtest/gtest.h>
#include <yaml-cpp/yaml.h>

#include <nlohmann/json.hpp>

#include <filesystem>
#include <map>
#include <regex>
#include <set>
#include <sstream>
#include <vector>
#include <string>

#include "core/util/file_io.h"
#include "core/version.h"
#include "server/service_state.h"
#include "tests/server/metrics_samples.h"
#include "tests/server/store/store_test_util.h"

namespace loom::server {

namespace {

// A rules file recording each of `expressions`, for `promtool check rules`.
std::string RecordingRules(const std::vector<std::string>& expressions) {
  YAML::Emitter out;
  out << YAML::BeginMap << YAML::Key << "groups" << YAML::Value << YAML::BeginSeq << YAML::BeginMap;
  out << YAML::Key << "name" << YAML::Value << "checked" << YAML::Key << "rules" << YAML::Value << YAML::BeginSeq;
  for (size_t i = 0; i < expressions.size(); ++i) {
    out << YAML::BeginMap << YAML::Key << "record" << YAML::Value << "loom:checked_" + std::to_string(i)
        << YAML::Key << "expr" << YAML::Value << expressions[i] << YAML::EndMap;
  }
  out << YAML::EndSeq << YAML::EndMap << YAML::EndSeq << YAML::EndMap;
  return out.c_str();
}

// A `promtool test rules` file: every sample of `scrape` as `servers` instances
// report it, for two minutes; `expression` must read `expected` after one.
std::string ExpressionTest(const std::string& scrape, int servers, const std::string& expression, double expected) {
  YAML::Emitter out;
  out << YAML::BeginMap << YAML::Key << "rule_files" << YAML::Value << YAML::Flow << YAML::BeginSeq << YAML::EndSeq;
  out << YAML::Key << "tests" << YAML::Value << YAML::BeginSeq << YAML::BeginMap;
  out << YAML::Key << "interval" << YAML::Value << "1m" << YAML::Key << "input_series" << YAML::Value
      << YAML::BeginSeq;
  for (int server = 0; server < servers; ++server) {
    const std::string instance = "instance=\"server-" + std::to_string(server) + ":9464\"";
    for (const auto& [series, value] : Samples(scrape)) {
      const size_t brace = series.find('{');
      const std::string labelled = brace == std::string::npos
                                       ? series + "{" + instance + "}"
                                       : series.substr(0, series.size() - 1) + "," + instance + "}";
      const std::string text = std::to_string(value);
      out << YAML::BeginMap << YAML::Key << "series" << YAML::Value << labelled << YAML::Key << "values"
          << YAML::Value << text + " " + text + " " + text << YAML::EndMap;
    }
  }
  out << YAML::EndSeq << YAML::Key << "promql_expr_test" << YAML::Value << YAML::BeginSeq << YAML::BeginMap;
  out << YAML::Key << "expr" << YAML::Value << expression << YAML::Key << "eval_time" << YAML::Value << "1m";
  out << YAML::Key << "exp_samples" << YAML::Value << YAML::BeginSeq << YAML::BeginMap << YAML::Key << "labels"
      << YAML::Value << "{}" << YAML::Key << "value" << YAML::Value << expected << YAML::EndMap << YAML::EndSeq;
  out << YAML::EndMap << YAML::EndSeq << YAML::EndMap << YAML::EndSeq << YAML::EndMap;
  return out.c_str();
}

// The names a scrape serves: its families', and a histogram's _bucket, _count, _sum.
std::set<std::string> ServedNames(const std::string& scrape) {
  std::set<std::string> names;
  std::istringstream lines(scrape);
  for (std::string line; std::getline(lines, line);) {
    std::istringstream words(line);
    std::string hash, type, name, kind;
    if (!(words >> hash >> type >> name >> kind) || hash != "#" || type != "TYPE") continue;
    names.insert(name);
    if (kind == "histogram") {
      for (const char* suffix : {"_bucket", "_count", "_sum"}) names.insert(name + suffix);
    }
  }
  return names;
}

class ServerMetricsTest : public ::testing::Test {
 protected:
  ServerMetricsTest()
      : dir_(FreshDataDir()), queue_(dir_, clock_), artifacts_(dir_, ArtifactStoreOptions{1 << 20}),
        cache_(artifacts_, clock_), state_(queue_, artifacts_, cache_, clock_, "", "", false) {}

  std::filesystem::path dir_;
  FakeClock clock_;
  JobQueue queue_;
  ArtifactStore artifacts_;
  FabricCache cache_;
  ServiceState state_;
};

v1::Job Render() {
  v1::Job job;
  job.set_kind(v1::JOB_KIND_RENDER);
  job.mutable_render()->mutable_scene()->set_name("scene");
  return job;
}

TEST_F(ServerMetricsTest, ScrapeReportsTheStoreTheJobsAndTheCalls) {
  v1::PrecomputeJob precompute;
  precompute.mutable_fabric()->mutable_knit();
  const std::string key(64, 'a');
  queue_.SubmitPrecomputeOnce(precompute, key, 0);
  queue_.Submit(Render());
  queue_.Submit(Render());

  v1::WorkerCapabilities gpu, cpu;
  gpu.set_gl_renderer("NVIDIA H200/PCIe/SSE2");
  cpu.set_gl_renderer("llvmpipe (LLVM 15.0.6, 256 bits)");
  cpu.set_software_gl(true);
  const std::string gpu_worker = state_.workers.Register(gpu);
  state_.workers.Register(cpu);

  // The precompute runs 4 s on the GPU worker and succeeds 10 s after submission.
  const JobLease lease = *queue_.Lease(gpu_worker);
  state_.workers.Seen(gpu_worker, lease.job.id());
  clock_.Advance(10'000);
  const std::string hash = artifacts_.Put("fitted");
  queue_.Complete(lease.job.id(), lease.token, {hash}, /*run_ms=*/4'000);
  cache_.Put(key, {{"manifest.json", hash}}, "{}");
  ASSERT_TRUE(cache_.Get(key));
  ASSERT_FALSE(cache_.Get(std::string(64, 'b')));
  // A render's lease expires.
  ASSERT_TRUE(queue_.Lease("remote"));
  clock_.Advance(queue_.options().lease_duration_ms);
  ASSERT_EQ(queue_.RequeueExpired(), 1);
  state_.workers.Seen(gpu_worker, "");

  state_.metrics.ObserveRpc("LoomService", "GetJob", grpc::StatusCode::NOT_FOUND, 0.003);
  state_.metrics.ObserveRpc("LoomService", "GetJob", grpc::StatusCode::NOT_FOUND, 0.2);

  const std::string text = state_.metrics.Scrape(state_);
  const auto sample = [&](const std::string& name) { return Sample(text, name); };
  EXPECT_EQ(sample(R"(loom_jobs{kind="render",state="queued"})"), 2);
  EXPECT_EQ(sample(R"(loom_jobs{kind="precompute",state="succeeded"})"), 1);
  EXPECT_EQ(sample(R"(loom_jobs{kind="precompute",state="queued"})"), 0);
  EXPECT_EQ(sample(R"(loom_jobs_ready{kind="render"})"), 2);
  EXPECT_EQ(sample("loom_leases_total"), 2);
  EXPECT_EQ(sample(R"(loom_lease_expiries_total{reason="deadline"})"), 1);
  EXPECT_EQ(sample(R"(loom_lease_expiries_total{reason="stuck"})"), 0);
  EXPECT_EQ(sample("loom_failed_attempts_total"), 1);
  EXPECT_EQ(sample("loom_job_retries_total"), 1);
  EXPECT_EQ(sample(R"(loom_fabric_cache_lookups_total{result="hit"})"), 1);
  EXPECT_EQ(sample(R"(loom_fabric_cache_lookups_total{result="miss"})"), 1);
  EXPECT_EQ(sample("loom_fabric_cache_fabrics"), 1);
  EXPECT_EQ(sample("loom_fabric_cache_bytes"), 6);
  EXPECT_EQ(sample("loom_artifact_store_bytes"), 6);
  EXPECT_EQ(sample("loom_artifact_store_budget_bytes"), 1 << 20);
  EXPECT_EQ(sample(R"(loom_workers{renderer="NVIDIA H200/PCIe/SSE2",software_gl="false",state="idle"})"), 1);
  // The CPU worker was not heard from since the clock moved on.
  EXPECT_EQ(sample(R"x(loom_workers{renderer="llvmpipe (LLVM 15.0.6, 256 bits)",software_gl="true",)x"
                   R"x(state="lost"})x"),
            1);
  // The precompute's 10 s from submission to its end, and the worker's 4 s.
  EXPECT_EQ(sample(R"(loom_job_duration_seconds_count{kind="precompute",state="succeeded"})"), 1);
  EXPECT_EQ(sample(R"(loom_job_duration_seconds_sum{kind="precompute",state="succeeded"})"), 10);
  EXPECT_EQ(sample(R"(loom_job_duration_seconds_bucket{kind="precompute",state="succeeded",le="5"})"), 0);
  EXPECT_EQ(sample(R"(loom_job_duration_seconds_bucket{kind="precompute",state="succeeded",le="10"})"), 1);
  EXPECT_EQ(sample(R"(loom_job_run_seconds_sum{kind="precompute"})"), 4);
  EXPECT_EQ(sample(R"(loom_rpc_duration_seconds_count{code="NOT_FOUND",method="GetJob",service="LoomService"})"),
            2);
  EXPECT_EQ(
      sample(R"(loom_rpc_duration_seconds_bucket{code="NOT_FOUND",method="GetJob",service="LoomService",le="0.005"})"),
      1);
  EXPECT_EQ(sample(R"(loom_build_info{version=")" + std::string(kVersion) + R"("})"), 1);

  EXPECT_EQ(PromtoolProblems(text), "");
}

TEST_F(ServerMetricsTest, PromtoolRefusesABrokenScrapeAndABrokenQuery) {
  // The checks the tests here rely on can fail: a counter without _total, a sample
  // line that is not the text format, an expression that does not parse.
  EXPECT_NE(PromtoolProblems("# TYPE loom_leases counter\nloom_leases 1\n"), "");
  EXPECT_NE(PromtoolProblems("loom_jobs{kind=render} 1\n"), "");
  EXPECT_NE(PromtoolOnFile("check rules", RecordingRules({"sum(rate(loom_jobs[5m])"})), "");
}

// The deployment's files against what a server serves: the KEDA ScaledObject's query
// and the Grafana dashboard's (deploy/k8s/autoscale/).
class DeployedQueriesTest : public ServerMetricsTest {
 protected:
  // A queue with work of every kind of readiness: a precompute ready, a render
  // waiting for it, two renders ready, one leased and one running; and one render
  // done, one RPC handled (labelled histograms show once observed).
  std::string QueueScrape() {
    state_.metrics.ObserveRpc("LoomService", "GetJob", grpc::StatusCode::OK, 0.001);
    queue_.Submit(Render());
    const JobLease done = *queue_.Lease("w0");
    queue_.Complete(done.job.id(), done.token, {artifacts_.Put("frame")}, 1'000);
    v1::PrecomputeJob precompute;
    precompute.mutable_fabric()->mutable_knit();
    queue_.Submit(Render());
    queue_.Submit(Render());
    const v1::Job fabric = queue_.SubmitPrecomputeOnce(precompute, std::string(64, 'a'), 0);
    v1::Job waiting = Render();
    waiting.add_depends_on(fabric.id());
    queue_.Submit(waiting);
    queue_.Submit(Render());
    queue_.Submit(Render());
    const JobLease running = *queue_.Lease("w1");
    queue_.Heartbeat(running.job.id(), running.token, 0.5, "render");
    queue_.Lease("w2");
    return state_.metrics.Scrape(state_);
  }
};

TEST_F(DeployedQueriesTest, TheScaledObjectCountsTheWorkOnceWhateverTheServers) {
  const std::string scrape = QueueScrape();
  const double work = Sample(scrape, R"(loom_jobs{kind="render",state="leased"})") +
                      Sample(scrape, R"(loom_jobs{kind="render",state="running"})") +
                      Sample(scrape, R"(loom_jobs_ready{kind="render"})") +
                      Sample(scrape, R"(loom_jobs_ready{kind="precompute"})");
  ASSERT_EQ(work, 5);  // 2 renders and the precompute ready, 1 leased, 1 running

  const YAML::Node scaled = YAML::LoadFile(std::string(LOOM_SOURCE_DIR) + "/deploy/k8s/autoscale/scaledobject.yaml");
  ASSERT_EQ(scaled["kind"].as<std::string>(), "ScaledObject");
  EXPECT_EQ(scaled["spec"]["scaleTargetRef"]["name"].as<std::string>(), "loom-worker-gpu");
  const YAML::Node trigger = scaled["spec"]["triggers"][0];
  ASSERT_EQ(trigger["type"].as<std::string>(), "prometheus");
  const std::string query = trigger["metadata"]["query"].as<std::string>();
  // Prometheus's own engine evaluates the query on this scrape as one server and as
  // three servers of one store report it: the same work either way.
  for (const int servers : {1, 3}) {
    EXPECT_EQ(PromtoolOnFile("test rules", ExpressionTest(scrape, servers, query, work)), "")
        << servers << " server(s)";
  }
  // The test can fail: the same query summed over the servers counts the work thrice.
  EXPECT_NE(PromtoolOnFile("test rules", ExpressionTest(scrape, 3, "sum(loom_jobs_ready) + "
                                                                   "sum(loom_jobs{state=~\"leased|running\"})",
                                                        work)),
            "");
}

TEST_F(DeployedQueriesTest, TheGrafanaDashboardsQueriesParseAndNameServedMetrics) {
  const std::set<std::string> served = ServedNames(QueueScrape());
  const auto dashboard =
      nlohmann::json::parse(ReadFile(std::string(LOOM_SOURCE_DIR) + "/deploy/k8s/autoscale/grafana-dashboard.json"));
  std::vector<std::string> expressions;
  for (const auto& panel : dashboard.at("panels")) {
    for (const auto& target : panel.at("targets")) expressions.push_back(target.at("expr").get<std::string>());
  }
  ASSERT_GE(expressions.size(), 10u);
  EXPECT_EQ(PromtoolOnFile("check rules", RecordingRules(expressions)), "");
  const std::regex name("loom_[a-z0-9_]+");
  for (const std::string& expression : expressions) {
    for (auto match = std::sregex_iterator(expression.begin(), expression.end(), name); match != std::sregex_iterator();
         ++match) {
      EXPECT_TRUE(served.contains(match->str())) << match->str() << " in " << expression << " is not served";
    }
  }
}

}  // namespace
}  // namespace loom::server
