#include "core/animate/knit_simulation.h"

#include <algorithm>
#include <cmath>
#include <glm/gtc/constants.hpp>
#include <limits>

#include "core/util/error.h"

namespace loom::animate {
namespace {

// The field is evaluated no closer than this fraction of τ to a collider: a
// point inside one (a step past its last halving) gets the field's strongest
// finite push.
constexpr float kNearestField = 0.02f;

} // namespace

KnitSimulation::KnitSimulation(const KnitCloth &cloth,
                               const KnitMechanics &mechanics,
                               std::vector<Collider> colliders)
    : cloth_(cloth), mechanics_(mechanics),
      field_(mechanics.half_thickness, mechanics.core,
             mechanics.field_strength),
      colliders_(std::move(colliders)), pinned_(cloth.size(), 0),
      x_(cloth.positions), v_(cloth.size(), glm::vec3(0.0f)),
      min_distance_(std::numeric_limits<float>::infinity()) {
  if (cloth.size() != static_cast<size_t>(cloth.across) * cloth.along ||
      cloth.across < 2 || cloth.along < 2) {
    throw Error(ErrorCode::kInvalidArgument,
                "knit simulation: the cloth's points are not across × along");
  }
  const float arm = std::sqrt(cloth.course_spacing * cloth.wale_spacing);
  for (int j = 0; j < cloth.along; ++j) {
    for (int i = 0; i < cloth.across; ++i) {
      const size_t p = cloth.Index(i, j);
      if (i + 1 < cloth.across)
        springs_.push_back({p, cloth.Index(i + 1, j), cloth.course_spacing,
                            &mechanics_.course});
      if (j + 1 < cloth.along)
        springs_.push_back(
            {p, cloth.Index(i, j + 1), cloth.wale_spacing, &mechanics_.wale});
      if (i > 0 && i + 1 < cloth.across) {
        bends_.push_back({cloth.Index(i - 1, j), p, cloth.Index(i + 1, j),
                          mechanics_.bend_course, cloth.course_spacing, 0.0f});
      }
      if (j > 0 && j + 1 < cloth.along) {
        bends_.push_back({cloth.Index(i, j - 1), p, cloth.Index(i, j + 1),
                          mechanics_.bend_wale, cloth.wale_spacing, 0.0f});
      }
      // A cell's two opposite corners, at rest square.
      if (i + 1 < cloth.across && j + 1 < cloth.along) {
        const float right = glm::half_pi<float>();
        shears_.push_back({cloth.Index(i + 1, j), p, cloth.Index(i, j + 1),
                           mechanics_.shear, arm, right});
        shears_.push_back({cloth.Index(i, j + 1), cloth.Index(i + 1, j + 1),
                           cloth.Index(i + 1, j), mechanics_.shear, arm,
                           right});
      }
    }
  }
  min_distance_ = ColliderDistance(x_);
}

void KnitSimulation::Pin(size_t index) {
  if (index >= pinned_.size())
    throw Error(ErrorCode::kInvalidArgument,
                "knit simulation: no point " + std::to_string(index));
  pinned_[index] = 1;
  v_[index] = glm::vec3(0.0f);
}

void KnitSimulation::SetVelocity(size_t index, glm::vec3 velocity) {
  if (index >= pinned_.size())
    throw Error(ErrorCode::kInvalidArgument,
                "knit simulation: no point " + std::to_string(index));
  if (!pinned_[index])
    v_[index] = velocity;
}

double KnitSimulation::KineticEnergy() const {
  double energy = 0.0;
  for (const glm::vec3 &v : v_)
    energy += 0.5 * glm::dot(v, v);
  return energy;
}

void KnitSimulation::Accelerations(const std::vector<glm::vec3> &x,
                                   const std::vector<glm::vec3> &v, float dt,
                                   std::vector<glm::vec3> &a) const {
  a.assign(x.size(), mechanics_.gravity);
  for (size_t p = 0; p < x.size(); ++p)
    a[p] -= mechanics_.air_viscosity * v[p];
  for (const Spring &s : springs_) {
    const glm::vec3 d = x[s.b] - x[s.a];
    const float length = glm::length(d);
    if (length <= 0.0f)
      continue;
    const glm::vec3 f = SpringForce(*s.law, s.rest, length) * d / length;
    a[s.a] += f;
    a[s.b] -= f;
  }
  for (const Triple &t : bends_) {
    const auto f = BendForces(x[t.a], x[t.b], x[t.c], t.constant, t.arm);
    a[t.a] += f[0], a[t.b] += f[1], a[t.c] += f[2];
  }
  for (const Triple &t : shears_) {
    const auto f =
        ShearForces(x[t.a], x[t.b], x[t.c], t.rest_angle, t.constant, t.arm);
    a[t.a] += f[0], a[t.b] += f[1], a[t.c] += f[2];
  }
  // The colliders' fields push along their normals; friction opposes what else
  // would move the point along the surface (eq. 3 and the static threshold
  // K_s·|F|).
  for (size_t p = 0; p < x.size(); ++p) {
    for (const Collider &collider : colliders_) {
      const Contact contact = collider.Nearest(x[p]);
      if (contact.distance >= field_.half_thickness())
        continue;
      const float normal_force =
          field_(std::max(contact.distance, kNearestField * field_.core()));
      const glm::vec3 n = contact.normal;
      const glm::vec3 tangential_force = a[p] - glm::dot(a[p], n) * n;
      const glm::vec3 slip = v[p] - glm::dot(v[p], n) * n;
      const float slip_speed = glm::length(slip);
      a[p] += normal_force * n;
      if (slip_speed <= mechanics_.dynamic_friction * normal_force * dt &&
          glm::length(tangential_force) <=
              mechanics_.static_friction * normal_force) {
        a[p] -= tangential_force + slip / dt; // held
      } else if (slip_speed > 0.0f) {
        a[p] -= std::min(mechanics_.dynamic_friction * normal_force,
                         slip_speed / dt) *
                slip / slip_speed;
      }
    }
  }
  for (size_t p = 0; p < x.size(); ++p) {
    if (pinned_[p])
      a[p] = glm::vec3(0.0f);
  }
}

float KnitSimulation::StableStep() const {
  // ω² of a point: the stiffness of everything acting on it (unit mass). An
  // angle force of constant c and arm r moves its middle point with stiffness
  // about 4c/r.
  std::vector<float> stiffness(x_.size(), 0.0f);
  for (const Spring &s : springs_) {
    // At least the stiffness at the interval's edge: a step may carry a spring
    // out of it.
    const float k = std::max(
        SpringStiffness(*s.law, s.rest, glm::length(x_[s.b] - x_[s.a])),
        std::max(s.law->stretch / s.law->balance_high,
                 s.law->compress / s.law->balance_low) /
            s.rest);
    stiffness[s.a] += k;
    stiffness[s.b] += k;
  }
  for (const auto *triples : {&bends_, &shears_}) {
    for (const Triple &t : *triples) {
      const float k = t.constant / t.arm;
      stiffness[t.a] += k;
      stiffness[t.b] += 4.0f * k;
      stiffness[t.c] += k;
    }
  }
  float omega2 = 0.0f, speed = 0.0f;
  for (size_t p = 0; p < x_.size(); ++p) {
    if (pinned_[p])
      continue;
    for (const Collider &collider : colliders_) {
      const float d = collider.Nearest(x_[p]).distance;
      if (d < field_.half_thickness())
        stiffness[p] -=
            field_.Slope(std::max(d, kNearestField * field_.core()));
    }
    omega2 = std::max(omega2, stiffness[p]);
    speed = std::max(speed, glm::length(v_[p]));
  }
  float step = std::numeric_limits<float>::infinity();
  if (omega2 > 0.0f)
    step = mechanics_.courant / std::sqrt(omega2);
  if (speed > 0.0f)
    step =
        std::min(step, mechanics_.travel *
                           (field_.half_thickness() - field_.core()) / speed);
  return step;
}

bool KnitSimulation::Penetrates(const std::vector<glm::vec3> &x) const {
  for (size_t p = 0; p < x.size(); ++p) {
    for (const Collider &collider : colliders_) {
      if (collider.Nearest(x[p]).distance < 0.0f &&
          collider.Nearest(x_[p]).distance >= 0.0f)
        return true;
    }
  }
  return false;
}

float KnitSimulation::ColliderDistance(const std::vector<glm::vec3> &x) const {
  float least = std::numeric_limits<float>::infinity();
  for (const glm::vec3 &p : x) {
    for (const Collider &collider : colliders_)
      least = std::min(least, collider.Nearest(p).distance);
  }
  return least;
}

void KnitSimulation::Integrate(float dt, std::vector<glm::vec3> &x,
                               std::vector<glm::vec3> &v) {
  // Second-order Runge–Kutta (midpoint).
  Accelerations(x_, v_, dt, a1_);
  x_mid_.resize(x_.size());
  v_mid_.resize(x_.size());
  for (size_t p = 0; p < x_.size(); ++p) {
    x_mid_[p] = x_[p] + 0.5f * dt * v_[p];
    v_mid_[p] = v_[p] + 0.5f * dt * a1_[p];
  }
  Accelerations(x_mid_, v_mid_, dt, a2_);
  x.resize(x_.size());
  v.resize(x_.size());
  for (size_t p = 0; p < x_.size(); ++p) {
    x[p] = x_[p] + dt * v_mid_[p];
    v[p] = v_[p] + dt * a2_[p];
  }
}

void KnitSimulation::Advance(float duration, float max_step) {
  if (!(max_step > 0.0f))
    throw Error(ErrorCode::kInvalidArgument,
                "knit simulation: max_step must be > 0");
  std::vector<glm::vec3> x, v;
  double left = duration;
  while (left > 0.0) {
    float dt = std::min({max_step, StableStep(), static_cast<float>(left)});
    // A point outside a collider now must stay outside; halve the step until it
    // does.
    for (int halving = 0;; ++halving) {
      Integrate(dt, x, v);
      if (!Penetrates(x))
        break;
      if (halving == mechanics_.max_halvings) {
        ++counts_.penetrations;
        break;
      }
      ++counts_.halvings;
      dt *= 0.5f;
    }
    x_.swap(x);
    v_.swap(v);
    min_distance_ = std::min(min_distance_, ColliderDistance(x_));
    left -= dt;
    time_ += dt;
    ++counts_.steps;
  }
}

} // namespace loom::animate
