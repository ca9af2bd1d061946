// What the service refuses, and how (issue 22's findings of a client written from
// the protos alone): every refusal names the field and the limit, is counted
// against no job, and leaves the server as it was.

#include <gmock/gmock.h>
#include <grpcpp/client_context.h>
#include <gtest/gtest.h>
#include <spdlog/sinks/ostream_sink.h>
#include <spdlog/spdlog.h>

#include <chrono>
#include <sstream>

#include "rpc/artifact_transfer.h"
#include "server/artifact_upload.h"
#include "server/job_service.h"
#include "tests/server/service_fixture.h"

namespace loom::server {
namespace {

using ::testing::HasSubstr;

TEST_F(ServiceTest, AnUploadChunkOverTheProtosCapIsRefused) {
  ServerOptions options;
  options.local_workers = 0;
  StartServer(options);
  auto stub = RawStub(*server_, "");
  const std::string bytes(kMaxUploadChunkBytes + 1, 'v');
  grpc::ClientContext context;
  v1::UploadArtifactResponse response;
  const auto writer = stub->UploadArtifact(&context, &response);
  const v1::ArtifactRef artifact = rpc::MakeArtifactRef("mesh.obj", bytes);
  v1::UploadArtifactRequest message;
  *message.mutable_header()->mutable_artifact() = artifact;
  writer->Write(message);
  message.set_chunk(bytes);  // one chunk, 4 MiB + 1: within the 8 MiB message cap
  writer->Write(message);
  writer->WritesDone();
  const grpc::Status status = writer->Finish();
  EXPECT_EQ(status.error_code(), grpc::StatusCode::INVALID_ARGUMENT);
  EXPECT_THAT(status.error_message(), HasSubstr("chunk: 4194305 bytes exceed 4194304"));
  grpc::ClientContext find_context;
  v1::FindMissingArtifactsRequest find;
  find.add_sha256(artifact.sha256());
  v1::FindMissingArtifactsResponse missing;
  ASSERT_TRUE(stub->FindMissingArtifacts(&find_context, find, &missing).ok());
  EXPECT_EQ(missing.missing_size(), 1);  // nothing was stored
}

TEST_F(ServiceTest, FindMissingArtifactsTakesAtMostTenThousandHashes) {
  ServerOptions options;
  options.local_workers = 0;
  StartServer(options);
  auto stub = RawStub(*server_, "");
  v1::FindMissingArtifactsRequest request;
  for (int i = 0; i < kMaxFindMissingHashes; ++i) request.add_sha256(std::string(64, 'a'));
  grpc::ClientContext ok_context;
  v1::FindMissingArtifactsResponse response;
  ASSERT_TRUE(stub->FindMissingArtifacts(&ok_context, request, &response).ok());
  EXPECT_EQ(response.missing_size(), 1);  // without repeats
  request.add_sha256(std::string(64, 'b'));
  grpc::ClientContext context;
  const grpc::Status status = stub->FindMissingArtifacts(&context, request, &response);
  EXPECT_EQ(status.error_code(), grpc::StatusCode::INVALID_ARGUMENT);
  EXPECT_THAT(status.error_message(), HasSubstr("sha256: 10001 hashes exceed 10000"));
}

TEST_F(ServiceTest, EmptyJobIdsAreInvalidArgumentAndUnknownStatesAreRefused) {
  ServerOptions options;
  options.local_workers = 0;
  StartServer(options);
  auto stub = RawStub(*server_, "");
  {
    grpc::ClientContext context;
    v1::Job job;
    const grpc::Status status = stub->GetJob(&context, v1::GetJobRequest(), &job);
    EXPECT_EQ(status.error_code(), grpc::StatusCode::INVALID_ARGUMENT);
    EXPECT_EQ(status.error_message(), "job_id: is empty");
  }
  {
    grpc::ClientContext context;
    v1::Job job;
    EXPECT_EQ(stub->CancelJob(&context, v1::CancelJobRequest(), &job).error_code(),
              grpc::StatusCode::INVALID_ARGUMENT);
  }
  {
    grpc::ClientContext context;
    v1::ListJobsRequest request;
    request.add_states(v1::JOB_STATE_QUEUED);
    request.add_states(static_cast<v1::JobState>(42));  // as a newer or broken client sends it
    v1::ListJobsResponse response;
    const grpc::Status status = stub->ListJobs(&context, request, &response);
    EXPECT_EQ(status.error_code(), grpc::StatusCode::INVALID_ARGUMENT);
    EXPECT_THAT(status.error_message(), HasSubstr("states[1]: 42 is not a job state"));
  }
}

TEST_F(ServiceTest, LeaseJobForAWorkerThatNeverRegisteredIsNotFound) {
  ServerOptions options;
  options.local_workers = 0;
  StartServer(options);
  client::JobClient client = Client();
  client.Submit(PrecomputeRequest());
  auto worker = RawWorkerStub(*server_, "");
  grpc::ClientContext context;
  v1::LeaseJobRequest request;
  request.set_worker_id("w-made-up");
  v1::LeaseJobResponse response;
  const grpc::Status status = worker->LeaseJob(&context, request, &response);
  EXPECT_EQ(status.error_code(), grpc::StatusCode::NOT_FOUND);
  EXPECT_THAT(status.error_message(), HasSubstr("w-made-up is not registered"));
  EXPECT_EQ(client.ServerInfo().queued_jobs(), 1u);  // not leased
}

// An unauthenticated client cannot flood the log: at most one warning a second.
TEST_F(ServiceTest, RefusedCallsAreLoggedAtMostOnceASecond) {
  ServerOptions options;
  options.local_workers = 0;
  options.client_token = "client-secret";
  options.worker_token = "worker-secret";
  StartServer(options);
  std::ostringstream log;
  const auto sink = std::make_shared<spdlog::sinks::ostream_sink_mt>(log);
  spdlog::default_logger()->sinks().push_back(sink);
  auto stub = RawStub(*server_, "wrong");
  const auto start = std::chrono::steady_clock::now();
  constexpr int kCalls = 300;
  for (int i = 0; i < kCalls; ++i) {
    grpc::ClientContext context;
    v1::ServerInfo info;
    EXPECT_EQ(stub->GetServerInfo(&context, v1::GetServerInfoRequest(), &info).error_code(),
              grpc::StatusCode::UNAUTHENTICATED);
  }
  const double seconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
  spdlog::default_logger()->sinks().pop_back();
  int warnings = 0;
  for (size_t at = log.str().find("missing or wrong bearer token"); at != std::string::npos;
       at = log.str().find("missing or wrong bearer token", at + 1)) {
    ++warnings;
  }
  EXPECT_GE(warnings, 1);
  EXPECT_LE(warnings, 1 + static_cast<int>(seconds) + 1) << warnings << " warnings in " << seconds << " s";
  EXPECT_LT(warnings, kCalls / 10);
}

}  // namespace
}  // namespace loom::server
