// loom fabric precompute | render [--frames A..B] | animate | jobs list|show|watch|cancel|log|priority|retry|rm

#include <cstdio>
#include <filesystem>
#include <iostream>
#include <optional>
#include <set>

#include "client/client_command.h"
#include "client/frame_range.h"
#include "core/animate/cloth_sequence_io.h"
#include "core/image/image.h"
#include "core/spec/limits.h"
#include "core/spec/spec_json.h"
#include "core/util/error.h"
#include "core/util/file_io.h"
#include "core/util/progress_bar.h"
#include "core/util/subprocess.h"
#include "loom/v1/job.pb.h"
#include "loom/v1/job_state.h"

namespace loom::client {
namespace {

std::string StateName(v1::JobState state) {
  return v1::JobState_Name(state).substr(std::string_view("JOB_STATE_").size());
}
std::string KindName(v1::JobKind kind) { return v1::JobKind_Name(kind).substr(std::string_view("JOB_KIND_").size()); }

void PrintJobLine(const v1::Job& job) {
  std::printf("%-36s %-10s %-9s %5.1f%%  %s\n", job.id().c_str(), KindName(job.kind()).c_str(),
              StateName(job.state()).c_str(), 100.0 * job.progress().fraction(),
              job.error().empty() ? job.progress().stage().c_str() : job.error().c_str());
}

void PrintJob(const v1::Job& job) {
  std::printf("job %s\n  kind: %s\n  state: %s\n  priority: %d\n  attempts: %u of %u\n  progress: %.1f%% %s\n",
              job.id().c_str(), KindName(job.kind()).c_str(), StateName(job.state()).c_str(), job.priority(),
              job.attempts(), job.max_attempts(), 100.0 * job.progress().fraction(), job.progress().stage().c_str());
  if (!job.fabric_key().empty()) std::printf("  fabric key: %s\n", job.fabric_key().c_str());
  for (const std::string& id : job.depends_on()) std::printf("  depends on: %s\n", id.c_str());
  for (const std::string& hash : job.result_artifacts()) std::printf("  result: %s\n", hash.c_str());
  for (const std::string& worker : job.blocklisted_workers()) std::printf("  blocklisted worker: %s\n", worker.c_str());
  if (!job.worker_id().empty()) std::printf("  worker: %s\n", job.worker_id().c_str());
  if (!job.error().empty()) std::printf("  error: %s\n", job.error().c_str());
}

// Options every submitting command shares.
struct SubmitOptions {
  int priority = 0;
  std::string request_id;
  bool no_wait = false;

  void AddTo(CLI::App* command) {
    command->add_option("--priority", priority, "Higher runs first")->capture_default_str();
    command->add_option("--request-id", request_id, "Idempotency key: submitting again with it returns the first job");
    command->add_flag("--no-wait", no_wait, "Print the job and return without waiting for it");
  }
  void Fill(v1::SubmitJobRequest& request) const {
    request.set_priority(priority);
    request.set_client_request_id(request_id);
  }
};

// Follows the precomputes a submission made or joined (each once) to their end.
void WaitForDependencies(ClientFlags& flags, const google::protobuf::RepeatedPtrField<v1::Job>& dependencies) {
  std::set<std::string> seen;
  for (const v1::Job& dependency : dependencies) {
    if (IsTerminal(dependency.state()) || !seen.insert(dependency.id()).second) continue;
    WaitForJob(flags, dependency.id(), "precompute " + dependency.fabric_key().substr(0, 8), false);
  }
}

// Submit output: the job (JSON, or its id on stdout) and, when waiting, every
// dependency and then the job followed to the end.
v1::Job SubmitAndWait(ClientFlags& flags, const v1::SubmitJobRequest& request, const SubmitOptions& options,
                      const std::string& label) {
  const v1::SubmitJobResponse response = flags.Connect().Submit(request);
  if (flags.json)
    PrintJson(response);
  else
    std::fprintf(stderr, "submitted job %s\n", response.job().id().c_str());
  if (options.no_wait) return response.job();
  WaitForDependencies(flags, response.dependencies());
  return WaitForJob(flags, response.job().id(), label, false);
}

ClientCommand AddPrecompute(CLI::App& fabric, ClientFlags& flags) {
  struct Options {
    std::string fabric, settings, out;
    SubmitOptions submit;
  };
  auto options = std::make_shared<Options>();
  auto* command =
      fabric.add_subcommand("precompute", "Build a fabric's asset with its method on the server (cached by its key)");
  command->footer(
      "A fabric already in the server's cache is not fitted again: the submission is answered by a job that is\n"
      "SUCCEEDED at once and names the cached fabric (its log says so). To fit it again, remove it first\n"
      "(loom cache rm KEY).");
  command->add_option("fabric", options->fabric, "Fabric spec file (JSON)")->required();
  command->add_option("--settings", options->settings, "Precompute settings file (JSON); default: the defaults");
  command->add_option("--out,-o", options->out, "Also download the fitted asset into this directory");
  options->submit.AddTo(command);
  return {command, [&flags, options] {
            v1::SubmitJobRequest request;
            v1::PrecomputeJob& job = *request.mutable_precompute();
            *job.mutable_fabric() = LoadSpecFile<v1::FabricSpec>(options->fabric, "fabric");
            if (!options->settings.empty()) {
              *job.mutable_settings() = LoadSpecFile<v1::PrecomputeSettings>(options->settings, "precompute");
            }
            options->submit.Fill(request);
            const v1::Job done = SubmitAndWait(flags, request, options->submit, "precompute");
            if (options->submit.no_wait) return 0;
            if (const int code = JobExitCode(done)) return code;
            if (!options->out.empty()) flags.Connect().DownloadFabric(done.fabric_key(), options->out);
            if (flags.json)
              PrintJson(done);
            else
              std::printf("fabric %s\n", done.fabric_key().c_str());
            return 0;
          }};
}

// The one result of a render or animate job, downloaded.
std::string DownloadResult(ClientFlags& flags, const v1::Job& done) {
  if (done.result_artifacts_size() != 1) {
    throw Error(ErrorCode::kInternal, KindName(done.kind()) + " job " + done.id() + " has " +
                                          std::to_string(done.result_artifacts_size()) + " results, not 1");
  }
  return flags.Connect().Download(done.result_artifacts(0));
}

// loom render --frames: the range's jobs submitted, then followed in frame order
// (progress over the whole range), each frame written as it ends; a failed frame
// is reported and the rest still gathered. The MP4 is made once every frame is in.
struct FrameRangeOptions {
  std::string frames, mp4;
  float fps = 25;
};

int RenderFrameRange(ClientFlags& flags, const v1::SubmitJobRequest& request, const std::vector<int>& sequence_objects,
                     FrameRange range, const std::string& out, const FrameRangeOptions& options,
                     const SubmitOptions& submit) {
  const std::vector<v1::SubmitJobResponse> responses =
      SubmitFrameRange(flags.Connect(), request, sequence_objects, range);
  if (!flags.json) std::fprintf(stderr, "submitted %u frame job(s), frames %s\n", range.size(), options.frames.c_str());
  if (submit.no_wait || flags.json) {
    for (const v1::SubmitJobResponse& response : responses) {
      if (flags.json)
        PrintJson(response);
      else
        std::printf("%s\n", response.job().id().c_str());
    }
  }
  if (submit.no_wait) return 0;

  google::protobuf::RepeatedPtrField<v1::Job> dependencies;
  for (const v1::SubmitJobResponse& response : responses) dependencies.MergeFrom(response.dependencies());
  WaitForDependencies(flags, dependencies);
  std::vector<std::string> failed;
  {
    ProgressBar bar("render frames " + options.frames);
    for (uint32_t i = 0; i < range.size(); ++i) {
      const uint32_t frame = range.first + i;
      const v1::Job done = flags.Connect().Watch(responses[i].job().id(), [&](const v1::JobEvent& event) {
        bar.Update((i + event.job().progress().fraction()) / range.size(), "frame " + std::to_string(frame));
      });
      if (flags.json) PrintJson(done);
      if (done.state() != v1::JOB_STATE_SUCCEEDED) {
        failed.push_back("frame " + std::to_string(frame) + " (job " + done.id() + ") " +
                         (done.state() == v1::JOB_STATE_CANCELLED ? "was cancelled" : "failed: " + done.error()));
        continue;
      }
      WriteFileAtomic(FramePath(out, frame), DownloadResult(flags, done));
    }
  }
  for (const std::string& failure : failed) std::fprintf(stderr, "loom: %s\n", failure.c_str());
  if (!failed.empty()) {
    std::fprintf(stderr, "loom: %zu of %u frame(s) did not render; retry their jobs (loom jobs retry) and run the "
                 "same command with the same --request-id to gather them\n", failed.size(), range.size());
    return kJobFailedExit;
  }
  if (!flags.json) std::printf("wrote %u frame(s) %s\n", range.size(), out.c_str());
  if (options.mp4.empty()) return 0;
  // libx264 in yuv420p wants even sides: an odd frame gets a one-pixel border.
  RunProgram("ffmpeg",
             {"-y", "-loglevel", "error", "-framerate", std::to_string(options.fps), "-start_number",
              std::to_string(range.first), "-i", out, "-vf", "pad=ceil(iw/2)*2:ceil(ih/2)*2", "-c:v", "libx264",
              "-pix_fmt", "yuv420p", options.mp4},
             "install the Debian package ffmpeg (scripts/setup.sh)");
  if (!flags.json) std::printf("wrote %s\n", options.mp4.c_str());
  return 0;
}

// The checks a frame range's flags get before anything is uploaded or submitted;
// the range, if --frames asks for one.
std::optional<FrameRange> CheckFrameRangeFlags(const std::string& out, ImageFileFormat format,
                                               const FrameRangeOptions& options) {
  if (options.frames.empty()) {
    if (!options.mp4.empty()) throw Error(ErrorCode::kInvalidArgument, "--mp4: needs a frame range (--frames A..B)");
    return std::nullopt;
  }
  const FrameRange range = ParseFrameRange(options.frames);
  CheckFramePattern(out);
  if (options.mp4.empty()) return range;
  if (std::filesystem::path(options.mp4).extension() != ".mp4") {
    throw Error(ErrorCode::kInvalidArgument, "--mp4: " + options.mp4 + " does not end in .mp4");
  }
  if (format != ImageFileFormat::kPng) {
    throw Error(ErrorCode::kInvalidArgument, "--mp4: needs PNG frames (sRGB); --out " + out + " is not .png");
  }
  if (!(options.fps > 0 && options.fps <= kMaxFramesPerSecond)) {
    throw Error(ErrorCode::kInvalidArgument,
                "--fps: " + std::to_string(options.fps) + " is not in (0, " + std::to_string(kMaxFramesPerSecond) + "]");
  }
  return range;
}

ClientCommand AddRender(CLI::App& app, ClientFlags& flags) {
  struct Options {
    std::string scene, out;
    FrameRangeOptions range;
    SubmitOptions submit;
  };
  auto options = std::make_shared<Options>();
  auto* command = app.add_subcommand(
      "render", "Render a scene on the server (its OBJ and glTF meshes are uploaded; missing fabrics are precomputed)");
  command->add_option("scene", options->scene, "Scene spec file (JSON); mesh paths are relative to it")->required();
  command->add_option("--out,-o", options->out,
                      "Output image (.png sRGB or .exr linear); with --frames a pattern, as frames/f_%04d.png")
      ->required();
  command->add_option("--frames", options->range.frames,
                      "Render frames A..B (inclusive) of the scene's glTF mesh sequences, one job a frame");
  command->add_option("--mp4", options->range.mp4, "With --frames: also make this H.264 video of them (ffmpeg)");
  command->add_option("--fps", options->range.fps, "The video's frame rate")->capture_default_str();
  options->submit.AddTo(command);
  return {
      command, [&flags, options] {
        // A bad name fails before any work.
        const ImageFileFormat format = FormatFromPath(options->out);
        const std::optional<FrameRange> range = CheckFrameRangeFlags(options->out, format, options->range);
        v1::SubmitJobRequest request;
        v1::SceneSpec& scene = *request.mutable_render()->mutable_scene();
        scene = LoadSpecFile<v1::SceneSpec>(options->scene, "scene");
        const v1::ImageFormat wanted = format == ImageFileFormat::kExr ? v1::IMAGE_FORMAT_EXR : v1::IMAGE_FORMAT_PNG;
        if (scene.render().format() == v1::IMAGE_FORMAT_UNSPECIFIED) scene.mutable_render()->set_format(wanted);
        if (scene.render().format() != wanted) {
          throw Error(ErrorCode::kInvalidArgument, "scene.render.format is " +
                                                       v1::ImageFormat_Name(scene.render().format()) +
                                                       " but the output file is " + options->out);
        }
        const std::vector<int> sequence_objects = range ? SequenceObjects(scene) : std::vector<int>();
        const int uploaded = flags.Connect().UploadMeshes(scene, std::filesystem::path(options->scene).parent_path());
        if (uploaded > 0 && !flags.json) std::fprintf(stderr, "uploaded %d mesh(es)\n", uploaded);
        options->submit.Fill(request);
        if (range) {
          return RenderFrameRange(flags, request, sequence_objects, *range, options->out, options->range,
                                  options->submit);
        }
        const v1::Job done = SubmitAndWait(flags, request, options->submit, "render");
        if (options->submit.no_wait) return 0;
        if (const int code = JobExitCode(done)) return code;
        WriteFileAtomic(options->out, DownloadResult(flags, done));
        if (flags.json)
          PrintJson(done);
        else
          std::printf("wrote %s (job %s)\n", options->out.c_str(), done.id().c_str());
        return 0;
      }};
}

ClientCommand AddAnimate(CLI::App& app, ClientFlags& flags) {
  struct Options {
    std::string spec, out, obj_dir;
    SubmitOptions submit;
  };
  auto options = std::make_shared<Options>();
  auto* command = app.add_subcommand("animate", "Simulate a knit cloth's animation on the server (docs/animation.md)");
  command->add_option("spec", options->spec, "Animation spec file (JSON)")->required();
  command->add_option("--out,-o", options->out, "The mesh sequence: glTF 2.0 binary (.glb)")->required();
  command->add_option("--obj-dir", options->obj_dir, "Also write frame_NNNNN.obj per frame into this directory");
  options->submit.AddTo(command);
  return {command, [&flags, options] {
            if (std::filesystem::path(options->out).extension() != ".glb") {
              throw Error(ErrorCode::kInvalidArgument, "--out: " + options->out + " does not end in .glb");
            }
            v1::SubmitJobRequest request;
            v1::AnimationSpec& animation = *request.mutable_animate()->mutable_animation();
            animation = LoadSpecFile<v1::AnimationSpec>(options->spec, "animation");
            flags.Connect().UploadMeshes(animation, std::filesystem::path(options->spec).parent_path());
            options->submit.Fill(request);
            const v1::Job done = SubmitAndWait(flags, request, options->submit, "animate");
            if (options->submit.no_wait) return 0;
            if (const int code = JobExitCode(done)) return code;
            const std::string bytes = DownloadResult(flags, done);
            WriteFileAtomic(options->out, bytes);
            if (!options->obj_dir.empty()) {
              animate::WriteObjSequence(ParseGltfSequence(bytes, "job " + done.id()), options->obj_dir);
            }
            if (flags.json)
              PrintJson(done);
            else
              std::printf("wrote %s (job %s)\n", options->out.c_str(), done.id().c_str());
            return 0;
          }};
}

std::vector<ClientCommand> AddJobsCommands(CLI::App& app, ClientFlags& flags) {
  auto* jobs = app.add_subcommand("jobs", "List, show, watch, cancel, reprioritise, retry and delete jobs; read logs");
  std::vector<ClientCommand> commands;

  struct ListOptions {
    std::vector<std::string> states, kinds;
    uint32_t limit = 100;
    std::string page_token;
  };
  auto list_options = std::make_shared<ListOptions>();
  auto* list = jobs->add_subcommand("list", "Jobs, newest first");
  list->add_option("--state", list_options->states, "Only these states (queued, leased, running, succeeded, ...)");
  list->add_option("--kind", list_options->kinds, "Only these kinds (precompute, render, animate)");
  list->add_option("--limit", list_options->limit, "Page size")->check(CLI::Range(1, 1000))->capture_default_str();
  list->add_option("--page-token", list_options->page_token, "Continue from a previous page");
  commands.push_back({list, [&flags, list_options] {
                        v1::ListJobsRequest request;
                        for (std::string state : list_options->states) {
                          for (char& c : state) c = static_cast<char>(std::toupper(c));
                          v1::JobState value;
                          if (!v1::JobState_Parse("JOB_STATE_" + state, &value)) {
                            throw Error(ErrorCode::kInvalidArgument, "--state: unknown state '" + state + "'");
                          }
                          request.add_states(value);
                        }
                        for (std::string kind : list_options->kinds) {
                          for (char& c : kind) c = static_cast<char>(std::toupper(c));
                          v1::JobKind value;
                          if (!v1::JobKind_Parse("JOB_KIND_" + kind, &value)) {
                            throw Error(ErrorCode::kInvalidArgument, "--kind: unknown kind '" + kind + "'");
                          }
                          request.add_kinds(value);
                        }
                        request.set_page_size(list_options->limit);
                        request.set_page_token(list_options->page_token);
                        const v1::ListJobsResponse response = flags.Connect().List(request);
                        if (flags.json) {
                          PrintJson(response);
                          return 0;
                        }
                        for (const v1::Job& job : response.jobs()) PrintJobLine(job);
                        if (!response.next_page_token().empty()) {
                          std::printf("more: --page-token %s\n", response.next_page_token().c_str());
                        }
                        return 0;
                      }});

  // show, watch, cancel, log: one job id each.
  auto job_id = std::make_shared<std::string>();
  auto add = [&](const char* name, const char* help, std::function<int()> run) {
    auto* command = jobs->add_subcommand(name, help);
    command->add_option("job", *job_id, "Job id")->required();
    commands.push_back({command, std::move(run)});
  };
  add("show", "A job's state, progress, results and error", [&flags, job_id] {
    const v1::Job job = flags.Connect().Get(*job_id);
    if (flags.json)
      PrintJson(job);
    else
      PrintJob(job);
    return 0;
  });
  add("watch", "Follow a job to its end (its log lines, a progress bar on a terminal)",
      [&flags, job_id] { return JobExitCode(WaitForJob(flags, *job_id, "job " + job_id->substr(0, 8), true)); });
  add("cancel", "Cancel a job (a running one stops at its worker's next heartbeat)", [&flags, job_id] {
    const v1::Job job = flags.Connect().Cancel(*job_id);
    if (flags.json)
      PrintJson(job);
    else
      PrintJobLine(job);
    return 0;
  });
  add("log", "A job's log: the queue's and its workers' lines", [&flags, job_id] {
    const std::vector<std::string> lines = flags.Connect().Log(*job_id);
    if (flags.json) {
      v1::GetJobLogResponse response;
      for (const std::string& line : lines) response.add_lines(line);
      PrintJson(response);
    } else {
      for (const std::string& line : lines) std::printf("%s\n", line.c_str());
    }
    return 0;
  });

  struct PriorityOptions {
    std::string job_id;
    int32_t priority = 0;
  };
  auto priority = std::make_shared<PriorityOptions>();
  auto* set_priority = jobs->add_subcommand("priority", "Change a queued or running job's priority (higher first)");
  set_priority->add_option("job", priority->job_id, "Job id")->required();
  set_priority->add_option("priority", priority->priority, "New priority")->required();
  commands.push_back({set_priority, [&flags, priority] {
                        const v1::Job job = flags.Connect().SetPriority(priority->job_id, priority->priority);
                        if (flags.json)
                          PrintJson(job);
                        else
                          PrintJobLine(job);
                        return 0;
                      }});

  // retry, rm: any number of job ids.
  auto job_ids = std::make_shared<std::vector<std::string>>();
  auto add_many = [&](const char* name, const char* help, std::function<int()> run) {
    auto* command = jobs->add_subcommand(name, help);
    command->add_option("jobs", *job_ids, "Job ids")->required();
    commands.push_back({command, std::move(run)});
  };
  add_many("retry", "Queue failed or cancelled jobs again (and the failed jobs they depend on)", [&flags, job_ids] {
    const v1::RetryJobsResponse response = flags.Connect().Retry(*job_ids);
    if (flags.json)
      PrintJson(response);
    else
      for (const v1::Job& job : response.jobs()) PrintJobLine(job);
    return 0;
  });
  add_many("rm", "Delete finished jobs, their logs and their results (frames, sequences)", [&flags, job_ids] {
    const v1::DeleteJobsResponse response = flags.Connect().Delete(*job_ids);
    if (flags.json)
      PrintJson(response);
    else
      std::printf("deleted %u job(s), %u frame(s)\n", response.deleted_jobs(), response.removed_frames());
    return 0;
  });
  return commands;
}

}  // namespace

std::vector<ClientCommand> AddJobCommands(CLI::App& app, ClientFlags& flags) {
  auto* fabric = app.add_subcommand("fabric", "Fabric precomputes");
  std::vector<ClientCommand> commands = {AddPrecompute(*fabric, flags), AddRender(app, flags), AddAnimate(app, flags)};
  for (ClientCommand& command : AddJobsCommands(app, flags)) commands.push_back(std::move(command));
  return commands;
}

}  // namespace loom::client
