#include "core/animate/animation.h"

#include <chrono>
#include <cmath>

#include "core/animate/mesh_distance.h"
#include "core/spec/defaults.h"
#include "core/spec/validate.h"
#include "core/util/error.h"

namespace loom::animate {
namespace {

glm::vec3 ToVec3(const v1::Vec3& v) { return {v.x(), v.y(), v.z()}; }

Motion ToMotion(const google::protobuf::RepeatedPtrField<v1::LinearMotion>& legs) {
  Motion motion;
  for (const v1::LinearMotion& leg : legs) {
    motion.legs.push_back({ToVec3(leg.velocity()), leg.start_seconds(), leg.end_seconds()});
  }
  return motion;
}

// Collider k of the spec; a mesh built as a scene object would be (errors name
// the collider).
Collider ToCollider(const v1::ColliderSpec& spec, int k, const MeshTextResolver& meshes) {
  Collider collider;
  switch (spec.shape_case()) {
    case v1::ColliderSpec::kMesh: {
      const std::string name = "animation.colliders[" + std::to_string(k) + "].mesh";
      v1::SceneSpec scene;
      v1::SceneObject& object = *scene.add_objects();
      *object.mutable_mesh() = spec.mesh().mesh();
      *object.mutable_transform() = spec.mesh().transform();
      const MeshTextResolver read = [&](const v1::MeshRef& mesh, const TextSink& consume) {
        if (!meshes) throw Error(ErrorCode::kInvalidArgument, name + ": mesh files cannot be read here");
        meshes(mesh, consume);
      };
      collider = Collider::Mesh(std::make_shared<const MeshDistance>(BuildSceneGeometry(scene, read).at(0).mesh, name));
      break;
    }
    case v1::ColliderSpec::kPlane:
      collider = Collider::Plane(ToVec3(spec.plane().point()), ToVec3(spec.plane().normal()));
      break;
    case v1::ColliderSpec::kSphere:
      collider = Collider::Sphere(ToVec3(spec.sphere().centre()), spec.sphere().radius());
      break;
    default:
      collider = Collider::Box(ToVec3(spec.box().centre()), ToVec3(spec.box().half_extent()));
      break;
  }
  return collider.Moving(ToMotion(spec.motion()));
}

}  // namespace

std::vector<Collider> BuildColliders(const v1::AnimationSpec& spec, const MeshTextResolver& meshes) {
  std::vector<Collider> colliders;
  for (int k = 0; k < spec.colliders_size(); ++k) colliders.push_back(ToCollider(spec.colliders(k), k, meshes));
  return colliders;
}

KnitMechanics Mechanics(const v1::KnitMechanicsSpec& spec) {
  KnitMechanics mechanics;
  if (spec.has_contact_damping()) mechanics.contact_damping = spec.contact_damping();
  if (spec.has_static_friction()) mechanics.static_friction = spec.static_friction();
  if (spec.has_dynamic_friction()) mechanics.dynamic_friction = spec.dynamic_friction();
  if (spec.has_air_viscosity()) mechanics.air_viscosity = spec.air_viscosity();
  if (spec.has_courant()) mechanics.courant = spec.courant();
  if (spec.has_self_collision()) mechanics.self_collision = spec.self_collision();
  return mechanics;
}

ClothAnimation RunAnimation(const v1::AnimationSpec& raw, const std::function<void(size_t, size_t)>& progress,
                            unsigned threads, const MeshTextResolver& meshes) {
  ThrowIfAny(Validate(raw));
  const v1::AnimationSpec spec = WithDefaults(raw);
  const v1::KnitClothSpec& cloth_spec = spec.cloth();
  ClothAnimation animation;
  animation.cloth = FlatKnitCloth(static_cast<int>(cloth_spec.loops()), static_cast<int>(cloth_spec.courses()),
                                  cloth_spec.course_spacing(), cloth_spec.wale_spacing(), ToVec3(cloth_spec.origin()),
                                  ToVec3(cloth_spec.course_axis()), ToVec3(cloth_spec.wale_axis()));
  animation.frames_per_second = spec.frames_per_second();

  animation.colliders = BuildColliders(spec, meshes);
  KnitMechanics mechanics = Mechanics(spec.mechanics());
  mechanics.threads = threads;
  KnitSimulation simulation(animation.cloth, mechanics, animation.colliders);
  for (int k = 0; k < spec.colliders_size(); ++k) {
    const v1::ColliderSpec& collider = spec.colliders(k);
    if (collider.has_sphere() && collider.sphere().mass() > 0.0f) {
      simulation.Free(static_cast<size_t>(k), collider.sphere().mass(), collider.sphere().release_seconds());
    }
  }
  const KnitCloth& cloth = animation.cloth;
  for (size_t p = 0; p < cloth.size(); ++p) simulation.SetVelocity(p, ToVec3(spec.initial_velocity()));
  for (const v1::PinSpec& pin : spec.pins()) {
    const Motion motion = ToMotion(pin.motion());
    const double release = pin.release_seconds() > 0 ? pin.release_seconds() : std::numeric_limits<double>::infinity();
    const auto hold = [&](int i, int j) { simulation.Pin(cloth.Index(i, j), motion, release); };
    switch (pin.which_case()) {
      case v1::PinSpec::kLoop:
        hold(static_cast<int>(pin.loop().loop()), static_cast<int>(pin.loop().course()));
        break;
      case v1::PinSpec::kCourse:
        for (int i = 0; i < cloth.across; ++i) hold(i, static_cast<int>(pin.course()));
        break;
      default:
        for (int j = 0; j < cloth.along; ++j) hold(static_cast<int>(pin.wale()), j);
        break;
    }
  }

  const size_t steps = AnimationFrames(spec);
  const double frame_time = 1.0 / spec.frames_per_second();
  animation.frames.reserve(steps + 1);
  animation.collider_tracks.resize(animation.colliders.size());
  const auto record = [&] {
    animation.frames.push_back(simulation.positions());
    for (size_t k = 0; k < animation.colliders.size(); ++k) {
      animation.collider_tracks[k].push_back(simulation.collider_displacement(k));
    }
  };
  record();
  const auto start = std::chrono::steady_clock::now();
  for (size_t frame = 1; frame <= steps; ++frame) {
    simulation.Advance(static_cast<float>(frame * frame_time - simulation.time()), static_cast<float>(frame_time));
    record();
    if (progress) progress(frame, steps);
  }
  animation.simulation_seconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
  animation.counts = simulation.counts();
  animation.min_collider_distance = simulation.min_collider_distance();
  animation.min_self_distance = simulation.min_self_distance();
  return animation;
}

}  // namespace loom::animate
