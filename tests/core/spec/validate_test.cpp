#include "core/spec/validate.h"

#include <google/protobuf/util/message_differencer.h>
#include <gtest/gtest.h>

#include <nlohmann/json.hpp>
#include <string>
#include <string_view>

#include "core/spec/defaults.h"
#include "core/spec/limits.h"
#include "core/spec/spec_json.h"
#include "core/util/error.h"

namespace loom {
namespace {

using google::protobuf::util::MessageDifferencer;

template <typename Spec>
ValidationIssues ValidateJson(std::string_view json, const std::string& root) {
  return Validate(ParseSpecJson<Spec>(json, root), root);
}

// A valid scene: a plane seen from the front and above, no lights.
constexpr std::string_view kSceneBase = R"({
  "objects": [{"mesh": {"builtin": "BUILTIN_SHAPE_PLANE"}}],
  "camera": {"position": {"x": 0, "y": -3, "z": 2}}
})";

// kSceneBase with `patch` merged in (RFC 7396: arrays are replaced, null removes).
std::string SceneJson(std::string_view patch) {
  nlohmann::json json = nlohmann::json::parse(kSceneBase);
  json.merge_patch(nlohmann::json::parse(patch));
  return json.dump();
}

// "[{}, {}, ...]" with `count` copies of `element`.
std::string JsonArray(int count, std::string_view element) {
  std::string array = "[";
  for (int i = 0; i < count; ++i) array.append(i ? ", " : "").append(element);
  return array + "]";
}

bool HasIssue(const ValidationIssues& issues, std::string_view path, std::string_view message) {
  for (const ValidationIssue& issue : issues) {
    if (issue.path == path && issue.message == message) return true;
  }
  return false;
}

// --- One bad value, one issue: a table per spec type ---------------------------

// `json` holds exactly one bad value; validation must report exactly one issue.
struct RuleCase {
  const char* name;
  std::string json;
  const char* path;
  const char* message;
};

std::string CaseName(const testing::TestParamInfo<RuleCase>& info) { return info.param.name; }

void ExpectSingleIssue(const ValidationIssues& issues, const RuleCase& rule) {
  SCOPED_TRACE(rule.json);
  ASSERT_EQ(issues.size(), 1u) << FormatIssues(issues);
  EXPECT_EQ(issues[0].path, rule.path);
  EXPECT_EQ(issues[0].message, rule.message);
}

class FabricRule : public testing::TestWithParam<RuleCase> {};
TEST_P(FabricRule, ReportsPathAndLimit) {
  ExpectSingleIssue(ValidateJson<v1::FabricSpec>(GetParam().json, "fabric"), GetParam());
}

INSTANTIATE_TEST_SUITE_P(
    Validate, FabricRule,
    testing::Values(
        // Structure.
        RuleCase{"NoStructure", R"({})", "fabric", "one of knit or woven is required"},
        RuleCase{"TooManyYarns", R"({"knit": {}, "yarns": )" + JsonArray(17, "{}") + "}", "fabric.yarns",
                 "17 exceeds 16"},
        RuleCase{"NameTooLong", R"({"knit": {}, "name": ")" + std::string(257, 'a') + "\"}", "fabric.name",
                 "length 257 exceeds 256"},
        // Yarns.
        RuleCase{"YarnNameTooLong", R"({"knit": {}, "yarns": [{"name": ")" + std::string(300, 'y') + "\"}]}",
                 "fabric.yarns[0].name", "length 300 exceeds 256"},
        RuleCase{"RadiusTooLarge", R"({"woven": {}, "yarns": [{"radius": 0.7}]})", "fabric.yarns[0].radius",
                 "0.7 exceeds 0.5"},
        RuleCase{"KnitRadiusTooLarge", R"({"knit": {}, "yarns": [{"radius": 0.15}]})", "fabric.yarns[0].radius",
                 "0.15 exceeds 0.08 (for a knit: thicker yarns jam where loops interlock)"},
        RuleCase{"RadiusNegative", R"({"woven": {}, "yarns": [{}, {"radius": -0.1}]})", "fabric.yarns[1].radius",
                 "-0.1 is not above 0"},
        RuleCase{"TooManyPlies", R"({"knit": {}, "yarns": [{"plies": 9}]})", "fabric.yarns[0].plies", "9 exceeds 8"},
        RuleCase{"TwistTooLarge", R"({"knit": {}, "yarns": [{"twist_degrees": 91}]})", "fabric.yarns[0].twist_degrees",
                 "91 exceeds 90"},
        RuleCase{"TwistTooNegative", R"({"knit": {}, "yarns": [{"twist_degrees": -91}]})",
                 "fabric.yarns[0].twist_degrees", "-91 is below -90"},
        RuleCase{"FuzzTooLarge", R"({"knit": {}, "yarns": [{"fuzz": 1.5}]})", "fabric.yarns[0].fuzz", "1.5 exceeds 1"},
        RuleCase{"FuzzNegative", R"({"knit": {}, "yarns": [{"fuzz": -0.25}]})", "fabric.yarns[0].fuzz",
                 "-0.25 is below 0"},
        RuleCase{"DiffuseNegative", R"({"knit": {}, "yarns": [{"diffuse_albedo": {"r": -0.1}}]})",
                 "fabric.yarns[0].diffuse_albedo.r", "-0.1 is below 0"},
        RuleCase{"SpecularNegative", R"({"knit": {}, "yarns": [{"specular_albedo": {"b": -0.2}}]})",
                 "fabric.yarns[0].specular_albedo.b", "-0.2 is below 0"},
        RuleCase{"EnergyNotConserved",
                 R"({"knit": {}, "yarns": [{"diffuse_albedo": {"r": 0.9, "g": 0.9, "b": 0.9},
                                            "specular_albedo": {"r": 0.1, "g": 0.2, "b": 0.1}}]})",
                 "fabric.yarns[0]", "diffuse_albedo.g + specular_albedo.g = 1.1 exceeds 1 (energy conservation)"},
        RuleCase{"RoughnessTooLarge", R"({"knit": {}, "yarns": [{"roughness": 1.5}]})", "fabric.yarns[0].roughness",
                 "1.5 exceeds 1"},
        RuleCase{"RoughnessNegative", R"({"knit": {}, "yarns": [{"roughness": -1}]})", "fabric.yarns[0].roughness",
                 "-1 is not above 0"},
        RuleCase{"HeightScaleTooLarge",
                 R"({"woven": {}, "yarns": [{"shading": "YARN_SHADING_MICROFLAKE", "height_scale": 3}]})",
                 "fabric.yarns[0].height_scale", "3 exceeds 2"},
        RuleCase{"LambertBlendNegative",
                 R"({"woven": {}, "yarns": [{"shading": "YARN_SHADING_MICROFLAKE", "lambert_blend": -0.5}]})",
                 "fabric.yarns[0].lambert_blend", "-0.5 is below 0"},
        RuleCase{"DiffuseTransmissionTooLarge",
                 R"({"woven": {}, "yarns": [{"shading": "YARN_SHADING_MICROFLAKE", "diffuse_transmission": 1.5}]})",
                 "fabric.yarns[0].diffuse_transmission", "1.5 exceeds 1"},
        RuleCase{"DiffuseTransmissionWithKajiyaKay", R"({"woven": {}, "yarns": [{"diffuse_transmission": 0.5}]})",
                 "fabric.yarns[0].diffuse_transmission", "only for shading YARN_SHADING_MICROFLAKE"},
        RuleCase{"HeightScaleWithKajiyaKay", R"({"woven": {}, "yarns": [{"height_scale": 0.5}]})",
                 "fabric.yarns[0].height_scale", "only for shading YARN_SHADING_MICROFLAKE"},
        RuleCase{"UnknownYarnShading", R"({"woven": {}, "yarns": [{"shading": 7}]})", "fabric.yarns[0].shading",
                 "7 is not a known YarnShading value"},
        // Knit.
        RuleCase{"RibTooWide", R"({"knit": {"pattern": "KNIT_PATTERN_RIB", "rib_knit": 17}})", "fabric.knit.rib_knit",
                 "17 exceeds 16"},
        RuleCase{"RibWidthOutsideRib", R"({"knit": {"pattern": "KNIT_PATTERN_GARTER", "rib_purl": 2}})",
                 "fabric.knit.rib_purl", "must be 0 for garter (only rib patterns use it)"},
        RuleCase{"TooManyWales", R"({"knit": {"wales": 33}})", "fabric.knit.wales", "33 exceeds 32"},
        RuleCase{"TooManyCourses", R"({"knit": {"courses": 40}})", "fabric.knit.courses", "40 exceeds 32"},
        RuleCase{"GarterCoursesNotMultiple", R"({"knit": {"pattern": "KNIT_PATTERN_GARTER", "courses": 3}})",
                 "fabric.knit.courses", "3 is not a multiple of 2 (the garter pattern repeats every 2 courses)"},
        RuleCase{"RibWalesNotMultiple",
                 R"({"knit": {"pattern": "KNIT_PATTERN_RIB", "rib_knit": 2, "rib_purl": 1, "wales": 4}})",
                 "fabric.knit.wales", "4 is not a multiple of 3 (the rib pattern repeats every 3 wales)"},
        RuleCase{"SeedWalesNotMultiple", R"({"knit": {"pattern": "KNIT_PATTERN_SEED", "wales": 5}})",
                 "fabric.knit.wales", "5 is not a multiple of 2 (the seed pattern repeats every 2 wales)"},
        RuleCase{"LoopAspectTooSmall", R"({"knit": {"loop_aspect": 0.4}})", "fabric.knit.loop_aspect",
                 "0.4 is below 0.5"},
        RuleCase{"LoopAspectTooLarge", R"({"knit": {"loop_aspect": 1.6}})", "fabric.knit.loop_aspect",
                 "1.6 exceeds 1.5"},
        RuleCase{"LoopJitterTooLarge", R"({"knit": {"loop_jitter": 0.15}})", "fabric.knit.loop_jitter",
                 "0.15 exceeds 0.1"},
        RuleCase{"LoopJitterNegative", R"({"knit": {"loop_jitter": -0.5}})", "fabric.knit.loop_jitter",
                 "-0.5 is below 0"},
        RuleCase{"ColourPatternLongerThanTile", R"({"knit": {"wales": 2, "colour_pattern": [0, 0, 0]}})",
                 "fabric.knit.colour_pattern", "3 exceeds 2 (wales × courses)"},
        RuleCase{"ColourPatternYarnIndex", R"({"knit": {"wales": 2, "colour_pattern": [0, 2]}, "yarns": [{}, {}]})",
                 "fabric.knit.colour_pattern[1]", "2 exceeds 1 (the last yarn index)"},
        // Woven.
        RuleCase{"PlainWithN", R"({"woven": {"n": 2}})", "fabric.woven.n",
                 "must be 0 for plain (only twill, satin and basket weaves use it)"},
        RuleCase{"PlainWithM", R"({"woven": {"pattern": "WEAVE_PATTERN_PLAIN", "m": 1}})", "fabric.woven.m",
                 "must be 0 for plain (only twill and satin weaves use it)"},
        RuleCase{"TwillNTooLarge", R"({"woven": {"pattern": "WEAVE_PATTERN_TWILL", "n": 17}})", "fabric.woven.n",
                 "17 exceeds 16"},
        RuleCase{"TwillMTooLarge", R"({"woven": {"pattern": "WEAVE_PATTERN_TWILL", "m": 20}})", "fabric.woven.m",
                 "20 exceeds 16"},
        RuleCase{"SatinNTooSmall", R"({"woven": {"pattern": "WEAVE_PATTERN_SATIN", "n": 4}})", "fabric.woven.n",
                 "4 is below 5"},
        RuleCase{"SatinNTooLarge", R"({"woven": {"pattern": "WEAVE_PATTERN_SATIN", "n": 33, "m": 2}})",
                 "fabric.woven.n", "33 exceeds 32"},
        RuleCase{"SatinNWithoutMove", R"({"woven": {"pattern": "WEAVE_PATTERN_SATIN", "n": 6}})", "fabric.woven.n",
                 "6 has no valid satin move (no m with 1 < m < 5 and gcd(m, 6) = 1)"},
        RuleCase{"SatinMoveNotCoprime", R"({"woven": {"pattern": "WEAVE_PATTERN_SATIN", "n": 8, "m": 4}})",
                 "fabric.woven.m", "4 is not a valid satin move for n = 8 (need 1 < m < 7 and gcd(m, 8) = 1)"},
        RuleCase{"SatinMoveTooLarge", R"({"woven": {"pattern": "WEAVE_PATTERN_SATIN", "n": 5, "m": 4}})",
                 "fabric.woven.m", "4 is not a valid satin move for n = 5 (need 1 < m < 4 and gcd(m, 5) = 1)"},
        RuleCase{"SatinMoveOne", R"({"woven": {"pattern": "WEAVE_PATTERN_SATIN", "n": 7, "m": 1}})", "fabric.woven.m",
                 "1 is not a valid satin move for n = 7 (need 1 < m < 6 and gcd(m, 7) = 1)"},
        RuleCase{"BasketNTooLarge", R"({"woven": {"pattern": "WEAVE_PATTERN_BASKET", "n": 9}})", "fabric.woven.n",
                 "9 exceeds 8"},
        RuleCase{"BasketWithM", R"({"woven": {"pattern": "WEAVE_PATTERN_BASKET", "m": 2}})", "fabric.woven.m",
                 "must be 0 for basket (only twill and satin weaves use it)"},
        RuleCase{"InclinationTooLarge", R"({"woven": {"inclination_degrees": 61}})", "fabric.woven.inclination_degrees",
                 "61 exceeds 60"},
        RuleCase{"InclinationNegative", R"({"woven": {"inclination_degrees": -5}})", "fabric.woven.inclination_degrees",
                 "-5 is below 0"},
        RuleCase{"GapRatioAtLimit", R"({"woven": {"gap_ratio": 0.9}})", "fabric.woven.gap_ratio",
                 "0.9 is not below 0.9"},
        RuleCase{"GapRatioNegative", R"({"woven": {"gap_ratio": -0.1}})", "fabric.woven.gap_ratio", "-0.1 is below 0"},
        RuleCase{"WarpColoursTooLong", R"({"woven": {"warp_colours": )" + JsonArray(257, "0") + "}}",
                 "fabric.woven.warp_colours", "257 exceeds 256"},
        RuleCase{"WeftColourYarnIndex", R"({"woven": {"weft_colours": [0, 1]}})", "fabric.woven.weft_colours[1]",
                 "1 exceeds 0 (the last yarn index)"},
        // Every float is finite, every enum named, wherever it is.
        RuleCase{"NaN", R"({"knit": {"loop_aspect": "NaN"}})", "fabric.knit.loop_aspect", "NaN is not a finite number"},
        RuleCase{"InfinityInRepeatedNested", R"({"knit": {}, "yarns": [{}, {"diffuse_albedo": {"r": "Infinity"}}]})",
                 "fabric.yarns[1].diffuse_albedo.r", "Infinity is not a finite number"},
        RuleCase{"MinusInfinity", R"({"woven": {"gap_ratio": "-Infinity"}})", "fabric.woven.gap_ratio",
                 "-Infinity is not a finite number"},
        RuleCase{"UnknownEnumNumber", R"({"knit": {"pattern": 99}})", "fabric.knit.pattern",
                 "99 is not a known KnitPattern value"}),
    CaseName);

class PrecomputeRule : public testing::TestWithParam<RuleCase> {};
TEST_P(PrecomputeRule, ReportsPathAndLimit) {
  ExpectSingleIssue(ValidateJson<v1::PrecomputeSettings>(GetParam().json, "precompute"), GetParam());
}

INSTANTIATE_TEST_SUITE_P(
    Validate, PrecomputeRule,
    testing::Values(
        RuleCase{"ResolutionTooLarge", R"({"spatial_resolution": 512})", "precompute.spatial_resolution",
                 "512 exceeds 256"},
        RuleCase{"ResolutionTooSmall", R"({"spatial_resolution": 1})", "precompute.spatial_resolution", "1 is below 2"},
        RuleCase{"ResolutionNotPowerOfTwo", R"({"spatial_resolution": 48})", "precompute.spatial_resolution",
                 "48 is not a power of two (mip levels halve the resolution)"},
        RuleCase{"TooManyViewDirections", R"({"view_directions": 4225})", "precompute.view_directions",
                 "4225 exceeds 4096"},
        RuleCase{"TooFewLightDirections", R"({"light_directions": 1})", "precompute.light_directions", "1 is below 4"},
        RuleCase{"DirectionsNotSquare", R"({"spatial_resolution": 8, "light_directions": 4000})",
                 "precompute.light_directions", "4000 is not a perfect square (directions lie on a k×k grid)"},
        RuleCase{"TooManyRadianceSamples",
                 R"({"spatial_resolution": 64, "view_directions": 256, "light_directions": 256})", "precompute",
                 "spatial_resolution² × view_directions × light_directions = 268435456 radiance samples exceeds "
                 "67108864"},
        RuleCase{"TooManyLobes", R"({"lobes": 4})", "precompute.lobes", "4 exceeds 3"},
        RuleCase{"LutThresholdNegative", R"({"lut_change_threshold": -0.5})", "precompute.lut_change_threshold",
                 "-0.5 is not above 0"},
        RuleCase{"LutThresholdTooLarge", R"({"lut_change_threshold": 11})", "precompute.lut_change_threshold",
                 "11 exceeds 10"},
        RuleCase{"TooManyAlternations", R"({"max_alternations": 101})", "precompute.max_alternations",
                 "101 exceeds 100"},
        RuleCase{"TooManyLmIterations", R"({"max_lm_iterations": 1001})", "precompute.max_lm_iterations",
                 "1001 exceeds 1000"},
        RuleCase{"TooManyBounces", R"({"indirect_bounces": 3})", "precompute.indirect_bounces", "3 exceeds 2"},
        RuleCase{"ColourComponentsWithIndirectLight", R"({"colour_components": true})", "precompute.colour_components",
                 "needs indirect_bounces 0, not 1: light inter-reflected between yarns is not linear in their albedos"},
        RuleCase{"TooMuchSupersampling", R"({"supersampling": 9})", "precompute.supersampling", "9 exceeds 8"},
        RuleCase{"NaNThreshold", R"({"lut_change_threshold": "NaN"})", "precompute.lut_change_threshold",
                 "NaN is not a finite number"},
        RuleCase{"UnknownMipLevels", R"({"mip_levels": 7})", "precompute.mip_levels",
                 "7 is not a known MipLevels value"}),
    CaseName);

class RenderRule : public testing::TestWithParam<RuleCase> {};
TEST_P(RenderRule, ReportsPathAndLimit) {
  ExpectSingleIssue(ValidateJson<v1::RenderSettings>(GetParam().json, "render"), GetParam());
}

INSTANTIATE_TEST_SUITE_P(
    Validate, RenderRule,
    testing::Values(
        RuleCase{"Neural", R"({"method": "RENDER_METHOD_NEURAL"})", "render.method",
                 "RENDER_METHOD_NEURAL is not implemented yet (roadmap)"},
        RuleCase{"Auto", R"({"method": "RENDER_METHOD_AUTO"})", "render.method",
                 "RENDER_METHOD_AUTO is not implemented yet (roadmap)"},
        RuleCase{"WidthTooLarge", R"({"width": 9000})", "render.width", "9000 exceeds 8192"},
        RuleCase{"HeightTooLarge", R"({"height": 8193})", "render.height", "8193 exceeds 8192"},
        RuleCase{"TooManyPixels", R"({"width": 8192, "height": 8192})", "render",
                 "width × height = 67108864 pixels exceeds 33554432"},
        RuleCase{"MsaaNotPowerOfTwo", R"({"msaa_samples": 3})", "render.msaa_samples",
                 "3 is not one of 1, 2, 4, 8, 16"},
        RuleCase{"MsaaTooLarge", R"({"msaa_samples": 32})", "render.msaa_samples", "32 is not one of 1, 2, 4, 8, 16"},
        RuleCase{"ShadowMapNotPowerOfTwo", R"({"shadow_map_size": 3000})", "render.shadow_map_size",
                 "3000 is not a power of two"},
        RuleCase{"ShadowMapTooSmall", R"({"shadow_map_size": 128})", "render.shadow_map_size", "128 is below 256"},
        RuleCase{"ShadowMapTooLarge", R"({"shadow_map_size": 16384})", "render.shadow_map_size", "16384 exceeds 8192"},
        RuleCase{"TooManyReferenceSamples", R"({"reference_samples": 5000})", "render.reference_samples",
                 "5000 exceeds 4096"},
        RuleCase{"LodBiasTooFine", R"({"lod_bias": -4.5})", "render.lod_bias", "-4.5 is below -4"},
        RuleCase{"LodBiasTooCoarse", R"({"lod_bias": 5})", "render.lod_bias", "5 exceeds 4"},
        RuleCase{"LodBiasNotFinite", R"({"lod_bias": "NaN"})", "render.lod_bias", "NaN is not a finite number"},
        RuleCase{"UnknownFormat", R"({"format": 5})", "render.format", "5 is not a known ImageFormat value"},
        RuleCase{"UnknownShadingRate", R"({"shading_rate": 3})", "render.shading_rate",
                 "3 is not a known ShadingRate value"},
        RuleCase{"UnknownShadingPass", R"({"shading_pass": 3})", "render.shading_pass",
                 "3 is not a known ShadingPass value"}),
    CaseName);

class SceneRule : public testing::TestWithParam<RuleCase> {};
TEST_P(SceneRule, ReportsPathAndLimit) {
  ExpectSingleIssue(ValidateJson<v1::SceneSpec>(GetParam().json, "scene"), GetParam());
}

constexpr char kPlane[] = R"({"mesh": {"builtin": "BUILTIN_SHAPE_PLANE"}})";

// A scene whose only object is a plane carrying `binding`.
std::string BoundPlane(std::string_view binding) {
  return SceneJson(R"({"objects": [{"mesh": {"builtin": "BUILTIN_SHAPE_PLANE"}, "fabric": )" + std::string(binding) +
                   "}]}");
}

INSTANTIATE_TEST_SUITE_P(
    Validate, SceneRule,
    testing::Values(
        RuleCase{"NameTooLong", SceneJson(R"({"name": ")" + std::string(257, 's') + "\"}"), "scene.name",
                 "length 257 exceeds 256"},
        RuleCase{"NoObjects", SceneJson(R"({"objects": []})"), "scene.objects", "0 is below 1"},
        RuleCase{"TooManyObjects", SceneJson(R"({"objects": )" + JsonArray(65, kPlane) + "}"), "scene.objects",
                 "65 exceeds 64"},
        RuleCase{"ObjectNameTooLong",
                 SceneJson(R"({"objects": [{"name": ")" + std::string(257, 'o') +
                           R"(", "mesh": {"builtin": "BUILTIN_SHAPE_SPHERE"}}]})"),
                 "scene.objects[0].name", "length 257 exceeds 256"},
        // Meshes.
        RuleCase{"NoMesh", SceneJson(R"({"objects": [{}]})"), "scene.objects[0].mesh",
                 "one of builtin, obj_path, gltf_path or artifact is required"},
        RuleCase{"UnspecifiedBuiltin",
                 SceneJson(R"({"objects": [{"mesh": {"builtin": "BUILTIN_SHAPE_UNSPECIFIED"}}]})"),
                 "scene.objects[0].mesh.builtin", "BUILTIN_SHAPE_UNSPECIFIED is not a shape"},
        RuleCase{"EmptyObjPath", SceneJson(R"({"objects": [{"mesh": {"obj_path": ""}}]})"),
                 "scene.objects[0].mesh.obj_path", "is empty"},
        RuleCase{"ObjPathTooLong",
                 SceneJson(R"({"objects": [{"mesh": {"obj_path": ")" + std::string(4097, 'p') + "\"}}]}"),
                 "scene.objects[0].mesh.obj_path", "length 4097 exceeds 4096"},
        RuleCase{"EmptyGltfPath", SceneJson(R"({"objects": [{"mesh": {"gltf_path": ""}}]})"),
                 "scene.objects[0].mesh.gltf_path", "is empty"},
        RuleCase{"FramePastTheLimit", SceneJson(R"({"objects": [{"mesh": {"gltf_path": "a.glb", "frame": 3001}}]})"),
                 "scene.objects[0].mesh.frame", "3001 exceeds 3000"},
        RuleCase{"FrameOfAnObj", SceneJson(R"({"objects": [{"mesh": {"obj_path": "a.obj", "frame": 2}}]})"),
                 "scene.objects[0].mesh.frame", "applies to glTF mesh sequences only"},
        RuleCase{"GltfMeshOfAnObj", SceneJson(R"({"objects": [{"mesh": {"obj_path": "a.obj", "gltf_mesh": "ball"}}]})"),
                 "scene.objects[0].mesh.gltf_mesh", "applies to glTF meshes only"},
        RuleCase{"ArtifactNotHex", SceneJson(R"({"objects": [{"mesh": {"artifact": "abc"}}]})"),
                 "scene.objects[0].mesh.artifact", "is not a content hash (64 lowercase hex digits)"},
        RuleCase{"ArtifactUppercase",
                 SceneJson(R"({"objects": [{"mesh": {"artifact": ")" + std::string(64, 'A') + "\"}}]}"),
                 "scene.objects[0].mesh.artifact", "is not a content hash (64 lowercase hex digits)"},
        RuleCase{"TooManySegments",
                 SceneJson(R"({"objects": [{"mesh": {"builtin": "BUILTIN_SHAPE_SPHERE", "segments": 2000}}]})"),
                 "scene.objects[0].mesh.segments", "2000 exceeds 1024"},
        // Objects.
        RuleCase{"ZeroScaleComponent", SceneJson(R"({"objects": [{"mesh": {"builtin": "BUILTIN_SHAPE_PLANE"},
                                            "transform": {"scale": {"x": 1, "z": 1}}}]})"),
                 "scene.objects[0].transform.scale.y", "must not be zero (a zero scale flattens the object)"},
        RuleCase{"BaseColourTooBright", SceneJson(R"({"objects": [{"mesh": {"builtin": "BUILTIN_SHAPE_PLANE"},
                                            "base_colour": {"r": 1.5}}]})"),
                 "scene.objects[0].base_colour.r", "1.5 exceeds 1"},
        RuleCase{"BindingWithoutFabric", BoundPlane("{}"), "scene.objects[0].fabric.fabric",
                 "one of knit or woven is required"},
        RuleCase{"BindingFabric", BoundPlane(R"({"fabric": {"woven": {}, "yarns": [{"radius": 0.7}]}})"),
                 "scene.objects[0].fabric.fabric.yarns[0].radius", "0.7 exceeds 0.5"},
        RuleCase{"BindingPrecompute", BoundPlane(R"({"fabric": {"woven": {}}, "precompute": {"lobes": 5}})"),
                 "scene.objects[0].fabric.precompute.lobes", "5 exceeds 3"},
        RuleCase{"RepeatTooLarge", BoundPlane(R"({"fabric": {"woven": {}}, "repeat_u": 5000})"),
                 "scene.objects[0].fabric.repeat_u", "5000 exceeds 4096"},
        RuleCase{"RepeatNegative", BoundPlane(R"({"fabric": {"woven": {}}, "repeat_v": -1})"),
                 "scene.objects[0].fabric.repeat_v", "-1 is not above 0"},
        // Camera.
        RuleCase{"CameraAtTarget", SceneJson(R"({"camera": {"position": null}})"), "scene.camera.target",
                 "equals position (the camera needs a view direction)"},
        RuleCase{"UpAlongView", SceneJson(R"({"camera": {"position": {"y": 0, "z": 3}}})"), "scene.camera.up",
                 "(0, 0, 1) is parallel to the view direction (0, 0, -3)"},
        RuleCase{"FovTooLarge", SceneJson(R"({"camera": {"fov_y_degrees": 170}})"), "scene.camera.fov_y_degrees",
                 "170 is not below 170"},
        RuleCase{"FovNegative", SceneJson(R"({"camera": {"fov_y_degrees": -10}})"), "scene.camera.fov_y_degrees",
                 "-10 is not above 0"},
        RuleCase{"OrthoHeightNegative", SceneJson(R"({"camera": {"ortho_height": -1}})"), "scene.camera.ortho_height",
                 "-1 is not above 0"},
        RuleCase{"NearNegative", SceneJson(R"({"camera": {"near": -0.1}})"), "scene.camera.near",
                 "-0.1 is not above 0"},
        RuleCase{"FarBeforeNear", SceneJson(R"({"camera": {"near": 1, "far": 0.5}})"), "scene.camera.far",
                 "0.5 is not above 1 (near)"},
        // Lights.
        RuleCase{"TooManyLights", SceneJson(R"({"lights": )" + JsonArray(17, R"({"direction": {"z": 1}})") + "}"),
                 "scene.lights", "17 exceeds 16"},
        RuleCase{"DirectionalWithoutDirection", SceneJson(R"({"lights": [{"intensity": 2}]})"),
                 "scene.lights[0].direction", "is zero (a directional light needs a direction)"},
        RuleCase{"NegativeIntensity", SceneJson(R"({"lights": [{"direction": {"z": 1}, "intensity": -1}]})"),
                 "scene.lights[0].intensity", "-1 is below 0"},
        RuleCase{"NegativeLightColour",
                 SceneJson(R"({"lights": [{"type": "LIGHT_TYPE_POINT", "colour": {"r": 1, "g": -0.5, "b": 1}}]})"),
                 "scene.lights[0].colour.g", "-0.5 is below 0"},
        // Environment and render settings.
        RuleCase{"NegativeAmbient", SceneJson(R"({"ambient": {"r": -0.1}})"), "scene.ambient.r", "-0.1 is below 0"},
        RuleCase{"NegativeBackground", SceneJson(R"({"background": {"b": -1}})"), "scene.background.b",
                 "-1 is below 0"},
        RuleCase{"RenderSettings", SceneJson(R"({"render": {"width": 9000}})"), "scene.render.width",
                 "9000 exceeds 8192"},
        RuleCase{"NaNCameraPosition", SceneJson(R"({"camera": {"position": {"x": "NaN"}}})"), "scene.camera.position.x",
                 "NaN is not a finite number"},
        RuleCase{"InfiniteLightIntensity",
                 SceneJson(R"({"lights": [{"direction": {"z": 1}, "intensity": "Infinity"}]})"),
                 "scene.lights[0].intensity", "Infinity is not a finite number"},
        RuleCase{"NaNInBindingFabric", BoundPlane(R"({"fabric": {"woven": {}, "yarns": [{"roughness": "NaN"}]}})"),
                 "scene.objects[0].fabric.fabric.yarns[0].roughness", "NaN is not a finite number"}),
    CaseName);

// --- Defaults validate clean ---------------------------------------------------

// A valid animation: a 4 × 6 cloth for 1 s.
constexpr std::string_view kAnimationBase = R"({"cloth": {"loops": 4, "courses": 6}, "duration_seconds": 1})";

std::string AnimationJson(std::string_view patch) {
  nlohmann::json json = nlohmann::json::parse(kAnimationBase);
  json.merge_patch(nlohmann::json::parse(patch));
  return json.dump();
}

class AnimationRule : public testing::TestWithParam<RuleCase> {};
TEST_P(AnimationRule, ReportsPathAndLimit) {
  ExpectSingleIssue(ValidateJson<v1::AnimationSpec>(GetParam().json, "animation"), GetParam());
}

INSTANTIATE_TEST_SUITE_P(
    Validate, AnimationRule,
    testing::Values(
        RuleCase{"ZeroLoops", AnimationJson(R"({"cloth": {"loops": 0}})"), "animation.cloth.loops", "0 is below 2"},
        RuleCase{"TooManyCourses", AnimationJson(R"({"cloth": {"courses": 5000}})"), "animation.cloth.courses",
                 "5000 exceeds 2048"},
        RuleCase{"TooManyLoops",
                 AnimationJson(R"({"cloth": {"loops": 1024, "courses": 1024}, "duration_seconds": 0.04})"),
                 "animation.cloth.courses", "1048576 exceeds 262144 (loops × courses)"},
        RuleCase{"NegativeSpacing", AnimationJson(R"({"cloth": {"wale_spacing": -1}})"), "animation.cloth.wale_spacing",
                 "-1 is not above 0"},
        RuleCase{"ParallelAxes", AnimationJson(R"({"cloth": {"course_axis": {"x": 1}, "wale_axis": {"x": 2}}})"),
                 "animation.cloth.wale_axis", "(2, 0, 0) is parallel to course_axis (1, 0, 0)"},
        RuleCase{"WovenCloth", AnimationJson(R"({"cloth": {"fabric": {"woven": {}}}})"), "animation.cloth.fabric",
                 "must be a knit fabric (the cloth is knitted)"},
        RuleCase{"NegativeDuration", AnimationJson(R"({"duration_seconds": -1})"), "animation.duration_seconds",
                 "-1 is not above 0"},
        RuleCase{"NoDuration", AnimationJson(R"({"duration_seconds": null})"), "animation.duration_seconds",
                 "0 is not above 0"},
        RuleCase{"LongDuration", AnimationJson(R"({"duration_seconds": 700, "frames_per_second": 1})"),
                 "animation.duration_seconds", "700 exceeds 600"},
        RuleCase{"NaNDuration", AnimationJson(R"({"duration_seconds": "NaN"})"), "animation.duration_seconds",
                 "NaN is not a finite number"},
        RuleCase{"FastFrames", AnimationJson(R"({"frames_per_second": 500})"), "animation.frames_per_second",
                 "500 exceeds 120"},
        RuleCase{"AbsurdFrameCount", AnimationJson(R"({"duration_seconds": 600, "frames_per_second": 120})"),
                 "animation.frames_per_second", "120 frames a second for 600 s make 72000 frames; at most 3000"},
        RuleCase{"TooManyPoints", AnimationJson(R"({"cloth": {"loops": 512, "courses": 512}, "duration_seconds": 20})"),
                 "animation.duration_seconds", "501 frames of 512 × 512 loops make 131334144 points; at most 67108864"},
        RuleCase{"FastThrow", AnimationJson(R"({"initial_velocity": {"x": 2000}})"), "animation.initial_velocity.x",
                 "2000 exceeds 1000"},
        RuleCase{"PinPastTheCloth", AnimationJson(R"({"pins": [{"course": 6}]})"), "animation.pins[0].course",
                 "6 exceeds 5 (cloth.courses − 1)"},
        RuleCase{"PinLoopPastTheCloth", AnimationJson(R"({"pins": [{"loop": {"loop": 4, "course": 0}}]})"),
                 "animation.pins[0].loop.loop", "4 exceeds 3 (cloth.loops − 1)"},
        RuleCase{"PinNothing", AnimationJson(R"({"pins": [{}]})"), "animation.pins[0]",
                 "names no loop, course or wale"},
        RuleCase{"PinTwice", AnimationJson(R"({"pins": [{"course": 0}, {"loop": {"loop": 1}}]})"), "animation.pins[1]",
                 "pins loop (1, 0), which pins[0] pins already"},
        RuleCase{"ReleaseAfterTheEnd", AnimationJson(R"({"pins": [{"wale": 0, "release_seconds": 2}]})"),
                 "animation.pins[0].release_seconds", "2 exceeds 1 (duration_seconds)"},
        RuleCase{"MotionBackwards",
                 AnimationJson(R"({"pins": [{"wale": 0, "motion": [{"start_seconds": 0.5, "end_seconds": 0.25}]}]})"),
                 "animation.pins[0].motion[0].end_seconds", "0.25 is below 0.5 (start_seconds)"},
        RuleCase{"NoShape", AnimationJson(R"({"colliders": [{}]})"), "animation.colliders[0]",
                 "names no plane, sphere, box or mesh"},
        RuleCase{"FlatSphere", AnimationJson(R"({"colliders": [{"sphere": {}}]})"),
                 "animation.colliders[0].sphere.radius", "0 is not above 0"},
        RuleCase{"NegativeBallMass", AnimationJson(R"({"colliders": [{"sphere": {"radius": 1, "mass": -1}}]})"),
                 "animation.colliders[0].sphere.mass", "-1 is below 0"},
        RuleCase{"BallReleasedAfterTheEnd",
                 AnimationJson(R"({"colliders": [{"sphere": {"radius": 1, "mass": 1, "release_seconds": 3}}]})"),
                 "animation.colliders[0].sphere.release_seconds", "3 exceeds 1 (duration_seconds)"},
        RuleCase{"ReleasedWithoutMass",
                 AnimationJson(R"({"colliders": [{"sphere": {"radius": 1, "release_seconds": 0.5}}]})"),
                 "animation.colliders[0].sphere.release_seconds", "lets go a sphere without a mass (set mass)"},
        RuleCase{"MeshColliderWithoutMesh", AnimationJson(R"({"colliders": [{"mesh": {}}]})"),
                 "animation.colliders[0].mesh.mesh", "one of builtin, obj_path, gltf_path or artifact is required"},
        RuleCase{"FlatMeshCollider",
                 AnimationJson(R"({"colliders": [{"mesh": {"mesh": {"obj_path": "chair.obj"},
                                                            "transform": {"scale": {"x": 1, "y": 1}}}}]})"),
                 "animation.colliders[0].mesh.transform.scale.z",
                 "must not be zero (a zero scale flattens the object)"},
        RuleCase{"NegativeDamping", AnimationJson(R"({"mechanics": {"contact_damping": -1}})"),
                 "animation.mechanics.contact_damping", "-1 is below 0"},
        RuleCase{"AbsurdFriction", AnimationJson(R"({"mechanics": {"dynamic_friction": 11}})"),
                 "animation.mechanics.dynamic_friction", "11 exceeds 10"},
        RuleCase{"ZeroCourant", AnimationJson(R"({"mechanics": {"courant": 0}})"), "animation.mechanics.courant",
                 "0 is not above 0"},
        RuleCase{"UnstableCourant", AnimationJson(R"({"mechanics": {"courant": 2}})"), "animation.mechanics.courant",
                 "2 exceeds 1"},
        RuleCase{"PlaneWithoutNormal", AnimationJson(R"({"colliders": [{"plane": {}}]})"),
                 "animation.colliders[0].plane.normal", "is zero"},
        RuleCase{"HugeBox", AnimationJson(R"({"colliders": [{"box": {"half_extent": {"x": 1, "y": 1, "z": 20000}}}]})"),
                 "animation.colliders[0].box.half_extent.z", "20000 exceeds 10000"}),
    CaseName);

TEST(Validate, DefaultAnimationIsValid) {
  EXPECT_TRUE(ValidateJson<v1::AnimationSpec>(kAnimationBase, "animation").empty());
}

TEST(Validate, EmptyKnitAndWovenFabricsAreValid) {
  EXPECT_EQ(FormatIssues(ValidateJson<v1::FabricSpec>(R"({"knit": {}})", "fabric")), "");
  EXPECT_EQ(FormatIssues(ValidateJson<v1::FabricSpec>(R"({"woven": {}})", "fabric")), "");
}

TEST(Validate, EveryPatternWithDefaultsIsValid) {
  for (const char* pattern : {"STOCKINETTE", "REVERSE", "GARTER", "RIB", "SEED"}) {
    const std::string json = std::string(R"({"knit": {"pattern": "KNIT_PATTERN_)") + pattern + "\"}}";
    EXPECT_EQ(FormatIssues(ValidateJson<v1::FabricSpec>(json, "fabric")), "") << json;
  }
  for (const char* pattern : {"PLAIN", "TWILL", "SATIN", "BASKET"}) {
    const std::string json = std::string(R"({"woven": {"pattern": "WEAVE_PATTERN_)") + pattern + "\"}}";
    EXPECT_EQ(FormatIssues(ValidateJson<v1::FabricSpec>(json, "fabric")), "") << json;
  }
}

TEST(Validate, DefaultSettingsAreValid) {
  EXPECT_EQ(FormatIssues(Validate(v1::PrecomputeSettings())), "");
  EXPECT_EQ(FormatIssues(Validate(v1::RenderSettings())), "");
}

TEST(Validate, DefaultSceneWithOnePlaneIsValid) {
  EXPECT_EQ(FormatIssues(ValidateJson<v1::SceneSpec>(kSceneBase, "scene")), "");
}

TEST(Validate, RichValidSceneIsValid) {
  const std::string json = SceneJson(R"({
    "name": "sofa",
    "objects": [
      {"name": "cloth", "mesh": {"builtin": "BUILTIN_SHAPE_DRAPE", "segments": 64},
       "transform": {"translation": {"z": 0.5}, "rotation_degrees": {"z": 30}, "scale": {"x": 2, "y": 2, "z": -1}},
       "fabric": {"fabric": {"woven": {"pattern": "WEAVE_PATTERN_SATIN", "n": 8, "m": 3, "gap_ratio": 0.2,
                                       "warp_colours": [0, 1], "weft_colours": [1]},
                             "yarns": [{"name": "navy"}, {"name": "gold", "plies": 3, "twist_degrees": -30,
                                                          "diffuse_albedo": {"r": 0.8, "g": 0.6, "b": 0.1}}]},
                  "precompute": {"spatial_resolution": 16, "lobes": 1, "indirect_bounces": 0},
                  "repeat_u": 12, "repeat_v": 8}},
      {"mesh": {"artifact": "9f86d081884c7d659a2feaa0c55ad015a3bf4f1b2b0b822cd15d6c15b0f00a08"},
       "base_colour": {"r": 0.2, "g": 0.2, "b": 0.2}},
      {"mesh": {"obj_path": "meshes/chair.obj"}}],
    "camera": {"projection": "PROJECTION_ORTHOGRAPHIC", "target": {"z": 0.5}, "ortho_height": 3},
    "lights": [{"direction": {"x": 1, "y": -1, "z": 2}, "casts_shadows": true},
               {"type": "LIGHT_TYPE_POINT", "position": {"z": 4}, "intensity": 20}],
    "ambient": {"r": 0.05, "g": 0.05, "b": 0.05},
    "render": {"method": "RENDER_METHOD_REFERENCE", "width": 256, "height": 256, "msaa_samples": 1,
               "format": "IMAGE_FORMAT_EXR"}
  })");
  EXPECT_EQ(FormatIssues(ValidateJson<v1::SceneSpec>(json, "scene")), "");
}

TEST(Validate, ZeroIsARealValueWhereItMeansZero) {
  const auto fabric = ParseSpecJson<v1::FabricSpec>(
      R"({"woven": {"gap_ratio": 0}, "yarns": [{"twist_degrees": 0, "fuzz": 0}]})", "fabric");
  EXPECT_TRUE(Validate(fabric).empty());
  const v1::FabricSpec full = WithDefaults(fabric);
  EXPECT_EQ(full.woven().gap_ratio(), 0);
  EXPECT_EQ(full.yarns(0).twist_degrees(), 0);
  EXPECT_EQ(full.yarns(0).fuzz(), 0);

  const auto settings = ParseSpecJson<v1::PrecomputeSettings>(
      R"({"indirect_bounces": 0, "lookup_table": false, "half_float": false})", "precompute");
  EXPECT_TRUE(Validate(settings).empty());
  EXPECT_EQ(WithDefaults(settings).indirect_bounces(), 0u);
  EXPECT_FALSE(WithDefaults(settings).lookup_table());
  EXPECT_FALSE(WithDefaults(settings).half_float());
}

TEST(Validate, LumisliceRendersKnitCloth) {
  const std::string cloth = R"({"objects": [{"mesh": {"builtin": "BUILTIN_SHAPE_PLANE"}, "fabric": {"fabric": )";
  const std::string render = R"(}}], "render": {"method": "RENDER_METHOD_LUMISLICE"}})";
  EXPECT_EQ(FormatIssues(ValidateJson<v1::SceneSpec>(SceneJson(cloth + R"({"knit": {}})" + render), "scene")), "");
  EXPECT_EQ(FormatIssues(ValidateJson<v1::SceneSpec>(SceneJson(cloth + R"({"woven": {}})" + render), "scene")),
            "scene.objects[0].fabric.fabric: RENDER_METHOD_LUMISLICE renders knit fabrics only");
}

// msaa_samples are lumislice's rays a pixel on the nearest square grid; the frame that
// many times larger must fit the frame limits.
TEST(Validate, LumisliceRaysAPixelFitTheFrameLimits) {
  EXPECT_EQ(LumisliceRayGrid(1), 1u);
  EXPECT_EQ(LumisliceRayGrid(2), 1u);
  EXPECT_EQ(LumisliceRayGrid(4), 2u);
  EXPECT_EQ(LumisliceRayGrid(8), 3u);
  EXPECT_EQ(LumisliceRayGrid(16), 4u);
  const std::string cloth =
      R"({"objects": [{"mesh": {"builtin": "BUILTIN_SHAPE_PLANE"}, "fabric": {"fabric": {"knit": {}}}}],
      "render": {"method": "RENDER_METHOD_LUMISLICE", )";
  EXPECT_EQ(FormatIssues(ValidateJson<v1::SceneSpec>(
                SceneJson(cloth + R"("width": 2048, "height": 1024, "msaa_samples": 16}})"), "scene")),
            "");
  EXPECT_EQ(FormatIssues(ValidateJson<v1::SceneSpec>(
                SceneJson(cloth + R"("width": 4096, "height": 2048, "msaa_samples": 4}})"), "scene")),
            "");
  EXPECT_EQ(FormatIssues(ValidateJson<v1::SceneSpec>(
                SceneJson(cloth + R"("width": 4096, "height": 2048, "msaa_samples": 8}})"), "scene")),
            "scene.render.msaa_samples: 8 rays a pixel (3 × 3) make RENDER_METHOD_LUMISLICE render 12288 × 6144 "
            "pixels: at most 8192 a side and 33554432 in all");
}

TEST(Validate, PointLightNeedsNoDirection) {
  const std::string json = SceneJson(R"({"lights": [{"type": "LIGHT_TYPE_POINT", "position": {"z": 3}}]})");
  EXPECT_EQ(FormatIssues(ValidateJson<v1::SceneSpec>(json, "scene")), "");
}

TEST(Validate, AlbedosSummingToOneConserveEnergy) {
  const std::string json =
      R"({"knit": {}, "yarns": [{"diffuse_albedo": {"r": 0.96, "g": 0.96, "b": 0.96}}]})";  // + 0.04 specular
  EXPECT_EQ(FormatIssues(ValidateJson<v1::FabricSpec>(json, "fabric")), "");
}

// --- Several problems, paths and formatting ---------------------------------------

TEST(Validate, ReportsEveryProblemAtOnce) {
  const ValidationIssues issues = ValidateJson<v1::FabricSpec>(R"({
    "knit": {"pattern": "KNIT_PATTERN_GARTER", "courses": 3, "loop_aspect": 3},
    "yarns": [{"radius": 0.7, "diffuse_albedo": {"r": 1.2}, "specular_albedo": {}},
              {"plies": 9, "roughness": "NaN"}]
  })",
                                                               "fabric");
  EXPECT_EQ(issues.size(), 7u) << FormatIssues(issues);
  EXPECT_TRUE(HasIssue(issues, "fabric.yarns[1].roughness", "NaN is not a finite number"));
  EXPECT_TRUE(HasIssue(issues, "fabric.yarns[0].radius",
                       "0.7 exceeds 0.08 (for a knit: thicker yarns jam where loops interlock)"));
  EXPECT_TRUE(HasIssue(issues, "fabric.yarns[0].diffuse_albedo.r", "1.2 exceeds 1"));
  EXPECT_TRUE(HasIssue(issues, "fabric.yarns[0]",
                       "diffuse_albedo.r + specular_albedo.r = 1.2 exceeds 1 (energy conservation)"));
  EXPECT_TRUE(HasIssue(issues, "fabric.yarns[1].plies", "9 exceeds 8"));
  EXPECT_TRUE(
      HasIssue(issues, "fabric.knit.courses", "3 is not a multiple of 2 (the garter pattern repeats every 2 courses)"));
  EXPECT_TRUE(HasIssue(issues, "fabric.knit.loop_aspect", "3 exceeds 1.5"));
}

TEST(Validate, SceneReportsProblemsInEveryPart) {
  const ValidationIssues issues = ValidateJson<v1::SceneSpec>(
      BoundPlane(R"({"fabric": {"knit": {"wales": 64}}, "precompute": {"view_directions": 10}})"), "scene");
  EXPECT_EQ(issues.size(), 2u) << FormatIssues(issues);
  EXPECT_TRUE(HasIssue(issues, "scene.objects[0].fabric.fabric.knit.wales", "64 exceeds 32"));
  EXPECT_TRUE(HasIssue(issues, "scene.objects[0].fabric.precompute.view_directions",
                       "10 is not a perfect square (directions lie on a k×k grid)"));
}

TEST(Validate, PathsStartAtTheGivenRoot) {
  v1::FabricSpec fabric;
  fabric.mutable_knit()->set_wales(33);
  const ValidationIssues issues = Validate(fabric, "job.precompute.fabric");
  ASSERT_EQ(issues.size(), 1u);
  EXPECT_EQ(issues[0].path, "job.precompute.fabric.knit.wales");
  EXPECT_EQ(issues[0].ToString(), "job.precompute.fabric.knit.wales: 33 exceeds 32");
}

TEST(Validate, FormatIssuesWritesOneLinePerIssue) {
  const ValidationIssues issues = {{"a.b", "1 exceeds 0"}, {"c[2]", "is empty"}};
  EXPECT_EQ(FormatIssues(issues), "a.b: 1 exceeds 0\nc[2]: is empty");
  EXPECT_EQ(FormatIssues({}), "");
}

TEST(Validate, ThrowIfAnyThrowsInvalidArgumentWithEveryIssue) {
  EXPECT_NO_THROW(ThrowIfAny({}));
  v1::PrecomputeSettings settings;
  settings.set_lobes(4);
  settings.set_supersampling(9);
  try {
    ValidateOrThrow(settings);
    FAIL() << "expected an Error";
  } catch (const Error& error) {
    EXPECT_EQ(error.code(), ErrorCode::kInvalidArgument);
    EXPECT_STREQ(error.what(), "precompute.lobes: 4 exceeds 3\nprecompute.supersampling: 9 exceeds 8");
  }
}

// --- Defaults --------------------------------------------------------------------

template <typename Spec>
void ExpectIdempotent(const std::string& json, std::string_view root) {
  const Spec once = WithDefaults(ParseSpecJson<Spec>(json, root));
  const Spec twice = WithDefaults(once);
  std::string difference;
  MessageDifferencer differencer;
  differencer.ReportDifferencesToString(&difference);
  EXPECT_TRUE(differencer.Compare(once, twice)) << json << "\n" << difference;
}

TEST(Defaults, WithDefaultsIsIdempotent) {
  for (const char* json : {R"({})", R"({"knit": {}})", R"({"woven": {}})",
                           R"({"knit": {"pattern": "KNIT_PATTERN_RIB", "rib_knit": 2},
                               "yarns": [{}, {"radius": 0.05}]})",
                           R"({"woven": {"pattern": "WEAVE_PATTERN_SATIN", "n": 8}})",
                           R"({"woven": {"pattern": "WEAVE_PATTERN_SATIN", "n": 6}})",
                           R"({"woven": {"pattern": "WEAVE_PATTERN_TWILL"}})"}) {
    ExpectIdempotent<v1::FabricSpec>(json, "fabric");
  }
  ExpectIdempotent<v1::PrecomputeSettings>("{}", "precompute");
  ExpectIdempotent<v1::PrecomputeSettings>(R"({"indirect_bounces": 0, "lookup_table": false})", "precompute");
  ExpectIdempotent<v1::RenderSettings>("{}", "render");
  ExpectIdempotent<v1::SceneSpec>("{}", "scene");
  ExpectIdempotent<v1::SceneSpec>(BoundPlane(R"({"fabric": {"knit": {}}, "precompute": {}})"), "scene");
  ExpectIdempotent<v1::SceneSpec>(SceneJson(R"({"lights": [{}, {"type": "LIGHT_TYPE_POINT"}]})"), "scene");
}

TEST(Defaults, PrecomputeSettings) {
  const v1::PrecomputeSettings s = WithDefaults(v1::PrecomputeSettings());
  EXPECT_EQ(s.spatial_resolution(), 32u);
  EXPECT_EQ(s.view_directions(), 64u);
  EXPECT_EQ(s.light_directions(), 64u);
  EXPECT_EQ(s.lobes(), 2u);
  EXPECT_TRUE(s.has_lookup_table() && s.lookup_table());
  EXPECT_EQ(s.mip_levels(), v1::MIP_LEVELS_AUTO);
  EXPECT_FLOAT_EQ(s.lut_change_threshold(), 0.1f);
  EXPECT_EQ(s.max_alternations(), 8u);
  EXPECT_EQ(s.max_lm_iterations(), 50u);
  EXPECT_TRUE(s.has_indirect_bounces());
  EXPECT_EQ(s.indirect_bounces(), 1u);
  EXPECT_EQ(s.supersampling(), 2u);
  EXPECT_TRUE(s.has_half_float() && s.half_float());
  EXPECT_EQ(s.seed(), 0u);
  for (const v1::FabricMethod method :
       {v1::FABRIC_METHOD_TABULATED, v1::FABRIC_METHOD_FACTORED, v1::FABRIC_METHOD_NEURAL}) {
    v1::PrecomputeSettings table;
    table.set_method(method);
    table = WithDefaults(table);
    EXPECT_EQ(table.spatial_resolution(), 64u) << v1::FabricMethod_Name(method);
    EXPECT_EQ(table.view_directions(), 81u);
    EXPECT_EQ(table.light_directions(), 64u);
  }
}

TEST(Defaults, KnitFabric) {
  const v1::FabricSpec fabric = WithDefaults(ParseSpecJson<v1::FabricSpec>(R"({"knit": {}})", "fabric"));
  EXPECT_EQ(fabric.knit().pattern(), v1::KNIT_PATTERN_STOCKINETTE);
  EXPECT_EQ(fabric.knit().wales(), 1u);
  EXPECT_EQ(fabric.knit().courses(), 1u);
  EXPECT_FLOAT_EQ(fabric.knit().loop_aspect(), 1.25f);
  ASSERT_EQ(fabric.yarns_size(), 1);
  const v1::YarnSpec& yarn = fabric.yarns(0);
  EXPECT_FLOAT_EQ(yarn.radius(), 0.07f);
  EXPECT_EQ(yarn.plies(), 1u);
  EXPECT_FLOAT_EQ(yarn.roughness(), 0.5f);
  EXPECT_FLOAT_EQ(yarn.diffuse_albedo().g(), 0.5f);
  EXPECT_FLOAT_EQ(yarn.specular_albedo().b(), 0.04f);
}

TEST(Defaults, KnitPatternRepeats) {
  auto tile = [](const char* knit) {
    const v1::KnitSpec spec =
        WithDefaults(ParseSpecJson<v1::FabricSpec>(std::string(R"({"knit": )") + knit + "}", "fabric")).knit();
    return std::pair{spec.wales(), spec.courses()};
  };
  EXPECT_EQ(tile(R"({"pattern": "KNIT_PATTERN_REVERSE"})"), std::pair(1u, 1u));
  EXPECT_EQ(tile(R"({"pattern": "KNIT_PATTERN_GARTER"})"), std::pair(1u, 2u));
  EXPECT_EQ(tile(R"({"pattern": "KNIT_PATTERN_RIB"})"), std::pair(2u, 1u));
  EXPECT_EQ(tile(R"({"pattern": "KNIT_PATTERN_RIB", "rib_knit": 3, "rib_purl": 2})"), std::pair(5u, 1u));
  EXPECT_EQ(tile(R"({"pattern": "KNIT_PATTERN_SEED"})"), std::pair(2u, 2u));
  EXPECT_EQ(tile(R"({"pattern": "KNIT_PATTERN_SEED", "courses": 4})"), std::pair(2u, 4u));
}

TEST(Defaults, WovenFabric) {
  auto woven = [](const char* json) {
    return WithDefaults(ParseSpecJson<v1::FabricSpec>(std::string(R"({"woven": )") + json + "}", "fabric"));
  };
  const v1::FabricSpec plain = woven("{}");
  EXPECT_EQ(plain.woven().pattern(), v1::WEAVE_PATTERN_PLAIN);
  EXPECT_EQ(plain.woven().n(), 0u);
  EXPECT_EQ(plain.woven().m(), 0u);
  EXPECT_FLOAT_EQ(plain.woven().inclination_degrees(), 20.0f);
  EXPECT_FLOAT_EQ(plain.yarns(0).radius(), 0.25f);

  const v1::WovenSpec twill = woven(R"({"pattern": "WEAVE_PATTERN_TWILL"})").woven();
  EXPECT_EQ(std::pair(twill.n(), twill.m()), std::pair(2u, 1u));
  const v1::WovenSpec satin = woven(R"({"pattern": "WEAVE_PATTERN_SATIN"})").woven();
  EXPECT_EQ(std::pair(satin.n(), satin.m()), std::pair(5u, 2u));
  const v1::WovenSpec satin8 = woven(R"({"pattern": "WEAVE_PATTERN_SATIN", "n": 8})").woven();
  EXPECT_EQ(satin8.m(), 3u);
  const v1::WovenSpec basket = woven(R"({"pattern": "WEAVE_PATTERN_BASKET"})").woven();
  EXPECT_EQ(std::pair(basket.n(), basket.m()), std::pair(2u, 0u));
}

TEST(Defaults, ExplicitAlbedoIsKept) {
  const v1::FabricSpec fabric =
      WithDefaults(ParseSpecJson<v1::FabricSpec>(R"({"knit": {}, "yarns": [{"specular_albedo": {}}]})", "fabric"));
  EXPECT_EQ(fabric.yarns(0).specular_albedo().r(), 0.0f);  // present: black is a real value
}

TEST(Defaults, FabricWithoutStructureIsLeftAlone) {
  v1::FabricSpec fabric;
  fabric.set_name("nothing");
  EXPECT_TRUE(MessageDifferencer::Equals(WithDefaults(fabric), fabric));
}

TEST(Defaults, SatinMoves) {
  EXPECT_EQ(SmallestSatinMove(4), 0u);
  EXPECT_EQ(SmallestSatinMove(5), 2u);
  EXPECT_EQ(SmallestSatinMove(6), 0u);
  EXPECT_EQ(SmallestSatinMove(7), 2u);
  EXPECT_EQ(SmallestSatinMove(8), 3u);
  EXPECT_EQ(SmallestSatinMove(12), 5u);
  EXPECT_TRUE(IsValidSatinMove(8, 5));
  EXPECT_FALSE(IsValidSatinMove(8, 6));
  EXPECT_FALSE(IsValidSatinMove(8, 7));
}

TEST(Defaults, RenderSettings) {
  const v1::RenderSettings s = WithDefaults(v1::RenderSettings());
  EXPECT_EQ(s.method(), v1::RENDER_METHOD_SVBRDF);
  EXPECT_EQ(s.width(), 960u);
  EXPECT_EQ(s.height(), 540u);
  EXPECT_EQ(s.msaa_samples(), 4u);
  EXPECT_EQ(s.level_mode(), v1::LEVEL_MODE_TRILINEAR);
  EXPECT_EQ(s.texel_filter(), v1::TEXEL_FILTER_BILINEAR);
  EXPECT_EQ(s.shadow_map_size(), 2048u);
  EXPECT_EQ(s.reference_samples(), 64u);
  EXPECT_EQ(s.format(), v1::IMAGE_FORMAT_UNSPECIFIED);
}

TEST(Defaults, LumisliceTakesOneRayAPixel) {
  v1::RenderSettings settings;
  settings.set_method(v1::RENDER_METHOD_LUMISLICE);
  EXPECT_EQ(WithDefaults(settings).msaa_samples(), 1u);
  settings.set_msaa_samples(4);
  EXPECT_EQ(WithDefaults(settings).msaa_samples(), 4u);
}

TEST(Defaults, Scene) {
  const v1::SceneSpec scene =
      WithDefaults(ParseSpecJson<v1::SceneSpec>(SceneJson(R"({"objects": [{"mesh": {"builtin": "BUILTIN_SHAPE_PLANE"}},
                                {"mesh": {"builtin": "BUILTIN_SHAPE_SPHERE"}, "fabric": {"fabric": {"woven": {}}}}],
                    "lights": [{}]})"),
                                                "scene"));
  EXPECT_FALSE(scene.objects(0).has_fabric());
  EXPECT_EQ(scene.objects(0).transform().scale().y(), 1.0f);
  const v1::FabricBinding& binding = scene.objects(1).fabric();
  EXPECT_EQ(binding.fabric().woven().pattern(), v1::WEAVE_PATTERN_PLAIN);
  EXPECT_EQ(binding.fabric().yarns_size(), 1);
  EXPECT_FALSE(binding.has_precompute());  // unset lets Loom choose
  EXPECT_EQ(binding.repeat_u(), 1.0f);
  EXPECT_EQ(binding.repeat_v(), 1.0f);

  const v1::Camera& camera = scene.camera();
  EXPECT_EQ(camera.projection(), v1::PROJECTION_PERSPECTIVE);
  EXPECT_EQ(camera.up().z(), 1.0f);
  EXPECT_FLOAT_EQ(camera.fov_y_degrees(), 40.0f);
  EXPECT_FLOAT_EQ(camera.ortho_height(), 2.0f);
  EXPECT_FLOAT_EQ(camera.near(), 0.01f);
  EXPECT_FLOAT_EQ(camera.far(), 100.0f);

  const v1::Light& light = scene.lights(0);
  EXPECT_EQ(light.type(), v1::LIGHT_TYPE_DIRECTIONAL);
  EXPECT_EQ(light.intensity(), 1.0f);
  EXPECT_EQ(light.colour().g(), 1.0f);
  EXPECT_EQ(scene.render().width(), 960u);
}

}  // namespace
}  // namespace loom
