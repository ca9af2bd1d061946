// The animate job through the service: an animation spec in, its mesh sequence
// out, the same as core's; a frame of a sequence rendered as a scene's mesh; bad
// specs and bad glTF uploads refused naming the field.

#include <gmock/gmock.h>
#include <gtest/gtest.h>

#include "core/animate/animation.h"
#include "core/animate/cloth_sequence_io.h"
#include "core/gl/egl_context.h"
#include "core/image/image.h"
#include "core/render/scene_render.h"
#include "core/scene/gltf_loader.h"
#include "core/scene/scene_geometry.h"
#include "core/spec/defaults.h"
#include "core/spec/spec_json.h"
#include "core/util/file_io.h"
#include "rpc/artifact_transfer.h"
#include "tests/server/service_fixture.h"

namespace loom::server {
namespace {

using ::testing::HasSubstr;

// A 6 × 8 cloth hung by its top course, 0.4 s at 25 frames a second.
v1::AnimationSpec Hanging() {
  return ParseSpecJson<v1::AnimationSpec>(R"({
    "name": "hanging",
    "cloth": {"loops": 6, "courses": 8, "wale_axis": {"z": -1}},
    "pins": [{"course": 0}],
    "initial_velocity": {"y": 2},
    "duration_seconds": 0.4
  })",
                                          "animation");
}

v1::SubmitJobRequest AnimateRequest(const v1::AnimationSpec& spec) {
  v1::SubmitJobRequest request;
  *request.mutable_animate()->mutable_animation() = spec;
  return request;
}

// TinyScene's camera and light on `mesh`, a plain object (no fabric) seen from the
// front, PNG-free EXR output.
v1::SceneSpec SequenceScene(const v1::MeshRef& mesh) {
  v1::SceneSpec scene = TinyScene();
  v1::SceneObject& object = *scene.mutable_objects(0);
  object.clear_fabric();
  *object.mutable_mesh() = mesh;
  object.mutable_transform()->mutable_scale()->set_x(0.3f);
  object.mutable_transform()->mutable_scale()->set_y(0.3f);
  object.mutable_transform()->mutable_scale()->set_z(0.3f);
  object.mutable_transform()->mutable_translation()->set_x(-0.75f);
  object.mutable_transform()->mutable_translation()->set_z(1.0f);
  return scene;
}

TEST_F(ServiceTest, AnAnimateJobReturnsCoresSequenceAndARenderDrawsItsFrames) {
  StartServer();
  client::JobClient client = Client();
  const v1::SubmitJobResponse submitted = client.Submit(AnimateRequest(Hanging()));
  EXPECT_EQ(submitted.job().kind(), v1::JOB_KIND_ANIMATE);
  const v1::Job done = client.Watch(submitted.job().id(), [](const v1::JobEvent&) {});
  ASSERT_EQ(done.state(), v1::JOB_STATE_SUCCEEDED) << done.error();
  ASSERT_EQ(done.result_artifacts_size(), 1);
  EXPECT_GT(done.timings().run_ms(), 0.0);
  const std::string glb = client.Download(done.result_artifacts(0));
  const MeshSequence served = ParseGltfSequence(glb, "served");

  // Core's run of the same spec, frame for frame (one thread below 4096 points:
  // the same sums in the same order).
  const animate::ClothAnimation core = animate::RunAnimation(Hanging());
  ASSERT_EQ(served.frames.size(), 11u);
  ASSERT_EQ(served.frames.size(), core.frames.size());
  for (size_t k = 0; k < core.frames.size(); ++k) {
    for (size_t p = 0; p < core.frames[k].size(); ++p) {
      ASSERT_NEAR(glm::distance(served.frames[k][p], core.frames[k][p]), 0.0f, 1e-5f) << k << " " << p;
    }
  }
  EXPECT_GT(glm::distance(served.frames[10][47], served.frames[0][47]), 0.2f);  // the cloth swung

  // Frame 10 of the sequence as a scene's mesh: the served frame equals the core
  // render of the same scene read from the file, and differs from frame 0's.
  const auto glb_path = data_dir_ / "hanging.glb";
  WriteFileAtomic(glb_path, glb);
  v1::MeshRef uploaded;
  uploaded.set_artifact(done.result_artifacts(0));
  uploaded.set_frame(10);
  const v1::Job rendered =
      client.Watch(client.Submit(RenderRequest(SequenceScene(uploaded))).job().id(), [](const v1::JobEvent&) {});
  ASSERT_EQ(rendered.state(), v1::JOB_STATE_SUCCEEDED) << rendered.error();
  const Image served_frame = ReadImageBytes(client.Download(rendered.result_artifacts(0)), "served.exr");

  const auto context = gl::EglContext::Create();
  GpuRenderer renderer(*context);
  const auto core_render = [&](uint32_t frame) {
    v1::MeshRef local;
    local.set_gltf_path(glb_path.string());
    local.set_frame(frame);
    const v1::SceneSpec full = WithDefaults(SequenceScene(local));
    const auto path = data_dir_ / ("core-" + std::to_string(frame) + ".exr");
    WriteImage(RenderScene(renderer, full, BuildSceneGeometry(full, FileMeshResolver("/")), {}).image, path);
    return ReadImage(path);  // the served frame's half-float quantisation
  };
  const Image frame10 = core_render(10), frame0 = core_render(0);
  ASSERT_EQ(served_frame.pixels.size(), frame10.pixels.size());
  float max_difference = 0.0f, moved = 0.0f;
  for (size_t i = 0; i < frame10.pixels.size(); ++i) {
    max_difference = std::max(max_difference, std::abs(served_frame.pixels[i] - frame10.pixels[i]));
    moved = std::max(moved, std::abs(frame0.pixels[i] - frame10.pixels[i]));
  }
  EXPECT_EQ(max_difference, 0.0f);
  EXPECT_GT(moved, 0.1f);

  // Deleting the job removes its sequence (nothing else holds it).
  EXPECT_EQ(client.Delete({done.id()}).removed_frames(), 1u);
}

// A box under the hanging cloth's lower end, as an OBJ (x −1…6, y −3…3, z −12…−7.5).
constexpr const char* kBoxObj =
    "v -1 -3 -12\nv 6 -3 -12\nv 6 3 -12\nv -1 3 -12\nv -1 -3 -7.5\nv 6 -3 -7.5\nv 6 3 -7.5\nv -1 3 -7.5\n"
    "f 1 3 2\nf 1 4 3\nf 5 6 7\nf 5 7 8\nf 1 2 6\nf 1 6 5\nf 4 8 7\nf 4 7 3\nf 1 5 8\nf 1 8 4\n"
    "f 2 3 7\nf 2 7 6\n";

TEST_F(ServiceTest, AnAnimationsMeshColliderIsUploadedHeldForTheJobAndReadByTheWorker) {
  StartServer();
  client::JobClient client = Client();
  WriteFileAtomic(data_dir_ / "box.obj", kBoxObj);
  v1::AnimationSpec spec = Hanging();
  spec.add_colliders()->mutable_mesh()->mutable_mesh()->set_obj_path("box.obj");
  const v1::AnimationSpec local = spec;
  EXPECT_EQ(client.UploadMeshes(spec, data_dir_), 1);
  ASSERT_EQ(spec.colliders(0).mesh().mesh().source_case(), v1::MeshRef::kArtifact);
  const v1::Job done =
      client.Watch(client.Submit(AnimateRequest(spec)).job().id(), [](const v1::JobEvent&) {});
  ASSERT_EQ(done.state(), v1::JOB_STATE_SUCCEEDED) << done.error();
  const MeshSequence served = ParseGltfSequence(client.Download(done.result_artifacts(0)), "served");
  // Core's run with the file beside the spec, frame for frame; the cloth came
  // into the box's field.
  const animate::ClothAnimation core = animate::RunAnimation(local, {}, 0, FileMeshResolver(data_dir_));
  EXPECT_LT(core.min_collider_distance, 0.9f);
  ASSERT_EQ(served.frames.size(), core.frames.size());
  for (size_t k = 0; k < core.frames.size(); ++k) {
    for (size_t p = 0; p < core.frames[k].size(); ++p) {
      ASSERT_NEAR(glm::distance(served.frames[k][p], core.frames[k][p]), 0.0f, 1e-5f) << k << " " << p;
    }
  }
  // A mesh that is not closed is refused at submission, naming the collider.
  WriteFileAtomic(data_dir_ / "open.obj", std::string(kBoxObj).substr(0, std::string(kBoxObj).rfind("f ")));
  v1::AnimationSpec open = Hanging();
  open.add_colliders()->mutable_mesh()->mutable_mesh()->set_obj_path("open.obj");
  client.UploadMeshes(open, data_dir_);
  try {
    client.Submit(AnimateRequest(open));
    FAIL() << "an open mesh collider was queued";
  } catch (const Error& error) {
    EXPECT_THAT(error.what(), HasSubstr("animation.colliders[0].mesh: not closed"));
  }
}

TEST_F(ServiceTest, BadAnimationsAndSequenceFramesAreRefusedNamingTheFieldAndStoreNothing) {
  ServerOptions options;
  options.local_workers = 0;
  StartServer(options);
  auto stub = RawStub(*server_, "");
  const auto expect_invalid = [&](const v1::SubmitJobRequest& request, const std::string& message) {
    const grpc::Status status = RawSubmit(*stub, request);
    EXPECT_EQ(status.error_code(), grpc::StatusCode::INVALID_ARGUMENT) << message << ": " << status.error_message();
    EXPECT_THAT(status.error_message(), HasSubstr(message));
  };
  v1::AnimationSpec zero_loops = Hanging();
  zero_loops.mutable_cloth()->set_loops(0);
  expect_invalid(AnimateRequest(zero_loops), "animation.cloth.loops: 0 is below 2");
  v1::AnimationSpec backwards = Hanging();
  backwards.set_duration_seconds(-1);
  expect_invalid(AnimateRequest(backwards), "animation.duration_seconds");
  v1::AnimationSpec absurd = Hanging();
  absurd.set_duration_seconds(600);
  absurd.set_frames_per_second(120);
  expect_invalid(AnimateRequest(absurd), "3000");
  v1::AnimationSpec chair = Hanging();
  chair.add_colliders()->mutable_mesh()->mutable_mesh()->set_obj_path("chair.obj");
  expect_invalid(AnimateRequest(chair),
                 "animation.colliders[0].mesh.mesh.obj_path: the server never opens client paths");

  // A sequence of 11 frames has no frame 11; an OBJ has no frame 1.
  const animate::ClothAnimation animation = animate::RunAnimation(Hanging());
  const auto glb_path = data_dir_ / "hanging.glb";
  animate::WriteGltfSequence(animate::ClothSequence(animation), glb_path);
  const std::string glb = ReadFile(glb_path);
  v1::UploadArtifactRequest::Header header;
  *header.mutable_artifact() = rpc::MakeArtifactRef("mesh.glb", glb);
  rpc::UploadArtifact(*stub, header, glb);
  v1::MeshRef past_the_end;
  past_the_end.set_artifact(header.artifact().sha256());
  past_the_end.set_frame(11);
  expect_invalid(RenderRequest(SequenceScene(past_the_end)), "scene.objects[0] (cloth): frame 11 of a sequence of 11");

  const std::string obj = "v 0 0 0\nv 1 0 0\nv 0 1 0\nvt 0 0\nvt 1 0\nvt 0 1\nf 1/1 2/2 3/3\n";
  *header.mutable_artifact() = rpc::MakeArtifactRef("mesh.obj", obj);
  rpc::UploadArtifact(*stub, header, obj);
  v1::MeshRef obj_frame;
  obj_frame.set_artifact(header.artifact().sha256());
  obj_frame.set_frame(1);
  expect_invalid(RenderRequest(SequenceScene(obj_frame)), "frame 1 of an OBJ mesh");

  // A glTF naming a file of the server's.
  const std::string external = R"({"asset": {"version": "2.0"}, "buffers": [{"uri": "/etc/passwd", "byteLength": 48}],
    "meshes": [{"primitives": [{"attributes": {"POSITION": 0}}]}]})";
  *header.mutable_artifact() = rpc::MakeArtifactRef("mesh.gltf", external);
  rpc::UploadArtifact(*stub, header, external);
  v1::MeshRef reads_a_file;
  reads_a_file.set_artifact(header.artifact().sha256());
  expect_invalid(RenderRequest(SequenceScene(reads_a_file)), "refers to the file '/etc/passwd'");

  v1::MeshRef client_path;
  client_path.set_gltf_path("/home/someone/cloth.glb");
  expect_invalid(RenderRequest(SequenceScene(client_path)), "scene.objects[0].mesh.gltf_path");

  client::JobClient client = Client();
  EXPECT_EQ(JobCount(client), 0);
}

}  // namespace
}  // namespace loom::server
