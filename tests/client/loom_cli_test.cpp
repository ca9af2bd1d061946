// The `loom` binary against a server in this process: what scripts rely on (exit
// codes, messages naming the field, mesh upload, the frame on disk).

#include <gtest/gtest.h>
#include <sys/wait.h>

#include <cstdlib>
#include <nlohmann/json.hpp>

#include "core/scene/gltf_loader.h"
#include "core/spec/spec_json.h"
#include "core/util/file_io.h"
#include "tests/server/service_fixture.h"

namespace loom::server {
namespace {

struct CliRun {
  int exit_code;
  std::string output;  // stdout and stderr
};

class LoomCliTest : public ServiceTest {
 protected:
  CliRun Loom(const std::string& arguments, const std::string& server = "") {
    const auto output_path = data_dir_ / "cli-output.txt";
    const std::string command = std::string(LOOM_CLI) + " --server " + (server.empty() ? server_->address() : server) +
                                " " + arguments + " > " + output_path.string() + " 2>&1";
    const int status = std::system(command.c_str());
    return {WIFEXITED(status) ? WEXITSTATUS(status) : -1, ReadFile(output_path)};
  }
  std::filesystem::path Write(const std::string& name, const std::string& text) {
    WriteFileAtomic(data_dir_ / "files" / name, text);
    return data_dir_ / "files" / name;
  }
  // `loom fabric precompute --no-wait` of the tiny knit; returns the job id.
  std::string SubmitPrecompute() {
    const auto fabric = Write("fabric.json", R"({"knit": {}})");
    const auto settings = Write("settings.json", SpecToJson(TinySettings()));
    const CliRun submitted =
        Loom("--json fabric precompute " + fabric.string() + " --settings " + settings.string() + " --no-wait");
    EXPECT_EQ(submitted.exit_code, 0) << submitted.output;
    return nlohmann::json::parse(submitted.output)["job"]["id"];
  }
};

TEST_F(LoomCliTest, WorkersListsTheWorkerThatRanAJob) {
  StartServer();
  const std::string id = SubmitPrecompute();
  ASSERT_EQ(Loom("jobs watch " + id).exit_code, 0);
  const CliRun run = Loom("--json workers");
  ASSERT_EQ(run.exit_code, 0) << run.output;
  const nlohmann::json workers = nlohmann::json::parse(run.output)["workers"];
  ASSERT_EQ(workers.size(), 1u) << run.output;
  EXPECT_EQ(workers[0]["jobs_succeeded"], 1);
  EXPECT_EQ(workers[0]["state"], "idle");
  EXPECT_EQ(workers[0].value("current_job_id", ""), "");
  const CliRun table = Loom("workers");
  EXPECT_NE(table.output.find(" 1 done, 0 failed"), std::string::npos) << table.output;
}

TEST_F(LoomCliTest, UnreachableServerIsExitCode4) {
  ServerOptions options;
  options.local_workers = 0;
  StartServer(options);
  const CliRun run = Loom("server-info", "127.0.0.1:1");
  EXPECT_EQ(run.exit_code, 4) << run.output;
  EXPECT_NE(run.output.find("GetServerInfo"), std::string::npos) << run.output;
}

TEST_F(LoomCliTest, BadSpecIsExitCode2NamingTheFieldAndUnknownJobIs3) {
  ServerOptions options;
  options.local_workers = 0;
  StartServer(options);
  const auto scene = Write("scene.json", R"({"objects": [{"mesh": {"builtin": "BUILTIN_SHAPE_PLANE"}, "colour": 1}]})");
  CliRun run = Loom("render " + scene.string() + " -o " + (data_dir_ / "f.png").string());
  EXPECT_EQ(run.exit_code, 2) << run.output;
  EXPECT_NE(run.output.find("scene.objects[0].colour: unknown field"), std::string::npos) << run.output;

  run = Loom("jobs show no-such-job");
  EXPECT_EQ(run.exit_code, 3) << run.output;
}

TEST_F(LoomCliTest, CancelledJobIsExitCode6) {
  ServerOptions options;
  options.local_workers = 0;  // the job stays queued until cancelled
  StartServer(options);
  const std::string id = SubmitPrecompute();
  EXPECT_EQ(Loom("jobs cancel " + id).exit_code, 0);
  const CliRun watched = Loom("jobs watch " + id);
  EXPECT_EQ(watched.exit_code, 6) << watched.output;
  EXPECT_NE(watched.output.find("cancelled"), std::string::npos) << watched.output;
}

TEST_F(LoomCliTest, RenderUploadsTheObjMeshAndWritesTheFrame) {
  StartServer();
  // A unit quad with UVs, as an OBJ next to the scene.
  Write("quad.obj",
        "v -0.5 -0.5 0\nv 0.5 -0.5 0\nv 0.5 0.5 0\nv -0.5 0.5 0\n"
        "vt 0 0\nvt 1 0\nvt 1 1\nvt 0 1\nvn 0 0 1\nf 1/1/1 2/2/1 3/3/1\nf 1/1/1 3/3/1 4/4/1\n");
  v1::SceneSpec scene = TinyScene(48, 32);
  scene.mutable_objects(0)->mutable_mesh()->set_obj_path("quad.obj");
  scene.mutable_render()->clear_format();
  const auto scene_path = Write("scene.json", SpecToJson(scene));
  const auto frame = data_dir_ / "out" / "frame.png";
  const CliRun run = Loom("render " + scene_path.string() + " -o " + frame.string());
  ASSERT_EQ(run.exit_code, 0) << run.output;
  EXPECT_NE(run.output.find("uploaded 1 mesh"), std::string::npos) << run.output;
  EXPECT_TRUE(std::filesystem::exists(frame));
  // The second time the server has the mesh: nothing is uploaded.
  const CliRun again = Loom("render " + scene_path.string() + " -o " + frame.string());
  ASSERT_EQ(again.exit_code, 0) << again.output;
  EXPECT_EQ(again.output.find("uploaded"), std::string::npos) << again.output;
}

TEST_F(LoomCliTest, AnimateWritesTheSequenceAndObjFramesAndARenderUploadsAFrameOfIt) {
  StartServer();
  const auto spec = Write("hanging.json", R"({"cloth": {"loops": 4, "courses": 6, "wale_axis": {"z": -1}},
      "pins": [{"course": 0}], "initial_velocity": {"y": 1}, "duration_seconds": 0.4})");
  CliRun run = Loom("animate " + spec.string() + " -o " + (data_dir_ / "cloth.png").string());
  EXPECT_EQ(run.exit_code, 2) << run.output;
  EXPECT_NE(run.output.find("--out: "), std::string::npos) << run.output;

  const auto glb = data_dir_ / "files" / "cloth.glb";
  run = Loom("animate " + spec.string() + " -o " + glb.string() + " --obj-dir " + (data_dir_ / "frames").string());
  ASSERT_EQ(run.exit_code, 0) << run.output;
  EXPECT_EQ(ReadGltfSequence(glb).frames.size(), 11u);
  EXPECT_TRUE(std::filesystem::exists(data_dir_ / "frames" / "frame_00010.obj"));
  EXPECT_FALSE(std::filesystem::exists(data_dir_ / "frames" / "frame_00011.obj"));

  // The sequence's last frame as a scene's mesh, beside the scene: the server holds
  // those bytes already (the job's result), so nothing is uploaded.
  v1::SceneSpec scene = TinyScene(48, 32);
  scene.mutable_objects(0)->mutable_mesh()->set_gltf_path("cloth.glb");
  scene.mutable_objects(0)->mutable_mesh()->set_frame(10);
  scene.mutable_render()->clear_format();
  const auto scene_path = Write("scene.json", SpecToJson(scene));
  run = Loom("render " + scene_path.string() + " -o " + (data_dir_ / "frame.png").string());
  ASSERT_EQ(run.exit_code, 0) << run.output;
  EXPECT_EQ(run.output.find("uploaded"), std::string::npos) << run.output;
  EXPECT_TRUE(std::filesystem::exists(data_dir_ / "frame.png"));
}

// `loom render --frames`: a job a frame, each written by the pattern, the video
// made by ffmpeg with every frame; bad flags refused naming the flag.
TEST_F(LoomCliTest, RenderFramesWritesEachFrameByThePatternAndTheVideo) {
  StartServer();
  const auto spec = Write("hanging.json", R"({"cloth": {"loops": 4, "courses": 6, "wale_axis": {"z": -1}},
      "pins": [{"course": 0}], "initial_velocity": {"y": 2}, "frames_per_second": 8, "duration_seconds": 1})");
  ASSERT_EQ(Loom("animate " + spec.string() + " -o " + (data_dir_ / "files" / "cloth.glb").string()).exit_code, 0);
  v1::SceneSpec scene = TinyScene(48, 32);
  scene.mutable_objects(0)->mutable_mesh()->set_gltf_path("cloth.glb");
  scene.mutable_render()->clear_format();
  const std::string scene_path = Write("scene.json", SpecToJson(scene)).string();
  const std::string pattern = (data_dir_ / "frames" / "f_%02d.png").string();
  const std::string video = (data_dir_ / "cloth.mp4").string();

  CliRun run = Loom("render " + scene_path + " -o " + pattern + " --frames 2..7 --mp4 " + video + " --fps 8");
  ASSERT_EQ(run.exit_code, 0) << run.output;
  EXPECT_NE(run.output.find("submitted 6 frame job(s)"), std::string::npos) << run.output;
  for (int frame = 0; frame < 9; ++frame) {
    const bool wanted = frame >= 2 && frame <= 7;
    EXPECT_EQ(std::filesystem::exists(data_dir_ / "frames" / ("f_0" + std::to_string(frame) + ".png")), wanted)
        << frame;
  }
  // Frame 5 of the range is what a render of frame 5 alone makes.
  scene.mutable_objects(0)->mutable_mesh()->set_frame(5);
  Write("scene5.json", SpecToJson(scene));
  ASSERT_EQ(Loom("render " + (data_dir_ / "files" / "scene5.json").string() + " -o " +
                 (data_dir_ / "alone5.png").string())
                .exit_code,
            0);
  EXPECT_EQ(ReadFile(data_dir_ / "alone5.png"), ReadFile(data_dir_ / "frames" / "f_05.png"));
  EXPECT_NE(ReadFile(data_dir_ / "frames" / "f_02.png"), ReadFile(data_dir_ / "frames" / "f_05.png"));
  // The video has the six frames.
  const auto probe = data_dir_ / "probe.txt";
  ASSERT_EQ(std::system(("ffprobe -v error -count_frames -select_streams v:0 -show_entries stream=nb_read_frames "
                         "-of csv=p=0 " + video + " > " + probe.string())
                            .c_str()),
            0);
  EXPECT_EQ(ReadFile(probe), "6\n");

  const std::pair<std::string, std::string> refused[] = {
      {" -o " + pattern + " --frames 7..2", "--frames: 7..2 ends before it begins"},
      {" -o " + pattern + " --frames 0..3001", "--frames: frame 3001 is past"},
      {" -o " + pattern + " --frames 0..9", "frame 9"},  // the sequence has frames 0 to 8
      {" -o " + (data_dir_ / "f.png").string() + " --frames 0..1", "--out: "},
      {" -o " + (data_dir_ / "f.png").string() + " --mp4 " + video, "--mp4: needs a frame range"},
      {" -o " + pattern + " --frames 0..1 --mp4 " + (data_dir_ / "v.avi").string(), "--mp4: "},
      {" -o " + (data_dir_ / "f_%d.exr").string() + " --frames 0..1 --mp4 " + video, "--mp4: needs PNG frames"},
      {" -o " + pattern + " --frames 0..1 --mp4 " + video + " --fps 0", "--fps: "},
  };
  for (const auto& [arguments, message] : refused) {
    run = Loom("render " + scene_path + arguments);
    EXPECT_EQ(run.exit_code, 2) << arguments << "\n" << run.output;
    EXPECT_NE(run.output.find(message), std::string::npos) << arguments << "\n" << run.output;
  }
  v1::SceneSpec plain_scene = TinyScene(48, 32);
  plain_scene.mutable_render()->clear_format();
  const auto plain = Write("plain.json", SpecToJson(plain_scene));
  run = Loom("render " + plain.string() + " -o " + pattern + " --frames 0..1");
  EXPECT_EQ(run.exit_code, 2) << run.output;
  EXPECT_NE(run.output.find("--frames: the scene has no glTF mesh"), std::string::npos) << run.output;
}

// The failure policy users of render farms expect (issue 22): change a job's
// priority, retry what failed or was cancelled, delete finished jobs and frames.
TEST_F(LoomCliTest, JobsCanBeReprioritisedRetriedAndDeleted) {
  ServerOptions options;
  options.local_workers = 0;  // jobs stay where the test puts them
  StartServer(options);
  const std::string id = SubmitPrecompute();

  CliRun run = Loom("--json jobs priority " + id + " 7");
  ASSERT_EQ(run.exit_code, 0) << run.output;
  EXPECT_EQ(nlohmann::json::parse(run.output)["priority"], 7);
  EXPECT_EQ(Loom("jobs retry " + id).exit_code, 5);  // queued: nothing to retry
  EXPECT_EQ(Loom("jobs rm " + id).exit_code, 5);     // not finished
  ASSERT_EQ(Loom("jobs cancel " + id).exit_code, 0);
  run = Loom("--json jobs retry " + id);
  ASSERT_EQ(run.exit_code, 0) << run.output;
  EXPECT_EQ(nlohmann::json::parse(run.output)["jobs"][0]["state"], "JOB_STATE_QUEUED");
  ASSERT_EQ(Loom("jobs cancel " + id).exit_code, 0);
  run = Loom("jobs rm " + id);
  ASSERT_EQ(run.exit_code, 0) << run.output;
  EXPECT_NE(run.output.find("deleted 1 job(s)"), std::string::npos) << run.output;
  EXPECT_EQ(Loom("jobs show " + id).exit_code, 3);
}

TEST_F(LoomCliTest, ATokenFileAuthenticatesAndSpecChecksNameTheFile) {
  ServerOptions options;
  options.local_workers = 0;
  options.client_token = "client-secret";
  options.worker_token = "worker-secret";
  StartServer(options);
  const auto token = Write("token", "client-secret\n");
  EXPECT_EQ(Loom("server-info").exit_code, 5);
  const CliRun run = Loom("--token-file " + token.string() + " server-info");
  EXPECT_EQ(run.exit_code, 0) << run.output;
  EXPECT_EQ(Loom("workers").exit_code, 5);
  const auto bad = Write("bad.json", R"({"knit": {"wales": 99}})");
  const CliRun check = Loom("spec check fabric " + bad.string());
  EXPECT_EQ(check.exit_code, 2) << check.output;
  EXPECT_EQ(check.output.rfind(bad.string() + ": fabric.knit.wales: ", 0), 0u) << check.output;
}

}  // namespace
}  // namespace loom::server
