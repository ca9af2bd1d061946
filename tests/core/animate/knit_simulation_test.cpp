#include "core/animate/knit_simulation.h"

#include <gtest/gtest.h>

#include <cmath>

#include "core/util/error.h"

namespace loom::animate {
namespace {

TEST(KnitSimulation, AHangingClothComesToRestCarryingItsWeight) {
  const KnitCloth cloth = FlatKnitCloth(5, 8, 1.0f, 1.0f, glm::vec3(0), glm::vec3(1, 0, 0), glm::vec3(0, 0, -1));
  KnitSimulation sim(cloth, KnitMechanics{}, {});
  for (int i = 0; i < cloth.across; ++i) sim.Pin(cloth.Index(i, 0));
  sim.Advance(30.0f, 0.04f);
  EXPECT_LT(sim.KineticEnergy(), 1e-5);
  // The springs under the pinned course hold up the 5 × 7 free loops.
  const auto& x = sim.positions();
  glm::vec3 held(0.0f);
  for (int i = 0; i < cloth.across; ++i) {
    const glm::vec3 d = x[cloth.Index(i, 1)] - x[cloth.Index(i, 0)];
    held += SpringForce(KnitMechanics{}.wale, 1.0f, glm::length(d)) * glm::normalize(d);
  }
  EXPECT_NEAR(-held.z, 35 * 9.81f, 0.02f * 35 * 9.81f);
  // No course is pulled or pushed: their springs lie inside the balance
  // interval.
  for (int j = 0; j < cloth.along; ++j) {
    for (int i = 0; i + 1 < cloth.across; ++i) {
      const float length = glm::length(x[cloth.Index(i + 1, j)] - x[cloth.Index(i, j)]);
      EXPECT_GE(length, 0.95f - 1e-3f);
      EXPECT_LE(length, 1.05f + 1e-3f);
    }
  }
}

// A 4 × 4 patch resting at equilibrium in a slope's field, `degrees` steep; how
// far it moves in 2 s.
float SlideOnSlope(float degrees, float static_friction) {
  const float angle = glm::radians(degrees);
  const glm::vec3 normal(0, -std::sin(angle), std::cos(angle)), down(0, -std::cos(angle), -std::sin(angle));
  KnitMechanics mechanics;
  mechanics.static_friction = static_friction;
  const ThicknessField field(mechanics.half_thickness, mechanics.core, mechanics.field_strength);
  const float depth = field.DistanceOf(9.81f * std::cos(angle));
  const KnitCloth cloth =
      FlatKnitCloth(4, 4, 1.0f, 1.0f, depth * normal + glm::vec3(-1.5f, 0, 0), glm::vec3(1, 0, 0), -down);
  KnitSimulation sim(cloth, mechanics, {Collider::Plane(glm::vec3(0), normal)});
  const glm::vec3 start = sim.positions()[0];
  sim.Advance(2.0f, 0.04f);
  EXPECT_GE(sim.min_collider_distance(), 0.0f);
  return glm::length(sim.positions()[0] - start);
}

TEST(KnitSimulation, StaticFrictionHoldsBelowItsAngleAndLetsGoAbove) {
  // K_s = 1: held below 45°, sliding above (then under K_d = 0.5).
  EXPECT_LT(SlideOnSlope(40.0f, 1.0f), 1e-3f);
  EXPECT_GT(SlideOnSlope(50.0f, 1.0f), 1.0f);
  // Without static friction the 40° patch slides (tan 40° > K_d).
  EXPECT_GT(SlideOnSlope(40.0f, 0.0f), 1.0f);
}

// A 2 × 2 patch thrown at a floor at kSpeed loops/s from just outside its field
// (a full step lands below it); the least distance of a point from the floor
// over 1 s, and the simulation's counts.
constexpr float kSpeed = 30.0f;
KnitSimulation Thrown(int max_halvings) {
  KnitMechanics mechanics;
  mechanics.travel = 1e9f;           // only the halving keeps the points out
  mechanics.contact_damping = 0.0f;  // nor does damping slow them first
  mechanics.max_halvings = max_halvings;
  const KnitCloth cloth =
      FlatKnitCloth(2, 2, 1.0f, 1.0f, glm::vec3(0, 0, 0.95f), glm::vec3(1, 0, 0), glm::vec3(0, 1, 0));
  KnitSimulation sim(cloth, mechanics, {Collider::Plane(glm::vec3(0), glm::vec3(0, 0, 1))});
  for (size_t p = 0; p < 4; ++p) sim.SetVelocity(p, glm::vec3(0, 0, -kSpeed));
  sim.Advance(1.0f, 0.04f);
  return sim;
}

TEST(KnitSimulation, TheHalvedStepPreventsAPenetrationTheFullStepMakes) {
  const KnitSimulation full = Thrown(0);
  EXPECT_LT(full.min_collider_distance(), 0.0f);
  EXPECT_GT(full.counts().penetrations, 0);
  const KnitSimulation halved = Thrown(12);
  EXPECT_GT(halved.min_collider_distance(), 0.0f);
  EXPECT_GT(halved.counts().halvings, 0);
  EXPECT_EQ(halved.counts().penetrations, 0);
  // It bounced: moving up, above the floor.
  EXPECT_GT(halved.positions()[0].z, 0.0f);
}

// A 5 × 32 strip lying on a floor, its second half folded back 1 loop above its
// first (the fold between courses 15 and 16), released.
KnitSimulation FoldedOnFloor(const KnitMechanics& mechanics) {
  const ThicknessField field(mechanics.half_thickness, mechanics.core, mechanics.field_strength);
  const float floor_rest = field.DistanceOf(2 * 9.81f);  // the bottom layer carries both
  KnitCloth cloth = FlatKnitCloth(5, 32, 1.0f, 1.0f, glm::vec3(0), glm::vec3(1, 0, 0), glm::vec3(0, 1, 0));
  for (int j = 0; j < 32; ++j) {
    for (int i = 0; i < 5; ++i) {
      cloth.positions[cloth.Index(i, j)] = j < 16 ? glm::vec3(i, j, floor_rest) : glm::vec3(i, 31 - j, floor_rest + 1);
    }
  }
  return KnitSimulation(cloth, mechanics, {Collider::Plane(glm::vec3(0), glm::vec3(0, 0, 1))});
}

// The mean height of the top layer's points above the bottom layer's beneath
// them, far from the fold (whose stiffness arches the top layer near it).
float LayerGap(const KnitSimulation& sim) {
  const KnitCloth& cloth = sim.cloth();
  float sum = 0.0f;
  int n = 0;
  for (int j = 1; j < 6; ++j) {
    for (int i = 0; i < 5; ++i) {
      sum += sim.positions()[cloth.Index(i, 31 - j)].z - sim.positions()[cloth.Index(i, j)].z;
      ++n;
    }
  }
  return sum / n;
}

TEST(KnitSimulation, AFoldedClothRestsOnItselfThroughTheThicknessField) {
  KnitSimulation sim = FoldedOnFloor(KnitMechanics{});
  sim.Advance(12.0f, 0.04f);
  EXPECT_LT(sim.KineticEnergy(), 0.05);
  // The top layer rests in the bottom's field where it bears its weight, as on
  // a floor: each contact is met from both layers.
  const float rest = ThicknessField(0.9f, 0.1f, 100.0f).DistanceOf(9.81f);
  EXPECT_NEAR(LayerGap(sim), rest, 0.03f);
  EXPECT_GT(sim.min_self_distance(), 0.2f);
  EXPECT_EQ(sim.counts().penetrations, 0);
  EXPECT_GT(sim.counts().contact_searches, 0);
  // Without self-collision the top layer falls through to the floor's field.
  KnitMechanics ghost;
  ghost.self_collision = false;
  KnitSimulation through = FoldedOnFloor(ghost);
  through.Advance(12.0f, 0.04f);
  EXPECT_LT(LayerGap(through), 0.15f);
}

// How far the folded strip's top layer slides along the course in 1 s, thrown
// at 3 loops/s, with self-friction of strength c7.
float SlideOverItself(float c7) {
  KnitMechanics mechanics;
  mechanics.self_friction_strength = c7;
  KnitSimulation sim = FoldedOnFloor(mechanics);
  sim.Advance(1.0f, 0.04f);  // settle
  const KnitCloth& cloth = sim.cloth();
  const size_t probe = cloth.Index(2, 28);
  const float start = sim.positions()[probe].x;
  for (int j = 16; j < 32; ++j) {
    for (int i = 0; i < 5; ++i) sim.SetVelocity(cloth.Index(i, j), glm::vec3(3, 0, 0));
  }
  sim.Advance(1.0f, 0.04f);
  EXPECT_EQ(sim.counts().penetrations, 0);
  return sim.positions()[probe].x - start;
}

TEST(KnitSimulation, SelfFrictionSlowsALayerSlidingOverAnother) {
  const float rough = SlideOverItself(150.0f), smooth = SlideOverItself(1e-3f);
  EXPECT_GT(smooth, 0.3f);
  EXPECT_LT(rough, 0.6f * smooth);
}

// The folded strip's top layer thrown down at the bottom at kSpeed from 1 loop
// above it, with no travel bound (which would otherwise slow it down in time).
KnitSimulation ThrownOntoItself(int max_halvings) {
  KnitMechanics mechanics;
  mechanics.max_halvings = max_halvings;
  mechanics.travel = 1e9f;
  mechanics.contact_damping = 0.0f;
  mechanics.courant = 0.3f;  // the penetrating variant blows up sooner at longer steps
  KnitSimulation sim = FoldedOnFloor(mechanics);
  const KnitCloth& cloth = sim.cloth();
  for (int j = 17; j < 32; ++j) {
    for (int i = 0; i < 5; ++i) sim.SetVelocity(cloth.Index(i, j), glm::vec3(0, 0, -kSpeed));
  }
  sim.Advance(0.06f, 0.04f);
  return sim;
}

TEST(KnitSimulation, TheHalvedStepKeepsAPointFromPassingThroughTheCloth) {
  const KnitSimulation full = ThrownOntoItself(0);
  EXPECT_GT(full.counts().penetrations, 0);
  const KnitSimulation halved = ThrownOntoItself(12);
  EXPECT_EQ(halved.counts().penetrations, 0);
  EXPECT_GT(halved.counts().halvings, 0);
  EXPECT_GT(halved.min_self_distance(), 0.0f);
  EXPECT_GT(LayerGap(halved), 0.0f);
}

// A 6 × 6 cloth in free fall whose points alternate ±1 loop/s up and down (a
// checkerboard of jitter); its spread of vertical velocities after 0.1 s, and how
// far its centre fell.
std::pair<float, float> Jitter(float smoothing_rate) {
  KnitMechanics mechanics;
  mechanics.smoothing_rate = smoothing_rate;
  const KnitCloth cloth = FlatKnitCloth(6, 6, 1.0f, 1.0f, glm::vec3(0), glm::vec3(1, 0, 0), glm::vec3(0, 1, 0));
  KnitSimulation sim(cloth, mechanics, {});
  for (int j = 0; j < 6; ++j) {
    for (int i = 0; i < 6; ++i) sim.SetVelocity(cloth.Index(i, j), glm::vec3(0, 0, (i + j) % 2 ? 1.0f : -1.0f));
  }
  sim.Advance(0.1f, 0.04f);
  float mean = 0.0f, spread = 0.0f, fall = 0.0f;
  for (size_t p = 0; p < cloth.size(); ++p) mean += sim.velocities()[p].z / cloth.size();
  for (size_t p = 0; p < cloth.size(); ++p) {
    spread += std::abs(sim.velocities()[p].z - mean) / cloth.size();
    fall += (cloth.positions[p].z - sim.positions()[p].z) / cloth.size();
  }
  return {spread, fall};
}

TEST(KnitSimulation, TheSmoothingFilterDampsJitterAndLeavesTheFallAlone) {
  const auto [raw_spread, raw_fall] = Jitter(0.0f);
  const auto [spread, fall] = Jitter(20.0f);
  EXPECT_LT(spread, 0.5f * raw_spread);
  // Free fall (½ g t² = 0.049) is the same motion for every point: unfiltered.
  EXPECT_NEAR(fall, raw_fall, 1e-3f);
  EXPECT_NEAR(raw_fall, 0.5f * 9.81f * 0.01f, 0.01f);
}

TEST(KnitSimulation, PinsFollowTheirMotionAndLetGoWithItsVelocity) {
  KnitMechanics mechanics;
  mechanics.air_viscosity = 0.0f;
  const KnitCloth cloth = FlatKnitCloth(2, 2, 1.0f, 1.0f, glm::vec3(0), glm::vec3(1, 0, 0), glm::vec3(0, 1, 0));
  KnitSimulation sim(cloth, mechanics, {});
  // All four carried up at 2 loops/s from 0.1 s to 0.6 s, let go at 0.5 s.
  for (size_t p = 0; p < 4; ++p) sim.Pin(p, Motion{glm::vec3(0, 0, 2), 0.1, 0.6}, 0.5);
  sim.Advance(0.3f, 0.04f);
  EXPECT_NEAR(sim.positions()[3].z, 0.4f, 1e-5f);
  EXPECT_NEAR(sim.velocities()[3].z, 2.0f, 1e-5f);
  sim.Advance(0.2f, 0.04f);  // to the release, exactly
  EXPECT_NEAR(sim.positions()[3].z, 0.8f, 1e-4f);
  // Free from 0.5 s: thrown up at 2 loops/s under gravity.
  sim.Advance(0.3f, 0.04f);
  EXPECT_NEAR(sim.positions()[3].z, 0.8f + 2 * 0.3f - 0.5f * 9.81f * 0.09f, 1e-3f);
  EXPECT_THROW(sim.Pin(99), Error);
}

// A 4 × 4 patch resting on a floor that slides along itself at 1 loop/s (a
// conveyor belt): its velocity along the belt after 2 s.
float RideOnBelt(float static_friction, float dynamic_friction) {
  KnitMechanics mechanics;
  mechanics.static_friction = static_friction;
  mechanics.dynamic_friction = dynamic_friction;
  const ThicknessField field(mechanics.half_thickness, mechanics.core, mechanics.field_strength);
  const KnitCloth cloth =
      FlatKnitCloth(4, 4, 1.0f, 1.0f, glm::vec3(0, 0, field.DistanceOf(9.81f)), glm::vec3(1, 0, 0), glm::vec3(0, 1, 0));
  const Collider belt = Collider::Plane(glm::vec3(0), glm::vec3(0, 0, 1)).Moving(Motion{glm::vec3(1, 0, 0), 0.0, 1e9});
  KnitSimulation sim(cloth, mechanics, {belt});
  sim.Advance(2.0f, 0.04f);
  EXPECT_GE(sim.min_collider_distance(), 0.0f);
  return sim.velocities()[5].x;
}

TEST(KnitSimulation, FrictionActsOnTheSlipAgainstAMovingCollider) {
  // Friction carries the patch along with the belt…
  EXPECT_NEAR(RideOnBelt(1.0f, 0.5f), 1.0f, 0.02f);
  // …and without friction the belt slides beneath it.
  EXPECT_NEAR(RideOnBelt(0.0f, 0.0f), 0.0f, 0.02f);
}

// A 3 × 3 patch dropped flat onto a floor from 5 loops up: how high it rises
// after it first reaches the floor's field.
float Rebound(float contact_damping) {
  KnitMechanics mechanics;
  mechanics.contact_damping = contact_damping;
  const KnitCloth cloth = FlatKnitCloth(3, 3, 1.0f, 1.0f, glm::vec3(0, 0, 5), glm::vec3(1, 0, 0), glm::vec3(0, 1, 0));
  KnitSimulation sim(cloth, mechanics, {Collider::Plane(glm::vec3(0), glm::vec3(0, 0, 1))});
  while (sim.positions()[4].z > 0.9f) sim.Advance(0.01f, 0.01f);
  float highest = 0.0f;
  for (int k = 0; k < 100; ++k) {
    sim.Advance(0.01f, 0.01f);
    highest = std::max(highest, sim.positions()[4].z);
  }
  EXPECT_EQ(sim.counts().penetrations, 0);
  return highest;
}

TEST(KnitSimulation, TheFibreLayerAbsorbsAnImpact) {
  // Damped, the patch stays in the field (below T = 0.9); the elastic field
  // throws it back up most of the way.
  EXPECT_LT(Rebound(50.0f), 0.9f);
  EXPECT_GT(Rebound(0.0f), 2.5f);
}

TEST(KnitSimulation, StopsWithAnErrorWhenDrivenPastWhatItFollows) {
  // Both ends torn apart at 1000 loops/s: the springs' exponential law runs away.
  const KnitCloth cloth = FlatKnitCloth(3, 6, 1.0f, 1.0f, glm::vec3(0), glm::vec3(1, 0, 0), glm::vec3(0, 1, 0));
  KnitSimulation sim(cloth, KnitMechanics{}, {});
  for (int i = 0; i < 3; ++i) {
    sim.Pin(cloth.Index(i, 0), Motion{glm::vec3(0, -1000, 0), 0.0, 1.0});
    sim.Pin(cloth.Index(i, 5), Motion{glm::vec3(0, 1000, 0), 0.0, 1.0});
  }
  try {
    sim.Advance(1.0f, 0.04f);
    FAIL() << "the torn cloth kept stepping";
  } catch (const Error& error) {
    EXPECT_EQ(error.code(), ErrorCode::kInvalidArgument);
    EXPECT_NE(std::string(error.what()).find("stable step"), std::string::npos) << error.what();
  }
}

TEST(KnitSimulation, ABallHeldByItsMotionFallsFreelyOnceLetGo) {
  // Carried along +x at 1 loop/s, let go at 0.5 s; nothing under it.
  const KnitCloth cloth = FlatKnitCloth(2, 2, 1.0f, 1.0f, glm::vec3(100, 0, 0), glm::vec3(1, 0, 0), glm::vec3(0, 1, 0));
  KnitSimulation sim(cloth, KnitMechanics{},
                     {Collider::Sphere(glm::vec3(0, 0, 50), 2.0f).Moving(Motion{glm::vec3(1, 0, 0), 0.0, 10.0})});
  for (size_t p = 0; p < 4; ++p) sim.Pin(p);
  sim.Free(0, 10.0f, 0.5);
  sim.Advance(0.5f, 0.04f);
  EXPECT_NEAR(sim.collider_displacement(0).x, 0.5f, 1e-5f);
  EXPECT_NEAR(sim.collider_displacement(0).z, 0.0f, 1e-6f);
  sim.Advance(1.0f, 0.04f);
  // Midpoint steps are exact under a constant acceleration.
  EXPECT_NEAR(sim.collider_displacement(0).x, 1.5f, 1e-4f);
  EXPECT_NEAR(sim.collider_displacement(0).z, -0.5f * 9.81f, 1e-3f);
  EXPECT_THROW(sim.Free(1, 1.0f), Error);
}

TEST(KnitSimulation, OnlyASphereWithMassCanBeLetGo) {
  const KnitCloth cloth = FlatKnitCloth(2, 2, 1.0f, 1.0f, glm::vec3(0), glm::vec3(1, 0, 0), glm::vec3(0, 1, 0));
  KnitSimulation sim(cloth, KnitMechanics{},
                     {Collider::Plane(glm::vec3(0, 0, -5), glm::vec3(0, 0, 1)),
                      Collider::Sphere(glm::vec3(0, 0, 9), 1)});
  EXPECT_THROW(sim.Free(0, 1.0f), Error);
  EXPECT_THROW(sim.Free(1, 0.0f), Error);
  EXPECT_NO_THROW(sim.Free(1, 1.0f));
}

TEST(KnitSimulation, ABallComesToRestOnAFloorWithoutSinkingIn) {
  const KnitCloth cloth = FlatKnitCloth(2, 2, 1.0f, 1.0f, glm::vec3(100, 0, 0), glm::vec3(1, 0, 0), glm::vec3(0, 1, 0));
  KnitSimulation sim(cloth, KnitMechanics{},
                     {Collider::Plane(glm::vec3(0), glm::vec3(0, 0, 1)), Collider::Sphere(glm::vec3(0, 0, 6), 2.0f)});
  for (size_t p = 0; p < 4; ++p) sim.Pin(p);
  sim.Free(1, 10.0f);
  sim.Advance(3.0f, 0.04f);
  EXPECT_NEAR(sim.collider_displacement(1).z, -4.0f, 1e-4f);  // its centre one radius above the floor
}

// A ball of `mass` dropped (or thrown down at `speed`) from 2 loops above the
// middle of a 15 × 15 cloth held at its edges (a trampoline).
struct Landing {
  float lowest = 0.0f;   // the ball's centre's lowest height
  float highest = 0.0f;  // and its highest after that
  float rest_mean = 0.0f, rest_range = 0.0f;  // over the last 2 s
  float least_distance = 0.0f;                // of a free loop to the ball
};
Landing DropOnTrampoline(float mass, float speed, float seconds) {
  const KnitCloth cloth =
      FlatKnitCloth(15, 15, 1.0f, 1.0f, glm::vec3(-7, -7, 0), glm::vec3(1, 0, 0), glm::vec3(0, 1, 0));
  const Motion throw_down(glm::vec3(0, 0, -speed), 0.0, 0.01);
  KnitSimulation sim(cloth, KnitMechanics{}, {Collider::Sphere(glm::vec3(0, 0, 5), 3.0f).Moving(throw_down)});
  for (int j = 0; j < 15; ++j) {
    for (int i = 0; i < 15; ++i) {
      if (i == 0 || j == 0 || i == 14 || j == 14) sim.Pin(cloth.Index(i, j));
    }
  }
  sim.Free(0, mass, 0.01);
  Landing landing{5.0f, -1e9f, 0.0f, 0.0f, 0.0f};
  float rest_low = 1e9f, rest_high = -1e9f;
  int rest_samples = 0;
  for (int k = 1; k * 0.05f <= seconds + 1e-4f; ++k) {
    sim.Advance(0.05f, 0.04f);
    const float z = 5.0f + sim.collider_displacement(0).z;
    if (z < landing.lowest) landing.lowest = z, landing.highest = z;
    landing.highest = std::max(landing.highest, z);
    if (k * 0.05f > seconds - 2.0f) {
      landing.rest_mean += z, ++rest_samples;
      rest_low = std::min(rest_low, z), rest_high = std::max(rest_high, z);
    }
  }
  EXPECT_EQ(sim.counts().penetrations, 0);
  landing.rest_mean /= static_cast<float>(rest_samples);
  landing.rest_range = rest_high - rest_low;
  landing.least_distance = sim.min_collider_distance();
  return landing;
}

TEST(KnitSimulation, AClothCarriesABallThatFallsOnIt) {
  // The ball comes to rest on the cloth, the cloth sagging under it more the
  // heavier it is: the cloth's push is what holds it up (a ball the cloth did
  // not push back would fall through, below −7).
  const Landing light = DropOnTrampoline(20.0f, 0.0f, 12.0f), heavy = DropOnTrampoline(200.0f, 0.0f, 12.0f);
  EXPECT_GT(light.least_distance, 0.0f);
  EXPECT_GT(heavy.least_distance, 0.0f);
  EXPECT_LT(light.rest_range, 0.1f);
  EXPECT_GT(light.rest_mean, -1.0f);
  EXPECT_LT(light.rest_mean, 2.0f);
  EXPECT_LT(heavy.rest_mean, light.rest_mean - 0.5f);
  EXPECT_GT(heavy.lowest, -7.0f);
}

TEST(KnitSimulation, ABallThrownAtAClothRebounds) {
  // Thrown down at 30 loops/s, the ball is thrown back up by the cloth's
  // springs and field, some of its energy lost to the fibre layer and the air.
  const Landing landing = DropOnTrampoline(20.0f, 30.0f, 2.0f);
  EXPECT_GT(landing.highest - landing.lowest, 4.0f);
  EXPECT_LT(landing.highest - landing.lowest, (30.0f * 30.0f / 2.0f) / 9.81f);
  EXPECT_GT(landing.least_distance, 0.0f);
}

}  // namespace
}  // namespace loom::animate
