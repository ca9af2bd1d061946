#include "core/animate/knit_simulation.h"

#include <algorithm>
#include <atomic>
#include <cmath>
#include <glm/gtc/constants.hpp>
#include <limits>
#include <optional>

#include "core/animate/closest_point.h"
#include "core/util/error.h"
#include "core/util/parallel_for.h"

namespace loom::animate {
namespace {

// A stable step shorter than this means the state has blown up (or is about
// to): the simulation stops with an error rather than crawl.
constexpr double kShortestStep = 1e-7;

// Work items of the parallel loops: this many springs, angles or points each.
constexpr size_t kChunk = 2048;
// Pairs (or points' pair lists) a parallel item takes: each costs closest points.
constexpr size_t kPairChunk = 256;
// Cloths of fewer points step on one thread (starting threads would cost more).
constexpr size_t kParallelPoints = 4096;

// The field is evaluated no closer than this fraction of τ to a collider or a
// triangle of the cloth: a point that came closer (a step past its last
// halving) gets the field's strongest finite push. A step that brings a point
// this close is redone at half its length.
constexpr float kNearestField = 0.02f;

}  // namespace

KnitSimulation::KnitSimulation(const KnitCloth& cloth, const KnitMechanics& mechanics, std::vector<Collider> colliders)
    : cloth_(cloth),
      mechanics_(mechanics),
      field_(mechanics.half_thickness, mechanics.core, mechanics.field_strength),
      colliders_(std::move(colliders)),
      bodies_(colliders_.size()),
      placed_(colliders_.size()),
      self_friction_field_(mechanics.half_thickness, mechanics.core, mechanics.self_friction_strength),
      pinned_(cloth.size(), 0),
      x_(cloth.positions),
      v_(cloth.size(), glm::vec3(0.0f)),
      threads_(cloth.size() < kParallelPoints ? 1 : ResolveThreadCount(mechanics.threads)),
      min_distance_(std::numeric_limits<float>::infinity()),
      min_self_distance_(std::numeric_limits<float>::infinity()) {
  if (cloth.size() != static_cast<size_t>(cloth.across) * cloth.along || cloth.across < 2 || cloth.along < 2) {
    throw Error(ErrorCode::kInvalidArgument, "knit simulation: the cloth's points are not across × along");
  }
  const float arm = std::sqrt(cloth.course_spacing * cloth.wale_spacing);
  for (int j = 0; j < cloth.along; ++j) {
    for (int i = 0; i < cloth.across; ++i) {
      const size_t p = cloth.Index(i, j);
      if (i + 1 < cloth.across)
        springs_.push_back({p, cloth.Index(i + 1, j), cloth.course_spacing, &mechanics_.course});
      if (j + 1 < cloth.along) springs_.push_back({p, cloth.Index(i, j + 1), cloth.wale_spacing, &mechanics_.wale});
      if (i > 0 && i + 1 < cloth.across) {
        bends_.push_back(
            {cloth.Index(i - 1, j), p, cloth.Index(i + 1, j), mechanics_.bend_course, cloth.course_spacing, 0.0f});
      }
      if (j > 0 && j + 1 < cloth.along) {
        bends_.push_back(
            {cloth.Index(i, j - 1), p, cloth.Index(i, j + 1), mechanics_.bend_wale, cloth.wale_spacing, 0.0f});
      }
      // A cell's two opposite corners, at rest square.
      if (i + 1 < cloth.across && j + 1 < cloth.along) {
        const float right = glm::half_pi<float>();
        shears_.push_back({cloth.Index(i + 1, j), p, cloth.Index(i, j + 1), mechanics_.shear, arm, right});
        shears_.push_back(
            {cloth.Index(i, j + 1), cloth.Index(i + 1, j + 1), cloth.Index(i + 1, j), mechanics_.shear, arm, right});
      }
    }
  }
  // Which contribution slots each point sums (CSR).
  contributions_.resize(2 * springs_.size() + 3 * (bends_.size() + shears_.size()));
  std::vector<std::vector<uint32_t>> slots(cloth.size());
  for (size_t k = 0; k < springs_.size(); ++k) {
    slots[springs_[k].a].push_back(static_cast<uint32_t>(2 * k));
    slots[springs_[k].b].push_back(static_cast<uint32_t>(2 * k + 1));
  }
  size_t slot = 2 * springs_.size();
  for (const auto* triples : {&bends_, &shears_}) {
    for (const Triple& t : *triples) {
      for (const size_t p : {t.a, t.b, t.c}) slots[p].push_back(static_cast<uint32_t>(slot++));
    }
  }
  incidence_offsets_.assign(1, 0);
  for (const auto& list : slots) {
    incidence_.insert(incidence_.end(), list.begin(), list.end());
    incidence_offsets_.push_back(static_cast<uint32_t>(incidence_.size()));
  }
  for (size_t k = 0; k < colliders_.size(); ++k) {
    placed_[k] = {colliders_[k].motion().Displacement(time_), colliders_[k].motion().Velocity(time_)};
  }
  min_distance_ = ColliderDistance(x_, placed_);
  if (mechanics_.self_collision) {
    if (!(mechanics_.cone_degrees > 0.0f && mechanics_.cone_degrees <= 90.0f)) {
      throw Error(ErrorCode::kInvalidArgument, "knit simulation: cone_degrees must lie in (0, 90]");
    }
    contacts_ = std::make_unique<SelfContactPairs>(cloth_, mechanics_.half_thickness, mechanics_.contact_skin,
                                                   mechanics_.self_exclusion, mechanics_.threads);
    contacts_->Update(x_);
    min_self_distance_ = CrossCloth(x_).least;
    present_closest_.swap(next_closest_);
    present_closest_search_ = next_closest_search_;
  }
}

SimulationCounts KnitSimulation::counts() const {
  SimulationCounts counts = counts_;
  if (contacts_) counts.contact_searches = contacts_->searches();
  return counts;
}

void KnitSimulation::Pin(size_t index, const Motion& motion, double release) {
  if (index >= pinned_.size())
    throw Error(ErrorCode::kInvalidArgument, "knit simulation: no point " + std::to_string(index));
  if (!motion.valid()) throw Error(ErrorCode::kInvalidArgument, "knit simulation: pin motion ends before it starts");
  if (pinned_[index])
    throw Error(ErrorCode::kInvalidArgument, "knit simulation: point " + std::to_string(index) + " pinned twice");
  pinned_[index] = 1;
  pins_.push_back({index, x_[index] - motion.Displacement(time_), motion, release});
  v_[index] = motion.Velocity(time_);
}

void KnitSimulation::MovePins(double t, std::vector<glm::vec3>& x, std::vector<glm::vec3>& v) const {
  for (const Pinned& pin : pins_) {
    x[pin.index] = pin.origin + pin.motion.Displacement(t);
    v[pin.index] = pin.motion.Velocity(t);
  }
}

void KnitSimulation::SetVelocity(size_t index, glm::vec3 velocity) {
  if (index >= pinned_.size())
    throw Error(ErrorCode::kInvalidArgument, "knit simulation: no point " + std::to_string(index));
  if (!pinned_[index]) v_[index] = velocity;
}

void KnitSimulation::Free(size_t collider, float mass, double release) {
  if (collider >= colliders_.size()) {
    throw Error(ErrorCode::kInvalidArgument, "knit simulation: no collider " + std::to_string(collider));
  }
  if (!colliders_[collider].sphere()) {
    throw Error(ErrorCode::kInvalidArgument, "knit simulation: only a sphere collider can be let go as a ball");
  }
  if (!(mass > 0.0f && std::isfinite(mass))) {
    throw Error(ErrorCode::kInvalidArgument, "knit simulation: a ball's mass must be > 0");
  }
  if (!(release >= time_)) throw Error(ErrorCode::kInvalidArgument, "knit simulation: a ball released in the past");
  bodies_[collider] = {mass, release};
}

void KnitSimulation::PlaceColliders(float h, const std::vector<Placement>& rates, const std::vector<glm::vec3>& push,
                                    std::vector<Placement>& out) const {
  out.resize(colliders_.size());
  for (size_t k = 0; k < colliders_.size(); ++k) {
    if (!MovesFreely(k)) {
      const Motion& motion = colliders_[k].motion();
      out[k] = {motion.Displacement(time_ + h), motion.Velocity(time_ + h)};
    }
  }
  for (size_t k = 0; k < colliders_.size(); ++k) {
    if (!MovesFreely(k)) continue;
    Placement ball{placed_[k].displacement + h * rates[k].velocity,
                   placed_[k].velocity + h * (mechanics_.gravity + push[k] / bodies_[k].mass)};
    // Out of the other colliders along their normals, its velocity into them
    // stopped.
    for (size_t other = 0; other < colliders_.size(); ++other) {
      if (MovesFreely(other)) continue;
      const Contact contact =
          colliders_[other].Nearest(colliders_[k].centre() + ball.displacement, out[other].displacement);
      const float depth = colliders_[k].radius() - contact.distance;
      if (depth <= 0.0f) continue;
      ball.displacement += depth * contact.normal;
      const float approach = glm::dot(ball.velocity - out[other].velocity, contact.normal);
      if (approach < 0.0f) ball.velocity -= approach * contact.normal;
    }
    out[k] = ball;
  }
}

double KnitSimulation::KineticEnergy() const {
  double energy = 0.0;
  for (const glm::vec3& v : v_) energy += 0.5 * glm::dot(v, v);
  return energy;
}

void KnitSimulation::Accelerations(const std::vector<glm::vec3>& x, const std::vector<glm::vec3>& v,
                                   const std::vector<Placement>& placed, const std::vector<PairGeometry>& closest,
                                   float dt, std::vector<glm::vec3>& a, std::vector<glm::vec3>& push) {
  // Each spring's and angle's forces into its slots of contributions_, then each
  // point's sum of its slots: both in parallel, and the sums in a fixed order
  // whatever the thread count.
  const size_t springs = springs_.size(), bends = bends_.size(), terms = springs + bends + shears_.size();
  const auto chunks = [](size_t count) { return (count + kChunk - 1) / kChunk; };
  ParallelFor(chunks(terms), threads_, [&](size_t chunk, unsigned) {
    for (size_t k = chunk * kChunk, end = std::min(terms, k + kChunk); k < end; ++k) {
      if (k < springs) {
        const Spring& s = springs_[k];
        const glm::vec3 d = x[s.b] - x[s.a];
        const float length = glm::length(d);
        const glm::vec3 f = length > 0.0f ? SpringForce(*s.law, s.rest, length) / length * d : glm::vec3(0.0f);
        contributions_[2 * k] = f, contributions_[2 * k + 1] = -f;
      } else {
        const bool bend = k < springs + bends;
        const Triple& t = bend ? bends_[k - springs] : shears_[k - springs - bends];
        const auto f = bend ? BendForces(x[t.a], x[t.b], x[t.c], t.constant, t.arm)
                            : ShearForces(x[t.a], x[t.b], x[t.c], t.rest_angle, t.constant, t.arm);
        const size_t slot = 2 * springs + 3 * (k - springs);
        contributions_[slot] = f[0], contributions_[slot + 1] = f[1], contributions_[slot + 2] = f[2];
      }
    }
  });
  a.resize(x.size());
  ParallelFor(chunks(x.size()), threads_, [&](size_t chunk, unsigned) {
    for (size_t p = chunk * kChunk, end = std::min(x.size(), p + kChunk); p < end; ++p) {
      glm::vec3 sum = mechanics_.gravity - mechanics_.air_viscosity * v[p];
      for (uint32_t i = incidence_offsets_[p]; i < incidence_offsets_[p + 1]; ++i) sum += contributions_[incidence_[i]];
      a[p] = sum;
    }
  });
  if (contacts_) AddSelfContact(x, v, closest, dt, a);
  // The colliders' fields push along their normals; friction opposes what else
  // would move the point along the surface (eq. 3 and the static threshold
  // K_s·|F|). What a collider does to a point (of unit mass) it feels the
  // opposite of, summed per chunk and then in the chunks' order.
  const size_t colliders = colliders_.size();
  chunk_push_.assign(chunks(x.size()) * colliders, glm::vec3(0.0f));
  ParallelFor(chunks(x.size()), threads_, [&](size_t chunk, unsigned) {
    for (size_t p = chunk * kChunk, end = std::min(x.size(), p + kChunk); p < end; ++p) {
      if (pinned_[p]) {
        a[p] = glm::vec3(0.0f);
        continue;
      }
      for (size_t k = 0; k < colliders; ++k) {
        const Contact contact = colliders_[k].Nearest(x[p], placed[k].displacement);
        if (contact.distance >= field_.half_thickness()) continue;
        const glm::vec3 before = a[p];
        const float normal_force = field_(std::max(contact.distance, kNearestField * field_.core()));
        const glm::vec3 n = contact.normal;
        const glm::vec3 tangential_force = a[p] - glm::dot(a[p], n) * n;
        const glm::vec3 relative = v[p] - placed[k].velocity;
        const glm::vec3 slip = relative - glm::dot(relative, n) * n;
        const float slip_speed = glm::length(slip);
        // The fibre layer damps the approach and the parting, but never pulls.
        a[p] += std::max(normal_force - mechanics_.contact_damping * glm::dot(relative, n), 0.0f) * n;
        if (slip_speed <= mechanics_.dynamic_friction * normal_force * dt &&
            glm::length(tangential_force) <= mechanics_.static_friction * normal_force) {
          a[p] -= tangential_force + slip / dt;  // held
        } else if (slip_speed > 0.0f) {
          a[p] -= std::min(mechanics_.dynamic_friction * normal_force, slip_speed / dt) * slip / slip_speed;
        }
        chunk_push_[chunk * colliders + k] -= a[p] - before;
      }
    }
  });
  push.assign(colliders, glm::vec3(0.0f));
  for (size_t chunk = 0; chunk < chunks(x.size()); ++chunk) {
    for (size_t k = 0; k < colliders; ++k) push[k] += chunk_push_[chunk * colliders + k];
  }
}

void KnitSimulation::AddSelfContact(const std::vector<glm::vec3>& x, const std::vector<glm::vec3>& v,
                                    const std::vector<PairGeometry>& closest, float dt,
                                    std::vector<glm::vec3>& a) const {
  // A point feels the layer of cloth nearest it on each side: of its pairs
  // within T whose offset from the triangle's nearest point lies within the
  // cone about the triangle's normal, the nearest, and the nearest on the other
  // side (a point between two layers). It is pushed away along the offset and
  // the triangle's corners the other way, split by the nearest point's weights,
  // each with half the field, since two layers in contact meet from both sides
  // (each one's points against the other's triangles); dynamic self-friction
  // opposes their relative slip.
  struct Touch {
    uint32_t triangle;
    glm::vec3 u, weights;
    float d;
  };
  const float cos_cone = std::cos(glm::radians(mechanics_.cone_degrees));
  const std::vector<glm::uvec3>& triangles = contacts_->triangles();
  const std::vector<PointTriangle>& pairs = contacts_->pairs();
  const auto apply = [&](uint32_t point, const Touch& touch) {
    const glm::uvec3 t = triangles[touch.triangle];
    const glm::vec3 w = touch.weights;
    const auto push = [&](glm::vec3 f) {
      a[point] += f;
      a[t.x] -= w.x * f, a[t.y] -= w.y * f, a[t.z] -= w.z * f;
    };
    const float depth = std::max(touch.d, kNearestField * field_.core());
    const glm::vec3 relative = v[point] - (w.x * v[t.x] + w.y * v[t.y] + w.z * v[t.z]);
    push(0.5f * std::max(field_(depth) - mechanics_.contact_damping * glm::dot(relative, touch.u), 0.0f) * touch.u);
    const glm::vec3 slip = relative - glm::dot(relative, touch.u) * touch.u;
    const float slip_speed = glm::length(slip);
    if (slip_speed > 0.0f) {
      // The pair's relative velocity changes by f·dt·(1 + Σw²) under a force f.
      const float stop = slip_speed / (dt * (1.0f + glm::dot(w, w)));
      push(-std::min(0.5f * mechanics_.dynamic_friction * self_friction_field_(depth), stop) * slip / slip_speed);
    }
  };
  // Each point's pairs are consecutive. Its touches are chosen in parallel (the
  // closest points are the work) and applied in the pairs' order after, so the
  // sums do not depend on the thread count.
  std::vector<size_t> starts;
  for (size_t k = 0; k < pairs.size(); ++k) {
    if (k == 0 || pairs[k].point != pairs[k - 1].point) starts.push_back(k);
  }
  starts.push_back(pairs.size());
  const size_t points = starts.size() - 1;
  std::vector<std::optional<Touch>> nearest(points), across(points);
  ParallelFor((points + kPairChunk - 1) / kPairChunk, threads_, [&](size_t chunk, unsigned) {
    for (size_t g = chunk * kPairChunk, end = std::min(points, g + kPairChunk); g < end; ++g) {
      const uint32_t point = pairs[starts[g]].point;
      for (size_t k = starts[g]; k < starts[g + 1]; ++k) {
        const TrianglePoint& q = closest[k].nearest;
        if (q.weights == glm::vec3(0.0f)) continue;
        const uint32_t triangle = pairs[k].triangle;
        const glm::uvec3 t = triangles[triangle];
        const glm::vec3 offset = x[point] - q.point;
        const float d = glm::length(offset);
        if (d >= field_.half_thickness() || !(d > 0.0f)) continue;
        const glm::vec3 normal = glm::cross(x[t.y] - x[t.x], x[t.z] - x[t.x]);
        const float twice_area = glm::length(normal);
        if (!(twice_area > 0.0f) || std::abs(glm::dot(offset, normal)) < cos_cone * twice_area * d) continue;
        const Touch touch{triangle, offset / d, q.weights, d};
        if (!nearest[g] || d < nearest[g]->d) {
          if (nearest[g] && glm::dot(nearest[g]->u, touch.u) < 0.0f) across[g] = nearest[g];
          nearest[g] = touch;
        } else if (glm::dot(nearest[g]->u, touch.u) < 0.0f && (!across[g] || d < across[g]->d)) {
          across[g] = touch;
        }
      }
    }
  });
  for (size_t g = 0; g < points; ++g) {
    const uint32_t point = pairs[starts[g]].point;
    // A later nearest may leave `across` on its own side.
    if (nearest[g]) apply(point, *nearest[g]);
    if (across[g] && glm::dot(nearest[g]->u, across[g]->u) < 0.0f) apply(point, *across[g]);
  }
}

void KnitSimulation::ClosestPoints(const std::vector<glm::vec3>& x, std::vector<PairGeometry>& out) const {
  const std::vector<PointTriangle>& pairs = contacts_->pairs();
  const std::vector<glm::uvec3>& triangles = contacts_->triangles();
  const float reach2 = field_.half_thickness() * field_.half_thickness();
  out.resize(pairs.size());
  ParallelFor((pairs.size() + kPairChunk - 1) / kPairChunk, threads_, [&](size_t chunk, unsigned) {
    for (size_t i = chunk * kPairChunk, end = std::min(pairs.size(), i + kPairChunk); i < end; ++i) {
      const glm::uvec3 t = triangles[pairs[i].triangle];
      const glm::vec3 p = x[pairs[i].point];
      const glm::vec3 normal = glm::cross(x[t.y] - x[t.x], x[t.z] - x[t.x]);
      const float side = glm::dot(p - x[t.x], normal), area2 = glm::dot(normal, normal);
      out[i].nearest = area2 > 0.0f && side * side >= reach2 * area2
                           ? TrianglePoint{}
                           : ClosestPointOnTriangle(p, x[t.x], x[t.y], x[t.z]);
      out[i].side = side;
    }
  });
}

const std::vector<KnitSimulation::PairGeometry>& KnitSimulation::PresentClosestPoints() {
  if (present_closest_search_ != contacts_->searches()) {
    ClosestPoints(x_, present_closest_);
    present_closest_search_ = contacts_->searches();
  }
  return present_closest_;
}

float KnitSimulation::StableStep() {
  // ω² of a point: the stiffness of everything acting on it (unit mass). An
  // angle force of constant c and arm r moves its middle point with stiffness
  // about 4c/r.
  std::vector<float> stiffness(x_.size(), 0.0f);
  for (const Spring& s : springs_) {
    // At least the stiffness at the interval's edge: a step may carry a spring
    // out of it.
    const float k =
        std::max(SpringStiffness(*s.law, s.rest, glm::length(x_[s.b] - x_[s.a])),
                 std::max(s.law->stretch / s.law->balance_high, s.law->compress / s.law->balance_low) / s.rest);
    stiffness[s.a] += k;
    stiffness[s.b] += k;
  }
  for (const auto* triples : {&bends_, &shears_}) {
    for (const Triple& t : *triples) {
      const float k = t.constant / t.arm;
      stiffness[t.a] += k;
      stiffness[t.b] += 4.0f * k;
      stiffness[t.c] += k;
    }
  }
  // A point closing on a surface within the field at speed s from distance d
  // steps at most travel·d/s: it cannot overshoot into the field's barrier,
  // whose stiffness the bound above sees only once the point is there.
  float step = std::numeric_limits<float>::infinity();
  const auto closing = [&](float d, float speed) {
    if (speed > 0.0f) step = std::min(step, mechanics_.travel * d / speed);
  };
  if (contacts_) {
    // Each pair's stiffness and closing speed in parallel (the closest points are
    // the work), then added up in the pairs' order.
    const std::vector<PointTriangle>& pairs = contacts_->pairs();
    const std::vector<PairGeometry>& closest = PresentClosestPoints();
    struct PairStiffness {
      float k = 0.0f, d = 0.0f, closing = 0.0f;  // d = 0: not within the field
    };
    std::vector<PairStiffness> per_pair(pairs.size());
    ParallelFor((pairs.size() + kPairChunk - 1) / kPairChunk, threads_, [&](size_t chunk, unsigned) {
      for (size_t i = chunk * kPairChunk, end = std::min(pairs.size(), i + kPairChunk); i < end; ++i) {
        const TrianglePoint& q = closest[i].nearest;
        if (q.weights == glm::vec3(0.0f)) continue;
        const glm::uvec3 t = contacts_->triangles()[pairs[i].triangle];
        const glm::vec3 x = x_[pairs[i].point];
        const float d = glm::distance(x, q.point);
        if (d >= field_.half_thickness() || !(d > 0.0f)) continue;
        const glm::vec3 w = q.weights;
        const glm::vec3 relative = v_[pairs[i].point] - (w.x * v_[t.x] + w.y * v_[t.y] + w.z * v_[t.z]);
        per_pair[i] = {-field_.Slope(std::max(d, kNearestField * field_.core())), d,
                       -glm::dot(relative, (x - q.point) / d)};
      }
    });
    for (size_t i = 0; i < pairs.size(); ++i) {
      if (per_pair[i].d == 0.0f) continue;
      const glm::uvec3 t = contacts_->triangles()[pairs[i].triangle];
      const float k = per_pair[i].k;
      stiffness[pairs[i].point] += k;
      stiffness[t.x] += k, stiffness[t.y] += k, stiffness[t.z] += k;
      closing(per_pair[i].d, per_pair[i].closing);
    }
  }
  // A free ball feels the stiffness of every point in its field, over its mass.
  std::vector<float> ball_stiffness(colliders_.size(), 0.0f);
  float omega2 = 0.0f, speed = 0.0f;
  for (size_t p = 0; p < x_.size(); ++p) {
    if (pinned_[p]) continue;
    for (size_t k = 0; k < colliders_.size(); ++k) {
      const Contact contact = colliders_[k].Nearest(x_[p], placed_[k].displacement);
      if (contact.distance >= field_.half_thickness()) continue;
      const float d = std::max(contact.distance, kNearestField * field_.core());
      stiffness[p] -= field_.Slope(d);
      ball_stiffness[k] -= field_.Slope(d);
      closing(d, -glm::dot(v_[p] - placed_[k].velocity, contact.normal));
    }
    omega2 = std::max(omega2, stiffness[p]);
    speed = std::max(speed, glm::length(v_[p]));
  }
  for (size_t k = 0; k < colliders_.size(); ++k) {
    if (MovesFreely(k)) omega2 = std::max(omega2, ball_stiffness[k] / bodies_[k].mass);
  }
  if (omega2 > 0.0f) step = std::min(step, mechanics_.courant / std::sqrt(omega2));
  if (speed > 0.0f) step = std::min(step, mechanics_.travel * (field_.half_thickness() - field_.core()) / speed);
  return step;
}

KnitSimulation::ClothCrossing KnitSimulation::CrossCloth(const std::vector<glm::vec3>& x) {
  const std::vector<glm::uvec3>& triangles = contacts_->triangles();
  const std::vector<PointTriangle>& pairs = contacts_->pairs();
  const float nearest_field = kNearestField * field_.core();
  ClosestPoints(x, next_closest_);
  next_closest_search_ = contacts_->searches();
  // The sides at the present positions, kept unless the pairs were searched again.
  const bool kept = present_closest_search_ == contacts_->searches();
  // Whether pair i's point enters its triangle's field or crosses it; `least`
  // keeps its distance at x when within the field.
  const auto enters = [&](size_t i, float& least) {
    const PointTriangle& pair = pairs[i];
    const glm::uvec3 t = triangles[pair.triangle];
    const size_t p = pair.point;
    if (next_closest_[i].nearest.weights != glm::vec3(0.0f)) {
      const float d = glm::distance(x[p], next_closest_[i].nearest.point);
      least = std::min(least, d);
      if (d < nearest_field &&
          glm::distance(x_[p], ClosestPointOnTriangle(x_[p], x_[t.x], x_[t.y], x_[t.z]).point) >= nearest_field) {
        return true;
      }
    }
    const float before = kept ? present_closest_[i].side
                              : glm::dot(x_[p] - x_[t.x], glm::cross(x_[t.y] - x_[t.x], x_[t.z] - x_[t.x]));
    const float after = next_closest_[i].side;
    if (before == 0.0f || (before > 0.0f) == (after > 0.0f)) return false;
    // Where the point meets the plane, taking the motion as linear.
    const float s = before / (before - after);
    const auto at = [&](size_t q) { return glm::mix(x_[q], x[q], s); };
    const glm::vec3 w = ProjectedWeights(at(p), at(t.x), at(t.y), at(t.z));
    return w.x >= 0.0f && w.y >= 0.0f && w.z >= 0.0f && w != glm::vec3(0.0f);
  };
  const size_t chunks = (pairs.size() + kPairChunk - 1) / kPairChunk;
  std::vector<float> least(chunks, std::numeric_limits<float>::infinity());
  std::atomic<bool> entered{false};
  ParallelFor(chunks, threads_, [&](size_t chunk, unsigned) {
    for (size_t i = chunk * kPairChunk, end = std::min(pairs.size(), i + kPairChunk); i < end; ++i) {
      if (enters(i, least[chunk])) entered = true;
    }
  });
  return {entered, least.empty() ? std::numeric_limits<float>::infinity()
                                 : *std::min_element(least.begin(), least.end())};
}

bool KnitSimulation::Penetrates(const std::vector<glm::vec3>& x, const std::vector<Placement>& placed,
                                float& self_distance) {
  const float nearest_field = kNearestField * field_.core();
  self_distance = std::numeric_limits<float>::quiet_NaN();
  for (size_t p = 0; p < x.size(); ++p) {
    if (pinned_[p]) continue;
    for (size_t k = 0; k < colliders_.size(); ++k) {
      if (colliders_[k].Nearest(x[p], placed[k].displacement).distance < nearest_field &&
          colliders_[k].Nearest(x_[p], placed_[k].displacement).distance >= nearest_field) {
        return true;
      }
    }
  }
  if (!contacts_) return false;
  const ClothCrossing crossing = CrossCloth(x);
  self_distance = crossing.least;
  return crossing.enters;
}

float KnitSimulation::ColliderDistance(const std::vector<glm::vec3>& x, const std::vector<Placement>& placed) const {
  float least = std::numeric_limits<float>::infinity();
  for (size_t p = 0; p < x.size(); ++p) {
    if (pinned_[p]) continue;
    for (size_t k = 0; k < colliders_.size(); ++k) {
      least = std::min(least, colliders_[k].Nearest(x[p], placed[k].displacement).distance);
    }
  }
  return least;
}

void KnitSimulation::Integrate(float dt, std::vector<glm::vec3>& x, std::vector<glm::vec3>& v,
                               std::vector<Placement>& placed) {
  // Second-order Runge–Kutta (midpoint), free balls with the cloth.
  if (contacts_) contacts_->Update(x_);
  static const std::vector<PairGeometry> kNone;
  Accelerations(x_, v_, placed_, contacts_ ? PresentClosestPoints() : kNone, dt, a1_, push_start_);
  x_mid_.resize(x_.size());
  v_mid_.resize(x_.size());
  for (size_t p = 0; p < x_.size(); ++p) {
    x_mid_[p] = x_[p] + 0.5f * dt * v_[p];
    v_mid_[p] = v_[p] + 0.5f * dt * a1_[p];
  }
  PlaceColliders(0.5f * dt, placed_, push_start_, placed_mid_);
  if (contacts_) {
    contacts_->Update(x_mid_);
    ClosestPoints(x_mid_, mid_closest_);
  }
  Accelerations(x_mid_, v_mid_, placed_mid_, mid_closest_, dt, a2_, push_mid_);
  x.resize(x_.size());
  v.resize(x_.size());
  for (size_t p = 0; p < x_.size(); ++p) {
    x[p] = x_[p] + dt * v_mid_[p];
    v[p] = v_[p] + dt * a2_[p];
  }
  PlaceColliders(dt, placed_mid_, push_mid_, placed);
  Smooth(dt, x, v);
  MovePins(time_ + dt, x, v);
}

void KnitSimulation::Smooth(float dt, std::vector<glm::vec3>& x, std::vector<glm::vec3>& v) {
  const float s = 1.0f - std::exp(-mechanics_.smoothing_rate * dt);
  if (!(s > 0.0f)) return;
  // The mean of a point's grid neighbours' displacement (then velocity) over the
  // step; a pinned neighbour's is zero.
  const auto smooth = [&](const auto& value, std::vector<glm::vec3>& out) {
    mean_.resize(x.size());
    for (int j = 0; j < cloth_.along; ++j) {
      for (int i = 0; i < cloth_.across; ++i) {
        glm::vec3 sum(0.0f);
        int n = 0;
        for (const glm::ivec2 step : {glm::ivec2(-1, 0), glm::ivec2(1, 0), glm::ivec2(0, -1), glm::ivec2(0, 1)}) {
          const int ni = i + step.x, nj = j + step.y;
          if (ni < 0 || nj < 0 || ni >= cloth_.across || nj >= cloth_.along) continue;
          sum += value(cloth_.Index(ni, nj));
          ++n;
        }
        mean_[cloth_.Index(i, j)] = sum / static_cast<float>(n);
      }
    }
    for (size_t p = 0; p < x.size(); ++p) {
      if (!pinned_[p]) out[p] += s * (mean_[p] - value(p));
    }
  };
  smooth([&](size_t p) { return x[p] - x_[p]; }, x);
  smooth([&](size_t p) { return v[p]; }, v);
}

void KnitSimulation::Advance(float duration, float max_step) {
  if (!(max_step > 0.0f)) throw Error(ErrorCode::kInvalidArgument, "knit simulation: max_step must be > 0");
  std::vector<glm::vec3> x, v;
  std::vector<Placement> placed;
  const double end = time_ + duration;
  while (time_ < end) {
    if (contacts_) contacts_->Update(x_);
    double until = end;  // the step ends at the next release
    for (const Pinned& pin : pins_) {
      if (pin.release > time_) until = std::min(until, pin.release);
    }
    for (const Body& body : bodies_) {
      if (body.mass > 0.0f && body.release > time_) until = std::min(until, body.release);
    }
    float dt = std::min({max_step, StableStep(), static_cast<float>(until - time_)});
    if (!(dt >= kShortestStep) && until - time_ >= kShortestStep) {
      throw Error(ErrorCode::kInvalidArgument,
                  "knit simulation: at " + std::to_string(time_) +
                      " s the stable step fell below 0.1 µs (the cloth was driven harder than the model follows: "
                      "a collider or pin too fast, or the cloth crushed)");
    }
    // A point outside a collider now must stay outside, and on its side of the
    // cloth's triangles; halve the step until it does.
    float self_distance = 0.0f;
    for (int halving = 0;; ++halving) {
      Integrate(dt, x, v, placed);
      if (contacts_) contacts_->Update(x);
      if (!Penetrates(x, placed, self_distance)) break;
      if (halving == mechanics_.max_halvings) {
        ++counts_.penetrations;
        break;
      }
      ++counts_.halvings;
      dt *= 0.5f;
    }
    x_.swap(x);
    v_.swap(v);
    placed_.swap(placed);
    // The crossing check of the step taken found the closest points at x_ (unless
    // a collider's penetration cut it short).
    if (contacts_ && !std::isnan(self_distance)) {
      present_closest_.swap(next_closest_);
      present_closest_search_ = next_closest_search_;
    } else {
      present_closest_search_ = -1;
    }
    // A pin or ball released now leaves with the velocity of its last step.
    const double previous = time_;
    time_ = until - time_ <= dt ? until : time_ + dt;
    for (size_t k = 0; k < colliders_.size(); ++k) {
      const Motion& motion = colliders_[k].motion();
      if (!MovesFreely(k)) {
        placed_[k] = {motion.Displacement(time_), motion.Velocity(time_)};
      } else if (bodies_[k].release > previous) {
        placed_[k].velocity = motion.Velocity(previous);
      }
    }
    for (size_t k = 0; k < pins_.size();) {
      if (pins_[k].release <= time_) {
        pinned_[pins_[k].index] = 0;
        v_[pins_[k].index] = pins_[k].motion.Velocity(previous);
        pins_.erase(pins_.begin() + static_cast<std::ptrdiff_t>(k));
      } else {
        ++k;
      }
    }
    min_distance_ = std::min(min_distance_, ColliderDistance(x_, placed_));
    if (contacts_) {
      // A step taken though it penetrates a collider was not checked against the cloth.
      if (std::isnan(self_distance)) self_distance = CrossCloth(x_).least;
      min_self_distance_ = std::min(min_self_distance_, self_distance);
    }
    ++counts_.steps;
  }
}

}  // namespace loom::animate
