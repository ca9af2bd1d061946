#include "client/job_client.h"

#include <map>

#include "core/util/error.h"
#include "core/util/file_io.h"
#include "core/util/sha256.h"
#include "loom/v1/job_state.h"
#include "rpc/artifact_transfer.h"
#include "rpc/channel.h"
#include "rpc/status.h"

namespace loom::client {
namespace {

using namespace std::chrono_literals;

// Every unary call: a deadline, the status turned into an Error naming the call.
template <typename Request, typename Response, typename Method>
Response Call(v1::LoomService::Stub& stub, Method method, const Request& request, std::string_view name) {
  grpc::ClientContext context;
  context.set_deadline(rpc::DeadlineIn(60s));
  Response response;
  rpc::ThrowIfFailed((stub.*method)(&context, request, &response), name);
  return response;
}

}  // namespace

JobClient::JobClient(std::shared_ptr<grpc::Channel> channel)
    : channel_(std::move(channel)), stub_(v1::LoomService::NewStub(channel_)) {}

void JobClient::WaitForServer(std::chrono::milliseconds timeout) {
  if (!channel_->WaitForConnected(rpc::DeadlineIn(timeout))) {
    throw Error(ErrorCode::kUnavailable, "no server answered within " + std::to_string(timeout.count()) + " ms");
  }
}

v1::SubmitJobResponse JobClient::Submit(const v1::SubmitJobRequest& request) {
  return Call<v1::SubmitJobRequest, v1::SubmitJobResponse>(*stub_, &v1::LoomService::Stub::SubmitJob, request,
                                                           "SubmitJob");
}

v1::Job JobClient::Get(const std::string& job_id) {
  v1::GetJobRequest request;
  request.set_job_id(job_id);
  return Call<v1::GetJobRequest, v1::Job>(*stub_, &v1::LoomService::Stub::GetJob, request, "GetJob");
}

v1::ListJobsResponse JobClient::List(const v1::ListJobsRequest& request) {
  return Call<v1::ListJobsRequest, v1::ListJobsResponse>(*stub_, &v1::LoomService::Stub::ListJobs, request, "ListJobs");
}

v1::Job JobClient::Cancel(const std::string& job_id) {
  v1::CancelJobRequest request;
  request.set_job_id(job_id);
  return Call<v1::CancelJobRequest, v1::Job>(*stub_, &v1::LoomService::Stub::CancelJob, request, "CancelJob");
}

v1::Job JobClient::SetPriority(const std::string& job_id, int32_t priority) {
  v1::SetJobPriorityRequest request;
  request.set_job_id(job_id);
  request.set_priority(priority);
  return Call<v1::SetJobPriorityRequest, v1::Job>(*stub_, &v1::LoomService::Stub::SetJobPriority, request,
                                                  "SetJobPriority");
}

v1::RetryJobsResponse JobClient::Retry(const std::vector<std::string>& job_ids) {
  v1::RetryJobsRequest request;
  for (const std::string& id : job_ids) request.add_job_ids(id);
  return Call<v1::RetryJobsRequest, v1::RetryJobsResponse>(*stub_, &v1::LoomService::Stub::RetryJobs, request,
                                                           "RetryJobs");
}

v1::DeleteJobsResponse JobClient::Delete(const std::vector<std::string>& job_ids) {
  v1::DeleteJobsRequest request;
  for (const std::string& id : job_ids) request.add_job_ids(id);
  return Call<v1::DeleteJobsRequest, v1::DeleteJobsResponse>(*stub_, &v1::LoomService::Stub::DeleteJobs, request,
                                                             "DeleteJobs");
}

std::vector<std::string> JobClient::Log(const std::string& job_id) {
  v1::GetJobLogRequest request;
  request.set_job_id(job_id);
  const auto response = Call<v1::GetJobLogRequest, v1::GetJobLogResponse>(*stub_, &v1::LoomService::Stub::GetJobLog,
                                                                          request, "GetJobLog");
  return {response.lines().begin(), response.lines().end()};
}

v1::Job JobClient::Watch(const std::string& job_id, const std::function<void(const v1::JobEvent&)>& on_event) {
  v1::WatchJobRequest request;
  request.set_job_id(job_id);
  grpc::ClientContext context;  // no deadline: a job may run for hours
  const auto reader = stub_->WatchJob(&context, request);
  v1::JobEvent event;
  v1::Job last;
  while (reader->Read(&event)) {
    last = event.job();
    on_event(event);
  }
  rpc::ThrowIfFailed(reader->Finish(), "WatchJob");
  if (!IsTerminal(last.state())) {
    throw Error(ErrorCode::kUnavailable, "WatchJob: the stream ended before job " + job_id + " did");
  }
  return last;
}

v1::ListFabricsResponse JobClient::ListFabrics() {
  return Call<v1::ListFabricsRequest, v1::ListFabricsResponse>(*stub_, &v1::LoomService::Stub::ListFabrics, {},
                                                               "ListFabrics");
}

v1::GetFabricResponse JobClient::GetFabric(const std::string& key) {
  v1::GetFabricRequest request;
  request.set_fabric_key(key);
  return Call<v1::GetFabricRequest, v1::GetFabricResponse>(*stub_, &v1::LoomService::Stub::GetFabric, request,
                                                           "GetFabric");
}

void JobClient::DeleteFabric(const std::string& key) {
  v1::DeleteFabricRequest request;
  request.set_fabric_key(key);
  Call<v1::DeleteFabricRequest, v1::DeleteFabricResponse>(*stub_, &v1::LoomService::Stub::DeleteFabric, request,
                                                          "DeleteFabric");
}

v1::CachedFabric JobClient::PinFabric(const std::string& key, bool pinned) {
  v1::PinFabricRequest request;
  request.set_fabric_key(key);
  request.set_pinned(pinned);
  return Call<v1::PinFabricRequest, v1::PinFabricResponse>(*stub_, &v1::LoomService::Stub::PinFabric, request,
                                                           "PinFabric")
      .fabric();
}

v1::CachedFabric JobClient::DownloadFabric(const std::string& key, const std::filesystem::path& directory) {
  const v1::CachedFabric fabric = GetFabric(key).fabric();
  for (const v1::ArtifactRef& file : fabric.files()) {
    if (file.name().empty() || file.name().find('/') != std::string::npos) {
      throw Error(ErrorCode::kInternal, "fabric " + key + ": the server named a file '" + file.name() + "'");
    }
    WriteFileAtomic(directory / file.name(), Download(file.sha256()));
  }
  return fabric;
}

int JobClient::UploadMeshes(v1::SceneSpec& scene, const std::filesystem::path& scene_directory) {
  std::vector<v1::MeshRef*> meshes;
  for (v1::SceneObject& object : *scene.mutable_objects()) meshes.push_back(object.mutable_mesh());
  return UploadMeshRefs(meshes, scene_directory);
}

int JobClient::UploadMeshes(v1::AnimationSpec& animation, const std::filesystem::path& spec_directory) {
  std::vector<v1::MeshRef*> meshes;
  for (v1::ColliderSpec& collider : *animation.mutable_colliders()) {
    if (collider.has_mesh()) meshes.push_back(collider.mutable_mesh()->mutable_mesh());
  }
  return UploadMeshRefs(meshes, spec_directory);
}

int JobClient::UploadMeshRefs(const std::vector<v1::MeshRef*>& meshes, const std::filesystem::path& directory) {
  std::map<std::string, std::string> bytes_by_hash, name_by_hash;
  for (v1::MeshRef* ref : meshes) {
    v1::MeshRef& mesh = *ref;
    const bool obj = mesh.source_case() == v1::MeshRef::kObjPath;
    if (!obj && mesh.source_case() != v1::MeshRef::kGltfPath) continue;
    std::string bytes = ReadFile(directory / (obj ? mesh.obj_path() : mesh.gltf_path()));
    std::string hash = Sha256Hex(bytes);
    name_by_hash.emplace(hash, obj ? "mesh.obj" : bytes.starts_with("glTF") ? "mesh.glb" : "mesh.gltf");
    mesh.set_artifact(hash);  // replaces the path (one source); the server tells the format by the bytes
    bytes_by_hash.emplace(std::move(hash), std::move(bytes));
  }
  if (bytes_by_hash.empty()) return 0;
  v1::FindMissingArtifactsRequest request;
  for (const auto& [hash, bytes] : bytes_by_hash) request.add_sha256(hash);
  const auto missing = Call<v1::FindMissingArtifactsRequest, v1::FindMissingArtifactsResponse>(
      *stub_, &v1::LoomService::Stub::FindMissingArtifacts, request, "FindMissingArtifacts");
  for (const std::string& hash : missing.missing()) {
    const std::string& bytes = bytes_by_hash.at(hash);
    v1::UploadArtifactRequest::Header header;
    *header.mutable_artifact() = rpc::MakeArtifactRef(name_by_hash.at(hash), bytes);
    rpc::UploadArtifact(*stub_, header, bytes);
  }
  return missing.missing_size();
}

std::string JobClient::Download(const std::string& sha256) { return rpc::DownloadArtifact(*stub_, sha256); }

v1::ListWorkersResponse JobClient::ListWorkers() {
  return Call<v1::ListWorkersRequest, v1::ListWorkersResponse>(*stub_, &v1::LoomService::Stub::ListWorkers, {},
                                                                "ListWorkers");
}

v1::ServerInfo JobClient::ServerInfo() {
  return Call<v1::GetServerInfoRequest, v1::ServerInfo>(*stub_, &v1::LoomService::Stub::GetServerInfo, {},
                                                        "GetServerInfo");
}

}  // namespace loom::client
