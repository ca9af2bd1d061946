#include "core/spec/spec_json.h"

#include <google/protobuf/util/message_differencer.h>
#include <gtest/gtest.h>
#include <unistd.h>

#include <cmath>
#include <filesystem>
#include <string>
#include <string_view>

#include "core/util/error.h"
#include "core/util/file_io.h"
#include "loom/v1/fabric.pb.h"
#include "loom/v1/precompute.pb.h"
#include "loom/v1/scene.pb.h"

namespace loom {
namespace {

using google::protobuf::util::MessageDifferencer;

// Every field of each spec type set at least once (names in both JSON spellings).
constexpr std::string_view kFabricJson = R"({
  "name": "cable rib",
  "knit": {"pattern": "KNIT_PATTERN_RIB", "ribKnit": 2, "rib_purl": 2, "wales": 8, "courses": 2,
           "loop_aspect": 1.3, "loop_jitter": 0.05, "seed": "12345678901234", "colour_pattern": [0, 1, 1, 0]},
  "yarns": [
    {"name": "wool", "radius": 0.14, "plies": 2, "twist_degrees": -25.5, "fuzz": 0.3,
     "diffuse_albedo": {"r": 0.8, "g": 0.1, "b": 0.1}, "specular_albedo": {"r": 0.04, "g": 0.04, "b": 0.04},
     "roughness": 0.6},
    {"name": "cream"}]
})";

constexpr std::string_view kWovenJson = R"({
  "woven": {"pattern": "WEAVE_PATTERN_TWILL", "n": 3, "m": 1, "inclination_degrees": 15, "gap_ratio": 0.1,
            "warp_colours": [0, 0, 1], "weftColours": [1]},
  "yarns": [{}, {"radius": 0.2}]
})";

constexpr std::string_view kPrecomputeJson = R"({
  "spatial_resolution": 64, "view_directions": 144, "light_directions": 100, "lobes": 3,
  "lookup_table": false, "mip_levels": "MIP_LEVELS_NONE", "lut_change_threshold": 0.05,
  "max_alternations": 12, "max_lm_iterations": 80, "indirect_bounces": 0, "supersampling": 4,
  "seed": "7", "half_float": false
})";

constexpr std::string_view kRenderJson = R"({
  "method": "RENDER_METHOD_REFERENCE", "width": 640, "height": 480, "msaa_samples": 8,
  "level_mode": "LEVEL_MODE_NEAREST", "shadow_map_size": 4096, "reference_samples": 256,
  "format": "IMAGE_FORMAT_EXR", "seed": "99"
})";

constexpr std::string_view kSceneJson = R"({
  "name": "studio",
  "objects": [
    {"name": "cloth", "mesh": {"builtin": "BUILTIN_SHAPE_DRAPE", "segments": 128},
     "transform": {"translation": {"x": 1, "y": 2, "z": 3}, "rotation_degrees": {"x": 90},
                   "scale": {"x": 2, "y": 2, "z": 2}},
     "fabric": {"fabric": {"woven": {"pattern": "WEAVE_PATTERN_SATIN", "n": 5, "m": 2}},
                "precompute": {"spatial_resolution": 16}, "repeat_u": 10, "repeat_v": 12.5},
     "base_colour": {"r": 0.5}},
    {"mesh": {"obj_path": "meshes/chair.obj"}},
    {"mesh": {"artifact": "9f86d081884c7d659a2feaa0c55ad015a3bf4f1b2b0b822cd15d6c15b0f00a08"}}],
  "camera": {"projection": "PROJECTION_ORTHOGRAPHIC", "position": {"y": -4, "z": 2}, "target": {"z": 0.5},
             "up": {"z": 1}, "fov_y_degrees": 35, "ortho_height": 3, "near": 0.1, "far": 50},
  "lights": [{"type": "LIGHT_TYPE_DIRECTIONAL", "direction": {"x": 1, "z": 1}, "colour": {"r": 1, "g": 0.9},
              "intensity": 3, "casts_shadows": true},
             {"type": "LIGHT_TYPE_POINT", "position": {"z": 5}, "intensity": 40}],
  "ambient": {"r": 0.02, "g": 0.02, "b": 0.03},
  "background": {"b": 0.1},
  "render": {"method": "RENDER_METHOD_SVBRDF", "width": 320, "height": 200, "format": "IMAGE_FORMAT_PNG"}
})";

// parse -> SpecToJson (pretty and compact) -> parse gives the same message.
template <typename Spec>
void ExpectRoundTrip(std::string_view json, std::string_view root) {
  const Spec original = ParseSpecJson<Spec>(json, root);
  for (const bool pretty : {true, false}) {
    const std::string printed = SpecToJson(original, pretty);
    const Spec reparsed = ParseSpecJson<Spec>(printed, root);
    std::string difference;
    MessageDifferencer differencer;
    differencer.ReportDifferencesToString(&difference);
    EXPECT_TRUE(differencer.Compare(original, reparsed)) << printed << "\n" << difference;
  }
}

// The message of the Error that parsing `json` throws ("" if it does not throw).
template <typename Spec>
std::string ParseError(std::string_view json, std::string_view root) {
  try {
    ParseSpecJson<Spec>(json, root);
  } catch (const Error& error) {
    EXPECT_EQ(error.code(), ErrorCode::kInvalidArgument);
    return error.what();
  }
  return "";
}

TEST(SpecJson, FabricRoundTrips) {
  ExpectRoundTrip<v1::FabricSpec>(kFabricJson, "fabric");
  ExpectRoundTrip<v1::FabricSpec>(kWovenJson, "fabric");
}

TEST(SpecJson, PrecomputeSettingsRoundTrip) { ExpectRoundTrip<v1::PrecomputeSettings>(kPrecomputeJson, "precompute"); }

TEST(SpecJson, RenderSettingsRoundTrip) { ExpectRoundTrip<v1::RenderSettings>(kRenderJson, "render"); }

TEST(SpecJson, SceneRoundTrips) { ExpectRoundTrip<v1::SceneSpec>(kSceneJson, "scene"); }

TEST(SpecJson, ParsesEveryFieldItIsGiven) {
  const auto fabric = ParseSpecJson<v1::FabricSpec>(kFabricJson, "fabric");
  EXPECT_EQ(fabric.knit().rib_knit(), 2u);  // lowerCamelCase spelling
  EXPECT_EQ(fabric.knit().seed(), 12345678901234u);
  EXPECT_EQ(fabric.knit().colour_pattern_size(), 4);
  EXPECT_FLOAT_EQ(fabric.yarns(0).twist_degrees(), -25.5f);
  const auto settings = ParseSpecJson<v1::PrecomputeSettings>(kPrecomputeJson, "precompute");
  EXPECT_TRUE(settings.has_indirect_bounces());  // explicit 0 is kept as present
  EXPECT_TRUE(settings.has_lookup_table());
  EXPECT_EQ(settings.mip_levels(), v1::MIP_LEVELS_NONE);
}

TEST(SpecJson, PrintsProtoFieldNames) {
  const std::string json = SpecToJson(ParseSpecJson<v1::FabricSpec>(kFabricJson, "fabric"), false);
  EXPECT_NE(json.find("\"rib_knit\":2"), std::string::npos) << json;
  EXPECT_EQ(json.find("ribKnit"), std::string::npos) << json;
  EXPECT_EQ(json.find('\n'), std::string::npos);
}

TEST(SpecJson, UnknownFieldNamesItsPath) {
  EXPECT_EQ(ParseError<v1::FabricSpec>(R"({"knit": {"ribKnitt": 2}})", "fabric"),
            "fabric.knit.ribKnitt: unknown field");
  EXPECT_EQ(ParseError<v1::SceneSpec>(R"({"objects": [{}, {"mesh": {"shape": 1}}]})", "scene"),
            "scene.objects[1].mesh.shape: unknown field");
}

TEST(SpecJson, BothMembersOfAOneofAreNamed) {
  EXPECT_EQ(ParseError<v1::FabricSpec>(R"({"knit": {}, "woven": {}})", "fabric"),
            "fabric: knit and woven are both set; give only one (oneof structure)");
  EXPECT_EQ(ParseError<v1::SceneSpec>(R"({"objects": [{"fabric": {"fabric": {"woven": {}, "knit": {}}}}]})", "scene"),
            "scene.objects[0].fabric.fabric: knit and woven are both set; give only one (oneof structure)");
}

// Protobuf reports a top-level unknown field without the "(path) " prefix.
TEST(SpecJson, TopLevelUnknownFieldNamesItsPath) {
  EXPECT_EQ(ParseError<v1::FabricSpec>(R"({"colour": "red"})", "fabric"), "fabric.colour: unknown field");
}

TEST(SpecJson, BadEnumNameNamesItsPath) {
  const std::string error = ParseError<v1::FabricSpec>(R"({"knit": {"pattern": "KNIT_PATTERN_CABLE"}})", "fabric");
  EXPECT_EQ(error.rfind("fabric.knit.pattern: ", 0), 0u) << error;
  EXPECT_NE(error.find("KNIT_PATTERN_CABLE"), std::string::npos) << error;
}

TEST(SpecJson, WrongTypeNamesItsPath) {
  std::string error = ParseError<v1::FabricSpec>(R"({"knit": {"wales": "many"}})", "fabric");
  EXPECT_EQ(error.rfind("fabric.knit.wales: ", 0), 0u) << error;
  error = ParseError<v1::FabricSpec>(R"({"knit": {}, "yarns": [{}, {"radius": "thick"}]})", "fabric");
  EXPECT_EQ(error.rfind("fabric.yarns[1].radius: ", 0), 0u) << error;
  error = ParseError<v1::PrecomputeSettings>(R"({"lobes": -1})", "precompute");
  EXPECT_EQ(error.rfind("precompute.lobes: ", 0), 0u) << error;
  error = ParseError<v1::SceneSpec>(R"({"camera": {"near": true}})", "scene");
  EXPECT_EQ(error.rfind("scene.camera.near: ", 0), 0u) << error;
}

TEST(SpecJson, SyntaxErrorNamesTheRoot) {
  const std::string error = ParseError<v1::FabricSpec>(R"({"knit": )", "fabric");
  EXPECT_EQ(error.rfind("fabric: ", 0), 0u) << error;
}

TEST(SpecJson, NonFiniteFloatsParse) {
  // Protobuf JSON spells them as strings; validation, not parsing, rejects them.
  const auto fabric = ParseSpecJson<v1::FabricSpec>(
      R"({"woven": {"gap_ratio": "NaN", "inclination_degrees": "-Infinity"}})", "fabric");
  EXPECT_TRUE(std::isnan(fabric.woven().gap_ratio()));
  EXPECT_TRUE(std::isinf(fabric.woven().inclination_degrees()));
}

TEST(SpecJson, LoadSpecFileNamesTheFile) {
  const std::filesystem::path dir =
      std::filesystem::temp_directory_path() / ("loom_spec_json_test_" + std::to_string(getpid()));
  const std::filesystem::path good = dir / "good.json", bad = dir / "bad.json";
  WriteFileAtomic(good, kFabricJson);
  WriteFileAtomic(bad, R"({"knit": {"wales": "many"}})");
  EXPECT_EQ(LoadSpecFile<v1::FabricSpec>(good, "fabric").knit().wales(), 8u);
  try {
    LoadSpecFile<v1::FabricSpec>(bad, "fabric");
    ADD_FAILURE() << "expected an Error";
  } catch (const Error& error) {
    EXPECT_EQ(error.code(), ErrorCode::kInvalidArgument);
    EXPECT_EQ(std::string(error.what()).rfind(bad.string() + ": fabric.knit.wales: ", 0), 0u) << error.what();
  }
  std::filesystem::remove_all(dir);
}

}  // namespace
}  // namespace loom
