#pragma once
// The client side of LoomService, one method per thing the `loom` CLI does, each
// throwing the loom::Error a failed call stands for (rpc/status.h), so the CLI's
// exit code says what went wrong. Also what tests drive the service with.

#include <grpcpp/channel.h>

#include <chrono>
#include <filesystem>
#include <functional>
#include <memory>
#include <string>
#include <vector>

#include "loom/v1/service.grpc.pb.h"

namespace loom::client {

class JobClient {
 public:
  explicit JobClient(std::shared_ptr<grpc::Channel> channel);

  v1::SubmitJobResponse Submit(const v1::SubmitJobRequest& request);
  v1::Job Get(const std::string& job_id);
  v1::ListJobsResponse List(const v1::ListJobsRequest& request);
  v1::Job Cancel(const std::string& job_id);
  v1::Job SetPriority(const std::string& job_id, int32_t priority);
  v1::RetryJobsResponse Retry(const std::vector<std::string>& job_ids);
  v1::DeleteJobsResponse Delete(const std::vector<std::string>& job_ids);
  std::vector<std::string> Log(const std::string& job_id);
  // Follows a job, calling `on_event` for every event, until it ends; returns the
  // job as it ended.
  v1::Job Watch(const std::string& job_id, const std::function<void(const v1::JobEvent&)>& on_event);

  v1::ListFabricsResponse ListFabrics();
  v1::GetFabricResponse GetFabric(const std::string& key);
  void DeleteFabric(const std::string& key);
  v1::CachedFabric PinFabric(const std::string& key, bool pinned);
  // Writes the cached asset's files into `directory` (a fabric asset directory,
  // readable by core/fit/fabric_asset.h). Returns the entry.
  v1::CachedFabric DownloadFabric(const std::string& key, const std::filesystem::path& directory);

  // Replaces each obj_path or gltf_path mesh of `scene` (relative to `scene_directory`) by the
  // artifact of its bytes, uploading only those the server lacks. The server never
  // sees a client path. Returns how many meshes were uploaded.
  int UploadMeshes(v1::SceneSpec& scene, const std::filesystem::path& scene_directory);
  // The same for an animation's mesh colliders.
  int UploadMeshes(v1::AnimationSpec& animation, const std::filesystem::path& spec_directory);
  // An artifact's bytes, verified.
  std::string Download(const std::string& sha256);

  v1::ServerInfo ServerInfo();
  v1::ListWorkersResponse ListWorkers();
  // Waits until the channel connects (a server starting up), at most `timeout`;
  // Error(kUnavailable) if it does not.
  void WaitForServer(std::chrono::milliseconds timeout);

 private:
  int UploadMeshRefs(const std::vector<v1::MeshRef*>& meshes, const std::filesystem::path& directory);
  std::shared_ptr<grpc::Channel> channel_;
  std::unique_ptr<v1::LoomService::Stub> stub_;
};

}  // namespace loom::client
