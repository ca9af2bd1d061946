// The job service under load (issue #6 "Benchmark"): 256×256 render jobs through
// the queue of an in-process loom-server on loopback (real gRPC over 127.0.0.1, a
// temporary data directory, --local-workers 1 or 2), the fabric cached beforehand.
//
// Each of `clients_per_worker × workers` client threads submits a render through
// the client API, follows it (WatchJob) to SUCCEEDED, downloads the frame and
// submits the next: a closed loop. With one client per worker no job waits in
// the queue, so latency minus render time is the service's own overhead (RPCs,
// lease, upload, PNG transfer); with two, every worker is kept busy with one job
// waiting behind it, the latency a user of a busy but not flooded farm sees. Counters:
//   jobs_per_s     finished jobs per second of wall time
//   p50_ms, p99_ms submit → SUCCEEDED and frame downloaded, per job
//   render_ms      the worker's own render time (Job.timings.run_ms), mean
//   render_share   mean render time / mean latency: the rest is queueing, RPCs,
//                  fabric and frame transfer, PNG encoding
//
// The fabric is precomputed first, untimed, with small settings (named in the
// label: the default settings take about a minute of fit), since only the render
// path is measured. Run: build/bench/loom_service_benchmark

#include <benchmark/benchmark.h>
#include <spdlog/spdlog.h>
#include <unistd.h>

#include <algorithm>
#include <atomic>
#include <chrono>
#include <filesystem>
#include <mutex>
#include <numeric>
#include <thread>
#include <vector>

#include "client/job_client.h"
#include "core/util/error.h"
#include "rpc/channel.h"
#include "server/loom_server.h"
#include "tests/server/tiny_specs.h"

namespace loom {
namespace {

constexpr int kJobs = 96;
constexpr uint32_t kFrameSize = 256;

struct JobSample {
  double latency_ms = 0;
  double render_ms = 0;
};

double Percentile(std::vector<double> values, double p) {
  std::sort(values.begin(), values.end());
  const auto index = static_cast<size_t>(p * static_cast<double>(values.size() - 1) + 0.5);
  return values[index];
}

std::string SettingsLabel(const v1::PrecomputeSettings& s) {
  return "fabric precomputed with " + std::to_string(s.spatial_resolution()) + "x" +
         std::to_string(s.spatial_resolution()) + " texels, " + std::to_string(s.view_directions()) + "x" +
         std::to_string(s.light_directions()) + " view x light directions, " + std::to_string(s.lobes()) + " lobe";
}

// Submit → SUCCEEDED → frame downloaded, timed.
JobSample RenderOne(client::JobClient& client, const v1::SubmitJobRequest& request) {
  const auto start = std::chrono::steady_clock::now();
  const v1::SubmitJobResponse submitted = client.Submit(request);
  if (submitted.dependencies_size() != 0) throw Error(ErrorCode::kInternal, "the fabric was not cached");
  const v1::Job done = client.Watch(submitted.job().id(), [](const v1::JobEvent&) {});
  if (done.state() != v1::JOB_STATE_SUCCEEDED) {
    throw Error(ErrorCode::kInternal, "job " + done.id() + " ended " + v1::JobState_Name(done.state()) + ": " + done.error());
  }
  const std::string frame = client.Download(done.result_artifacts(0));
  benchmark::DoNotOptimize(frame.data());
  const auto end = std::chrono::steady_clock::now();
  return {std::chrono::duration<double, std::milli>(end - start).count(), done.timings().run_ms()};
}

// `clients` threads, each rendering until `jobs` have been taken in all.
std::vector<JobSample> RenderBatch(const std::string& address, const v1::SubmitJobRequest& request, int jobs,
                                   int clients) {
  std::vector<JobSample> samples;
  std::mutex mu;
  std::atomic<int> next{0};
  std::vector<std::thread> threads;
  for (int c = 0; c < clients; ++c) {
    threads.emplace_back([&] {
      rpc::ChannelOptions channel;
      channel.address = address;
      client::JobClient client(rpc::MakeChannel(channel));
      while (next++ < jobs) {
        const JobSample sample = RenderOne(client, request);
        std::lock_guard lock(mu);
        samples.push_back(sample);
      }
    });
  }
  for (std::thread& thread : threads) thread.join();
  return samples;
}

void BM_RenderJobsThroughTheQueue(benchmark::State& state) {
  spdlog::set_level(spdlog::level::warn);  // a line per job would drown the figures
  const int workers = static_cast<int>(state.range(0));
  const int clients = static_cast<int>(state.range(1)) * workers;
  const auto data_dir = std::filesystem::temp_directory_path() /
                        ("loom-service-benchmark-" + std::to_string(::getpid()) + "-" + std::to_string(workers) + "-" +
                         std::to_string(clients));
  std::filesystem::remove_all(data_dir);
  {
    server::ServerOptions options;
    options.data_dir = data_dir;
    options.listen = "127.0.0.1:0";
    options.local_workers = workers;
    server::LoomServer server(options);
    rpc::ChannelOptions channel;
    channel.address = server.address();
    client::JobClient client(rpc::MakeChannel(channel));

    // Untimed: the fabric into the cache, then one job per client so that every
    // worker has fetched the fitted fabric and its GL state is warm.
    const v1::Job fabric = client.Watch(client.Submit(server::PrecomputeRequest()).job().id(),
                                        [](const v1::JobEvent&) {});
    if (fabric.state() != v1::JOB_STATE_SUCCEEDED) {
      state.SkipWithError(("precompute failed: " + fabric.error()).c_str());
      return;
    }
    v1::SceneSpec scene = server::TinyScene(kFrameSize, kFrameSize);
    scene.mutable_render()->set_format(v1::IMAGE_FORMAT_PNG);  // what `loom render -o frame.png` asks for
    const v1::SubmitJobRequest request = server::RenderRequest(scene);
    RenderBatch(server.address(), request, clients, clients);

    std::vector<JobSample> samples;
    for (auto _ : state) {
      const auto start = std::chrono::steady_clock::now();
      samples = RenderBatch(server.address(), request, kJobs, clients);
      const double seconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
      state.SetIterationTime(seconds);
      state.counters["jobs_per_s"] = static_cast<double>(samples.size()) / seconds;
    }
    std::vector<double> latencies;
    double render_sum = 0;
    for (const JobSample& sample : samples) {
      latencies.push_back(sample.latency_ms);
      render_sum += sample.render_ms;
    }
    const double latency_sum = std::accumulate(latencies.begin(), latencies.end(), 0.0);
    state.counters["jobs"] = static_cast<double>(samples.size());
    state.counters["p50_ms"] = Percentile(latencies, 0.50);
    state.counters["p99_ms"] = Percentile(latencies, 0.99);
    state.counters["render_ms"] = render_sum / static_cast<double>(samples.size());
    state.counters["render_share"] = render_sum / latency_sum;
    state.SetLabel(std::to_string(workers) + " worker(s), " + std::to_string(clients) + " clients, " +
                   std::to_string(kFrameSize) + "x" + std::to_string(kFrameSize) + " PNG; " +
                   SettingsLabel(server::TinySettings()));
  }
  std::filesystem::remove_all(data_dir);
}

BENCHMARK(BM_RenderJobsThroughTheQueue)
    ->ArgNames({"workers", "clients_per_worker"})
    ->ArgsProduct({{1, 2}, {1, 2}})
    ->Iterations(1)
    ->UseManualTime()
    ->Unit(benchmark::kMillisecond);

}  // namespace
}  // namespace loom

BENCHMARK_MAIN();
