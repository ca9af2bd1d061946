#include "core/plan/precompute_plan.h"

#include <gtest/gtest.h>

#include <cmath>
#include <set>

#include "core/spec/defaults.h"
#include "core/spec/fabric_key.h"
#include "core/spec/validate.h"
#include "core/util/error.h"

namespace loom {
namespace {

// A plane of side 2 seen head-on by an orthographic camera whose view is 2 units
// high on a 100-pixel frame (50 px per unit), tiled `repeat` times: a tile spans
// 100 / repeat pixels.
v1::SceneSpec PlaneScene(float repeat) {
  v1::SceneSpec scene;
  v1::SceneObject* cloth = scene.add_objects();
  cloth->set_name("cloth");
  cloth->mutable_mesh()->set_builtin(v1::BUILTIN_SHAPE_PLANE);
  cloth->mutable_transform()->mutable_scale()->set_x(2);
  cloth->mutable_transform()->mutable_scale()->set_y(2);
  cloth->mutable_transform()->mutable_scale()->set_z(1);
  cloth->mutable_fabric()->mutable_fabric()->mutable_knit();
  cloth->mutable_fabric()->set_repeat_u(repeat);
  cloth->mutable_fabric()->set_repeat_v(repeat);
  v1::Camera* camera = scene.mutable_camera();
  camera->set_projection(v1::PROJECTION_ORTHOGRAPHIC);
  camera->set_ortho_height(2);
  camera->mutable_position()->set_z(5);
  camera->mutable_up()->set_y(1);
  scene.mutable_render()->set_width(100);
  scene.mutable_render()->set_height(100);
  scene = WithDefaults(scene);
  ThrowIfAny(Validate(scene));
  return scene;
}

MeasuredVariation Variation(std::string name, FootprintClass footprint, double psnr_change, double precompute_ratio) {
  MeasuredVariation v;
  v.configuration = std::move(name);
  v.footprint = footprint;
  v.psnr_change_db = psnr_change;
  v.worst_psnr_change_db = psnr_change;
  v.precompute_ratio = precompute_ratio;
  v.bytes_ratio = precompute_ratio;
  v.scenes = 4;
  return v;
}

TEST(TileFootprint, HeadOnOrthographicPlaneGivesTheTileSizeInPixels) {
  for (const float repeat : {2.0f, 10.0f, 50.0f}) {
    const v1::SceneSpec scene = PlaneScene(repeat);
    const auto meshes = BuildSceneGeometry(scene, FileMeshResolver({}));
    const TileFootprint footprint = MeasureTileFootprint(scene, meshes[0]);
    EXPECT_GT(footprint.visible_triangles, 0);
    EXPECT_NEAR(footprint.largest_pixels, 100.0 / repeat, 1e-3 * 100.0 / repeat);
    EXPECT_NEAR(footprint.smallest_pixels, 100.0 / repeat, 1e-3 * 100.0 / repeat);
  }
}

TEST(TileFootprint, ATiltedPlaneShowsLessThanHeadOn) {
  v1::SceneSpec scene = PlaneScene(10);
  scene.mutable_camera()->mutable_position()->set_y(-5);  // 45°
  const auto meshes = BuildSceneGeometry(scene, FileMeshResolver({}));
  // The area shrinks by cos 45°, the side by its square root.
  EXPECT_NEAR(MeasureTileFootprint(scene, meshes[0]).largest_pixels, 10.0 * std::sqrt(std::sqrt(0.5)), 1e-2);
}

TEST(PrecomputePlan, TakesTheCheapestVariationWithinTheBudgetAndOnlyOne) {
  const v1::SceneSpec scene = PlaneScene(50);  // 2 px: far
  const auto meshes = BuildSceneGeometry(scene, FileMeshResolver({}));
  MeasuredVariation res8 = Variation("res8", FootprintClass::kFar, -0.1, 0.2);
  res8.spatial_resolution = 8;
  res8.supersampling = 8;
  MeasuredVariation res16 = Variation("res16", FootprintClass::kFar, 0.0, 0.4);
  res16.spatial_resolution = 16;
  MeasuredVariation dirs16 = Variation("dirs16", FootprintClass::kFar, -0.3, 0.1);
  dirs16.directions = 16;
  MeasuredVariation lobes1 = Variation("lobes1", FootprintClass::kFar, -0.3, 0.5);
  lobes1.lobes = 1;
  MeasuredVariation lobes1_near = Variation("lobes1", FootprintClass::kNear, 0.0, 0.01);
  lobes1_near.lobes = 3;  // another class: must not apply
  const std::vector<MeasuredVariation> table = {res8, res16, dirs16, lobes1, lobes1_near};

  const ScenePlan plan = PlanScene(scene, meshes, 0.5, table);
  ASSERT_EQ(plan.fabrics.size(), 1u);
  const FabricPlan& fabric = plan.fabrics[0];
  EXPECT_EQ(fabric.footprint_class, FootprintClass::kFar);
  EXPECT_EQ(fabric.footprint_resolution, 4u);
  // dirs16 saves most and fits; res8 and lobes1 fit too, but not together with it.
  EXPECT_EQ(fabric.chosen, (std::vector<std::string>{"dirs16"}));
  EXPECT_EQ(fabric.settings.view_directions(), 16u);
  EXPECT_EQ(fabric.settings.light_directions(), 16u);
  EXPECT_EQ(fabric.settings.spatial_resolution(), 32u);
  EXPECT_EQ(fabric.settings.lobes(), 2u);
  EXPECT_NEAR(fabric.predicted_psnr_loss_db, 0.3, 1e-9);
  EXPECT_NEAR(fabric.predicted_precompute_ratio, 0.1, 1e-9);
  EXPECT_EQ(fabric.key, FabricKey(fabric.fabric, fabric.settings));

  // A smaller budget: the cheapest that still fits.
  const FabricPlan tight = PlanScene(scene, meshes, 0.2, table).fabrics[0];
  EXPECT_EQ(tight.chosen, (std::vector<std::string>{"res8"}));
  EXPECT_EQ(tight.settings.spatial_resolution(), 8u);
  EXPECT_EQ(tight.settings.supersampling(), 8u);
  EXPECT_EQ(tight.settings.view_directions(), 64u);
  // A zero budget takes only what measured no loss.
  EXPECT_EQ(PlanScene(scene, meshes, 0.0, table).fabrics[0].chosen, (std::vector<std::string>{"res16"}));
}

TEST(PrecomputePlan, NeverGoesBelowTheResolutionTheFootprintCanShow) {
  const v1::SceneSpec scene = PlaneScene(5);  // 20 px: mid, 32 texels can show
  const auto meshes = BuildSceneGeometry(scene, FileMeshResolver({}));
  MeasuredVariation res8 = Variation("res8", FootprintClass::kMid, 0.0, 0.2);
  res8.spatial_resolution = 8;
  const FabricPlan fabric = PlanScene(scene, meshes, 1.0, {res8}).fabrics[0];
  EXPECT_EQ(fabric.footprint_class, FootprintClass::kMid);
  EXPECT_EQ(fabric.footprint_resolution, 32u);
  EXPECT_TRUE(fabric.chosen.empty());
  EXPECT_EQ(fabric.settings.SerializeAsString(), WithDefaults(v1::PrecomputeSettings()).SerializeAsString());
}

TEST(PrecomputePlan, PassesOverAVariationThatSavesNothingAndSaysSo) {
  const v1::SceneSpec scene = PlaneScene(50);  // far
  const auto meshes = BuildSceneGeometry(scene, FileMeshResolver({}));
  MeasuredVariation dirs49 = Variation("dirs49", FootprintClass::kFar, 0.0, 1.03);  // measured under load
  dirs49.directions = 49;
  const FabricPlan fabric = PlanScene(scene, meshes, 0.5, {dirs49}).fabrics[0];
  EXPECT_TRUE(fabric.chosen.empty());
  bool said = false;
  for (const std::string& reason : fabric.reasons) said |= reason.find("not dirs49: measured precompute x1.030") == 0;
  EXPECT_TRUE(said);
}

TEST(PrecomputePlan, ChoosesAnotherMethodAtItsDefaultsUnlessItsAssetGrowsTooMuch) {
  const v1::SceneSpec scene = PlaneScene(2);  // near
  const auto meshes = BuildSceneGeometry(scene, FileMeshResolver({}));
  MeasuredVariation factored = Variation("factored", FootprintClass::kNear, 1.5, 0.1);
  factored.worst_psnr_change_db = 0.4;
  factored.bytes_ratio = 7.5;
  factored.method = v1::FABRIC_METHOD_FACTORED;
  MeasuredVariation tabulated = Variation("tabulated", FootprintClass::kNear, 2.0, 0.08);
  tabulated.bytes_ratio = 57.0;
  tabulated.method = v1::FABRIC_METHOD_TABULATED;
  const MeasuredVariation lobes1 = [] {
    MeasuredVariation v = Variation("lobes1", FootprintClass::kNear, -0.2, 0.5);
    v.lobes = 1;
    return v;
  }();
  const FabricPlan fabric = PlanScene(scene, meshes, 0.5, {lobes1, tabulated, factored}).fabrics[0];
  EXPECT_EQ(fabric.chosen, (std::vector<std::string>{"factored"}));
  // The method's own defaults but the baseline's texels, as the sweep measured it.
  v1::PrecomputeSettings expected;
  expected.set_method(v1::FABRIC_METHOD_FACTORED);
  expected.set_spatial_resolution(32);
  EXPECT_EQ(fabric.settings.SerializeAsString(), WithDefaults(expected).SerializeAsString());
  EXPECT_EQ(fabric.settings.view_directions(), 81u);
  EXPECT_EQ(fabric.settings.spatial_resolution(), 32u);
  EXPECT_NEAR(fabric.predicted_psnr_loss_db, 0.0, 1e-9);  // a gain on every scene counts as no loss
  bool said = false;
  for (const std::string& reason : fabric.reasons) {
    said |= reason.find("not tabulated: its asset measured x57.0 the defaults' bytes") == 0;
  }
  EXPECT_TRUE(said);
  // A method that lost more than the budget somewhere in the class is not taken.
  factored.worst_psnr_change_db = -0.6;
  EXPECT_EQ(PlanScene(scene, meshes, 0.5, {lobes1, tabulated, factored}).fabrics[0].chosen,
            (std::vector<std::string>{"lobes1"}));
}

TEST(PrecomputePlan, AVariationMeasuredOnTooFewScenesOfTheClassIsTakenAtTheWorstOfEveryKind) {
  v1::SceneSpec scene = PlaneScene(50);  // far
  scene.mutable_objects(0)->mutable_fabric()->mutable_fabric()->mutable_woven();
  const auto meshes = BuildSceneGeometry(scene, FileMeshResolver({}));
  MeasuredVariation woven = Variation("dirs36", FootprintClass::kFar, 0.0, 0.4);
  woven.fabric_kind = FabricKind::kWovenMatte;
  woven.directions = 36;
  woven.scenes = kMinClassScenes - 1;
  MeasuredVariation knit = woven;
  knit.fabric_kind = FabricKind::kKnitMatte;
  knit.worst_psnr_change_db = -1.5;
  knit.scenes = 6;
  const FabricPlan thin = PlanScene(scene, meshes, 0.5, {woven, knit}).fabrics[0];
  EXPECT_TRUE(thin.chosen.empty());
  bool said = false;
  for (const std::string& reason : thin.reasons) said |= reason.find("dirs36: measured on 2 woven-matte scenes only") == 0;
  EXPECT_TRUE(said);
  woven.scenes = kMinClassScenes;  // enough scenes: its own class's figures
  EXPECT_EQ(PlanScene(scene, meshes, 0.5, {woven, knit}).fabrics[0].chosen, (std::vector<std::string>{"dirs36"}));
}

TEST(PrecomputePlan, BudgetsTheWorstMeasuredSceneNotTheMean) {
  const v1::SceneSpec scene = PlaneScene(50);  // far
  const auto meshes = BuildSceneGeometry(scene, FileMeshResolver({}));
  // Gains 1 dB on average but lost 0.8 dB on one scene of its class.
  MeasuredVariation res8 = Variation("res8-ss8", FootprintClass::kFar, 1.0, 0.2);
  res8.worst_psnr_change_db = -0.8;
  res8.spatial_resolution = 8;
  res8.supersampling = 8;
  EXPECT_TRUE(PlanScene(scene, meshes, 0.5, {res8}).fabrics[0].chosen.empty());
  const FabricPlan within = PlanScene(scene, meshes, 1.0, {res8}).fabrics[0];
  EXPECT_EQ(within.chosen, (std::vector<std::string>{"res8-ss8"}));
  EXPECT_NEAR(within.predicted_psnr_loss_db, 0.8, 1e-9);
}

TEST(PrecomputePlan, PlansEachFabricKindFromItsOwnMeasurements) {
  v1::SceneSpec scene = PlaneScene(50);  // far
  v1::YarnSpec* gold = scene.mutable_objects(0)->mutable_fabric()->mutable_fabric()->add_yarns();
  gold->mutable_specular_albedo()->set_r(0.3f);
  scene = WithDefaults(scene);
  const auto meshes = BuildSceneGeometry(scene, FileMeshResolver({}));
  MeasuredVariation matte = Variation("lobes1", FootprintClass::kFar, 0.0, 0.5);
  matte.lobes = 1;
  MeasuredVariation glossy = matte;
  glossy.fabric_kind = FabricKind::kKnitGlossy;
  glossy.worst_psnr_change_db = -2.0;
  const FabricPlan fabric = PlanScene(scene, meshes, 0.5, {matte, glossy}).fabrics[0];
  EXPECT_EQ(fabric.fabric_kind, FabricKind::kKnitGlossy);
  EXPECT_TRUE(fabric.kind_measured);
  EXPECT_TRUE(fabric.chosen.empty());  // the matte knits' 0 dB does not apply
  // The same table plans a matte knit with one lobe.
  const v1::SceneSpec matte_scene = PlaneScene(50);
  const auto matte_meshes = BuildSceneGeometry(matte_scene, FileMeshResolver({}));
  EXPECT_EQ(PlanScene(matte_scene, matte_meshes, 0.5, {matte, glossy}).fabrics[0].chosen,
            (std::vector<std::string>{"lobes1"}));
}

TEST(PrecomputePlan, AKindNotMeasuredIsPlannedFromTheWorstOfEveryKind) {
  const v1::SceneSpec scene = PlaneScene(50);  // a matte knit, far
  const auto meshes = BuildSceneGeometry(scene, FileMeshResolver({}));
  MeasuredVariation woven = Variation("lobes1", FootprintClass::kFar, -0.1, 0.4);
  woven.fabric_kind = FabricKind::kWovenMatte;
  woven.lobes = 1;
  MeasuredVariation glossy = Variation("lobes1", FootprintClass::kFar, -2.0, 0.6);
  glossy.fabric_kind = FabricKind::kWovenGlossy;
  glossy.lobes = 1;
  MeasuredVariation near = Variation("lobes1", FootprintClass::kNear, 0.0, 0.1);  // another footprint class
  near.lobes = 1;
  EXPECT_TRUE(PlanScene(scene, meshes, 0.5, {woven, glossy, near}).fabrics[0].chosen.empty());
  const FabricPlan fabric = PlanScene(scene, meshes, 3.0, {woven, glossy, near}).fabrics[0];
  EXPECT_FALSE(fabric.kind_measured);
  EXPECT_EQ(fabric.chosen, (std::vector<std::string>{"lobes1"}));
  EXPECT_NEAR(fabric.predicted_psnr_loss_db, 2.0, 1e-9);
  EXPECT_NEAR(fabric.predicted_precompute_ratio, 0.6, 1e-9);
}

TEST(PrecomputePlan, KeepsExplicitSettingsAndAppliesThePlanToTheOthers) {
  v1::SceneSpec scene = PlaneScene(50);
  *scene.add_objects() = scene.objects(0);
  scene.mutable_objects(1)->set_name("explicit");
  scene.mutable_objects(1)->mutable_fabric()->mutable_precompute()->set_lobes(3);
  scene = WithDefaults(scene);
  const auto meshes = BuildSceneGeometry(scene, FileMeshResolver({}));
  MeasuredVariation dirs16 = Variation("dirs16", FootprintClass::kFar, -0.1, 0.1);
  dirs16.directions = 16;
  const ScenePlan plan = PlanScene(scene, meshes, 0.5, {dirs16});
  ASSERT_EQ(plan.fabrics.size(), 2u);
  EXPECT_FALSE(plan.fabrics[0].explicit_settings);
  EXPECT_TRUE(plan.fabrics[1].explicit_settings);
  EXPECT_EQ(plan.fabrics[1].settings.lobes(), 3u);
  EXPECT_EQ(plan.fabrics[1].settings.view_directions(), 64u);

  const v1::SceneSpec planned = ApplyPlan(scene, plan);
  EXPECT_EQ(planned.objects(0).fabric().precompute().view_directions(), 16u);
  EXPECT_EQ(planned.objects(1).fabric().precompute().view_directions(), 64u);
  EXPECT_EQ(planned.objects(1).fabric().precompute().lobes(), 3u);
}

TEST(PrecomputePlan, RejectsABadBudgetNamingIt) {
  const v1::SceneSpec scene = PlaneScene(10);
  const auto meshes = BuildSceneGeometry(scene, FileMeshResolver({}));
  try {
    PlanScene(scene, meshes, -1.0, {});
    FAIL();
  } catch (const Error& e) {
    EXPECT_EQ(e.code(), ErrorCode::kInvalidArgument);
    EXPECT_NE(std::string(e.what()).find("error budget"), std::string::npos);
  }
}

TEST(PrecomputePlan, TheCompiledTableComesFromTheStandardSweep) {
  // Every footprint class has measurements of the bench set's three kinds, each
  // over scenes, with real ratios and the worst no better than the mean.
  std::set<FootprintClass> classes;
  std::set<FabricKind> kinds;
  for (const MeasuredVariation& v : StandardSweepVariations()) {
    classes.insert(v.footprint);
    kinds.insert(v.fabric_kind);
    EXPECT_GT(v.scenes, 0) << v.configuration;
    EXPECT_LE(v.worst_psnr_change_db, v.psnr_change_db + 1e-3) << v.configuration;
    EXPECT_GT(v.precompute_ratio, 0.0) << v.configuration;
    EXPECT_GT(v.bytes_ratio, 0.0) << v.configuration;
  }
  EXPECT_EQ(classes.size(), 3u);
  EXPECT_EQ(kinds, (std::set<FabricKind>{FabricKind::kKnitMatte, FabricKind::kWovenMatte, FabricKind::kWovenGlossy}));
}

}  // namespace
}  // namespace loom
