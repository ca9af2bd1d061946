#pragma once
// The lumislice paper's knit animation (§4.1–4.2): a KnitCloth's mass points
// moved by its springs (balance interval), bending, shearing, gravity and air
// viscosity, the thickness force field of the colliders with static and dynamic
// friction, the field of the cloth's own non-adjacent triangles with dynamic
// self-friction, integrated by second-order Runge–Kutta and smoothed. Each step
// is as long as the stability (CFL) bound allows, and is redone at half its
// length while it would carry a point into a collider or through one of the
// cloth's triangles. Units, constants and derivations: docs/animation.md.
//
// Colliders and pinned points may move along prescribed motions, and a sphere
// may be let go as a free ball the cloth pushes back (the paper's ball
// rebounding off a scarf).

#include <cstdint>
#include <glm/glm.hpp>
#include <limits>
#include <memory>
#include <vector>

#include "core/animate/closest_point.h"
#include "core/animate/collider.h"
#include "core/animate/knit_cloth.h"
#include "core/animate/knit_forces.h"
#include "core/animate/motion.h"
#include "core/animate/self_contact.h"

namespace loom::animate {

// The model's constants, in the simulation's units (a point's mass 1, lengths
// in loops, seconds). Defaults: the paper's §6 where its constants can hold a
// cloth, and docs/animation.md says where they cannot.
struct KnitMechanics {
  SpringLaw wale{1500.0f, 3000.0f};    // c₀ wale, c₁
  SpringLaw course{2000.0f, 3000.0f};  // c₀ course, c₁
  float bend_wale = 100.0f;            // c₂ wale
  float bend_course = 150.0f;          // c₂ course
  float shear = 1000.0f;               // c₃
  float half_thickness = 0.9f;         // T
  float core = 0.1f;                   // τ
  float field_strength = 100.0f;       // c₅ (the paper's 0.2 cannot bear a point's weight)
  float static_friction = 1.0f;        // K_s
  float dynamic_friction = 0.5f;       // K_d
  float air_viscosity = 0.6f;          // c₉
  // Inside a field the normal velocity relative to the surface is damped at
  // this rate (1/s), the push never turning into a pull: the fibre layer
  // absorbs an impact instead of returning it (the paper's field is elastic).
  float contact_damping = 50.0f;
  glm::vec3 gravity{0.0f, 0.0f, -9.81f};
  // A step is at most courant / ω_max, ω_max² the largest stiffness a point
  // feels…
  float courant = 0.5f;
  // …and carries no point further than this fraction of the field's fibre layer
  // (T − τ).
  float travel = 0.5f;
  // A step that carries a point into a collider or through a triangle of the
  // cloth is redone at half its length, at most this many times (0: never).
  int max_halvings = 12;
  // Self-contact: the field of the cloth's triangles acts on its points that lie
  // within `cone_degrees` of a triangle's normal, except the triangles of a
  // point's own neighbourhood (`self_exclusion` grid rings); dynamic
  // self-friction is K_d times the field of strength c₇ (the paper's c₇ : c₅ =
  // 0.3 : 0.2 kept).
  bool self_collision = true;
  float self_friction_strength = 150.0f;  // c₇
  float cone_degrees = 45.0f;
  int self_exclusion = 2;
  // Point–triangle pairs are searched again once a point has moved half this.
  float contact_skin = 0.3f;
  // The smoothing filter: after each step a point's displacement and velocity
  // move towards the mean of its grid neighbours' by 1 − e^{−rate·dt}.
  float smoothing_rate = 2.0f;
  // Threads of the force sums and the contact search (0: every core); the
  // result does not depend on them.
  unsigned threads = 0;
};

struct SimulationCounts {
  long steps = 0;     // steps taken
  long halvings = 0;  // steps redone at half their length
  // Steps that, after the last halving, carried a point into a collider or
  // through the cloth, or to within 0.02τ of either.
  long penetrations = 0;
  long contact_searches = 0;  // times the self-contact pairs were searched
};

class KnitSimulation {
 public:
  KnitSimulation(const KnitCloth& cloth, const KnitMechanics& mechanics, std::vector<Collider> colliders);

  // Holds point `index`, from where it is now, along `motion` until time
  // `release` (seconds; never by default), when it goes free with the velocity
  // it had.
  void Pin(size_t index, const Motion& motion = {}, double release = std::numeric_limits<double>::infinity());
  // Sets a free point's velocity (a throw).
  void SetVelocity(size_t index, glm::vec3 velocity);
  // Collider `collider` (a sphere) moves along its motion until time `release`
  // (seconds), then as a ball of `mass` point masses under gravity and the
  // cloth's push and friction, from where its motion left it at the velocity it
  // had. It does not turn; the colliders that are not free balls stop it
  // (without friction or rebound).
  void Free(size_t collider, float mass, double release = 0.0);

  // Advances the cloth by `duration` seconds in steps no longer than
  // `max_step` (a step ends at a pin's release).
  void Advance(float duration, float max_step);

  const std::vector<glm::vec3>& positions() const { return x_; }
  const std::vector<glm::vec3>& velocities() const { return v_; }
  const KnitCloth& cloth() const { return cloth_; }
  const KnitMechanics& mechanics() const { return mechanics_; }
  const ThicknessField& field() const { return field_; }
  // How far collider k has moved from where it was made, now.
  glm::vec3 collider_displacement(size_t k) const { return placed_.at(k).displacement; }
  double time() const { return time_; }
  // ½ Σ |v|² over the points.
  double KineticEnergy() const;
  // The least signed distance from any free point to any collider since the
  // start.
  float min_collider_distance() const { return min_distance_; }
  // The least distance from any point to a triangle of the cloth outside its
  // neighbourhood at the end of a step since the start (+∞ while none came
  // within the field, or without self-collision).
  float min_self_distance() const { return min_self_distance_; }
  SimulationCounts counts() const;

 private:
  // A contact pair at some positions: the nearest point of its triangle to its
  // point, and the point's side of the triangle's plane (the sign of
  // (p − a)·((b − a) × (c − a))).
  struct PairGeometry {
    TrianglePoint nearest;
    float side = 0.0f;
  };
  // Where a collider is at one stage of a step, and its velocity.
  struct Placement {
    glm::vec3 displacement{0.0f}, velocity{0.0f};
  };
  // The acceleration of every point at positions x and velocities v, for a step
  // of length dt (friction stops at most what dt would carry on), with the
  // colliders placed at `placed`; `push` gets the force of the cloth on each
  // collider. The contact pairs must have been updated for x, and `closest` be
  // their ClosestPoints at x.
  void Accelerations(const std::vector<glm::vec3>& x, const std::vector<glm::vec3>& v,
                     const std::vector<Placement>& placed, const std::vector<PairGeometry>& closest, float dt,
                     std::vector<glm::vec3>& a, std::vector<glm::vec3>& push);
  // Whether collider k moves as a free ball now.
  bool MovesFreely(size_t k) const { return bodies_[k].mass > 0.0f && time_ >= bodies_[k].release; }
  // The colliders a time h into the step: those on their motions where these
  // have them; free balls moved from where they are now by `rates`' velocities
  // and the accelerations gravity and `push` give them, then stopped by the
  // other colliders.
  void PlaceColliders(float h, const std::vector<Placement>& rates, const std::vector<glm::vec3>& push,
                      std::vector<Placement>& out) const;
  // The self-contact forces and dynamic self-friction, added to a.
  void AddSelfContact(const std::vector<glm::vec3>& x, const std::vector<glm::vec3>& v,
                      const std::vector<PairGeometry>& closest, float dt, std::vector<glm::vec3>& a) const;
  // Each contact pair's geometry at positions x; the nearest point is left out
  // (weights 0: no force, stiffness or entering the field needs it) when the
  // point lies T or farther from the triangle's plane, and so from the triangle.
  void ClosestPoints(const std::vector<glm::vec3>& x, std::vector<PairGeometry>& out) const;
  // ClosestPoints at the present positions: kept from the crossing check of the
  // step that led here unless the pairs were searched again since.
  const std::vector<PairGeometry>& PresentClosestPoints();
  // Whether the step from x_ to x carries a point through a non-adjacent
  // triangle (its signed distance to the triangle's plane changes sign while its
  // projection lies inside the triangle) or to within 0.02τ of one, and the least
  // distance from a point to a non-adjacent triangle at x.
  struct ClothCrossing {
    bool enters = false;
    float least = 0.0f;
  };
  // Its ClosestPoints at x are kept for when x is taken.
  ClothCrossing CrossCloth(const std::vector<glm::vec3>& x);
  // The smoothing filter on the step from x_ to (x, v).
  void Smooth(float dt, std::vector<glm::vec3>& x, std::vector<glm::vec3>& v);

  struct Spring {
    size_t a, b;
    float rest;
    const SpringLaw* law;
  };
  struct Triple {
    size_t a, b, c;
    float constant, arm, rest_angle;
  };

  // The longest stable step at the present state.
  float StableStep();
  // Whether a point farther than 0.02τ from a collider at the present positions
  // is nearer at x (inside it included), or CrossCloth(x) enters; self_distance
  // gets CrossCloth's least distance when it was asked (NaN when not).
  bool Penetrates(const std::vector<glm::vec3>& x, const std::vector<Placement>& placed, float& self_distance);
  // The least signed distance from the points x to any collider placed at `placed`.
  float ColliderDistance(const std::vector<glm::vec3>& x, const std::vector<Placement>& placed) const;
  // Moves the pinned points to where their motions have them at time t.
  void MovePins(double t, std::vector<glm::vec3>& x, std::vector<glm::vec3>& v) const;
  // One RK2 step of length dt from (x_, v_, placed_) into (x, v, placed).
  void Integrate(float dt, std::vector<glm::vec3>& x, std::vector<glm::vec3>& v, std::vector<Placement>& placed);

  KnitCloth cloth_;
  KnitMechanics mechanics_;
  ThicknessField field_;
  std::vector<Collider> colliders_;
  struct Body {
    float mass = 0.0f;  // 0: moved by its motion only
    double release = 0.0;
  };
  std::vector<Body> bodies_;         // per collider
  std::vector<Placement> placed_;    // per collider, now
  // Of a step: the cloth's force on each collider at its start and its middle.
  std::vector<glm::vec3> push_start_, push_mid_;
  std::vector<glm::vec3> chunk_push_;  // per chunk of points and collider
  std::vector<Placement> placed_mid_;
  ThicknessField self_friction_field_;
  std::unique_ptr<SelfContactPairs> contacts_;  // null without self-collision
  // ClosestPoints at the present positions and at the end of the step being
  // tried, with the search of the pairs each belongs to (−1: none), and at the
  // step's midpoint.
  std::vector<PairGeometry> present_closest_, next_closest_, mid_closest_;
  long present_closest_search_ = -1, next_closest_search_ = -1;
  std::vector<Spring> springs_;
  std::vector<Triple> bends_, shears_;
  struct Pinned {
    size_t index;
    glm::vec3 origin;
    Motion motion;
    double release;
  };
  std::vector<char> pinned_;  // per point
  std::vector<Pinned> pins_;  // those not yet released
  std::vector<glm::vec3> x_, v_;
  unsigned threads_;
  // Each spring's two forces and each angle's three, and the slots each point
  // sums: point p's are incidence_[incidence_offsets_[p] … incidence_offsets_[p + 1]).
  std::vector<glm::vec3> contributions_;
  std::vector<uint32_t> incidence_offsets_, incidence_;
  // Scratch of a step.
  std::vector<glm::vec3> a1_, a2_, x_mid_, v_mid_, mean_;
  double time_ = 0.0;
  SimulationCounts counts_;
  float min_distance_;
  float min_self_distance_;
};

}  // namespace loom::animate
