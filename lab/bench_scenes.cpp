#include "lab/bench_scenes.h"

#include <cmath>
#include <map>
#include <nlohmann/json.hpp>
#include <numbers>

#include "core/spec/spec_json.h"
#include "core/spec/spec_math.h"
#include "core/util/error.h"
#include "core/util/file_io.h"

namespace loom::lab {
namespace {

using nlohmann::json;

// The camera stands this far from the origin: beyond the nearest point of the
// longest (80°) patch, so nothing of it falls behind the near plane.
constexpr float kCameraDistance = 10.0f;
// The flat patch overfills the view by this factor so no edge shows.
constexpr double kOverfill = 1.1;

[[noreturn]] void Fail(const std::filesystem::path& file, const std::string& field, const std::string& problem) {
  throw Error(ErrorCode::kInvalidArgument, file.string() + ": " + field + ": " + problem);
}

const json& Field(const json& object, const std::string& name, const std::filesystem::path& file,
                  const std::string& path) {
  if (!object.is_object() || !object.contains(name)) Fail(file, path + name, "missing");
  return object.at(name);
}

// A cloth object covering `shape` scaled by `scale`, tiled `repeat_u` × `repeat_v`.
v1::SceneObject Cloth(const v1::FabricSpec& fabric, v1::BuiltinShape shape, const v1::Vec3& scale,
                      double repeat_u, double repeat_v) {
  v1::SceneObject object;
  object.set_name("cloth");
  object.mutable_mesh()->set_builtin(shape);
  *object.mutable_transform()->mutable_scale() = scale;
  *object.mutable_fabric()->mutable_fabric() = fabric;
  object.mutable_fabric()->set_repeat_u(static_cast<float>(repeat_u));
  object.mutable_fabric()->set_repeat_v(static_cast<float>(repeat_v));
  return object;
}

v1::Camera OrthographicCamera(const v1::Vec3& position, const v1::Vec3& up) {
  v1::Camera camera;
  camera.set_projection(v1::PROJECTION_ORTHOGRAPHIC);
  camera.set_ortho_height(static_cast<float>(kViewHeight));
  *camera.mutable_position() = position;
  *camera.mutable_target() = ToVec3(glm::vec3(0, 0, 0));
  *camera.mutable_up() = up;
  return camera;
}

}  // namespace

std::vector<BenchScene> LoadBenchScenes(const std::filesystem::path& set_file) {
  json set;
  try {
    set = json::parse(ReadFile(set_file));
  } catch (const json::parse_error& e) {
    Fail(set_file, "(file)", std::string("not JSON: ") + e.what());
  }
  const std::filesystem::path directory = set_file.parent_path();
  const json& frame = Field(set, "frame", set_file, "");
  const int width = Field(frame, "width", set_file, "frame.").get<int>();
  const int height = Field(frame, "height", set_file, "frame.").get<int>();
  if (width < 1 || height < 1) Fail(set_file, "frame", "width and height must be positive");

  v1::SceneSpec base = ParseSpecJson<v1::SceneSpec>(Field(set, "template", set_file, "").dump(), "template");
  base.mutable_render()->set_width(width);
  base.mutable_render()->set_height(height);

  std::map<std::string, double> distances;
  const auto read_distances = [&](const json& list, const std::string& path) {
    std::vector<std::string> order;
    for (const json& distance : list) {
      const std::string name = Field(distance, "name", set_file, path + "[].").get<std::string>();
      const double pixels = Field(distance, "tile_pixels", set_file, path + "[].").get<double>();
      if (!(pixels > 0.0)) Fail(set_file, path + "[" + name + "].tile_pixels", "must be > 0");
      if (distances.contains(name) && distances.at(name) != pixels) {
        Fail(set_file, path + "[" + name + "]", "a distance of that name has another tile_pixels");
      }
      distances[name] = pixels;
      order.push_back(name);
    }
    return order;
  };
  const std::vector<std::string> distance_order = read_distances(Field(set, "distances", set_file, ""), "distances");
  // Variants: more flat scenes of every fabric under other lights or at other
  // distances, named "<fabric>.flat<tilt>.<distance>.<variant>".
  struct Variant {
    std::string name;
    std::vector<double> tilts;
    std::vector<std::string> distances;
    v1::SceneSpec base;
  };
  std::vector<Variant> variants;
  for (const json& entry : set.value("variants", json::array())) {
    Variant variant;
    variant.name = Field(entry, "name", set_file, "variants[].").get<std::string>();
    const std::string path = "variants[" + variant.name + "].";
    variant.tilts = Field(entry, "tilts_degrees", set_file, path).get<std::vector<double>>();
    variant.distances = read_distances(Field(entry, "distances", set_file, path), path + "distances");
    variant.base = base;
    if (entry.contains("lights")) {
      json lights = json::object();
      lights["lights"] = entry.at("lights");
      v1::SceneSpec lit = ParseSpecJson<v1::SceneSpec>(lights.dump(), path + "lights");
      *variant.base.mutable_lights() = lit.lights();
    }
    variants.push_back(std::move(variant));
  }
  const double world_per_pixel = kViewHeight / height;
  const double aspect = static_cast<double>(width) / height;

  std::vector<BenchScene> scenes;
  for (const json& entry : Field(set, "fabrics", set_file, "")) {
    const std::string fabric_name = Field(entry, "name", set_file, "fabrics[].").get<std::string>();
    const auto fabric = LoadSpecFile<v1::FabricSpec>(
        directory / Field(entry, "file", set_file, "fabrics[].").get<std::string>(), "fabric");
    const auto add = [&](const std::string& view, const std::string& distance, v1::SceneObject object,
                         v1::Camera camera, const v1::SceneSpec& scene_base = {}, const std::string& variant = {}) {
      BenchScene bench{fabric_name + "." + view + "." + distance + (variant.empty() ? "" : "." + variant),
                       fabric_name, view, distance, distances.at(distance), variant.empty() ? base : scene_base,
                       variant};
      bench.scene.set_name(bench.name);
      *bench.scene.add_objects() = std::move(object);
      *bench.scene.mutable_camera() = std::move(camera);
      scenes.push_back(std::move(bench));
    };
    // The flat patch at `tilt` and `distance`.
    const auto add_flat = [&](double tilt, const std::string& path, const std::string& distance,
                              const v1::SceneSpec& scene_base, const std::string& variant) {
      if (!(tilt >= 0.0 && tilt <= 85.0)) Fail(set_file, path, "each tilt must lie in [0, 85]");
      const double radians = tilt * std::numbers::pi / 180.0;
      const double extent_u = kOverfill * kViewHeight * aspect;
      const double extent_v = kOverfill * kViewHeight / std::cos(radians);
      const double tile_world = distances.at(distance) * world_per_pixel;
      add("flat" + std::to_string(static_cast<int>(std::lround(tilt))), distance,
          Cloth(fabric, v1::BUILTIN_SHAPE_PLANE, ToVec3(glm::vec3(extent_u, extent_v, 1)), extent_u / tile_world,
                extent_v / tile_world),
          OrthographicCamera(
              ToVec3(glm::vec3(0, -kCameraDistance * std::sin(radians), kCameraDistance * std::cos(radians))),
              ToVec3(glm::vec3(0, 1, 0))),
          scene_base, variant);
    };
    for (const json& tilt_json : Field(set, "tilts_degrees", set_file, "")) {
      for (const std::string& distance : distance_order) {
        add_flat(tilt_json.get<double>(), "tilts_degrees", distance, base, {});
      }
    }
    for (const json& curved : set.value("curved", json::array())) {
      const std::string shape_name = Field(curved, "shape", set_file, "curved[].").get<std::string>();
      const std::string distance = Field(curved, "distance", set_file, "curved[].").get<std::string>();
      if (!distances.contains(distance)) Fail(set_file, "curved[].distance", "no distance named " + distance);
      if (shape_name != "BUILTIN_SHAPE_SPHERE") {
        Fail(set_file, "curved[].shape", "only BUILTIN_SHAPE_SPHERE is laid out so far");
      }
      // u runs once around the equator (2πr), v from pole to pole (πr).
      const double tile_world = distances.at(distance) * world_per_pixel;
      const double r = kCurvedRadius;
      add("sphere", distance,
          Cloth(fabric, v1::BUILTIN_SHAPE_SPHERE, ToVec3(glm::vec3(r, r, r)), 2.0 * std::numbers::pi * r / tile_world,
                std::numbers::pi * r / tile_world),
          OrthographicCamera(ToVec3(glm::vec3(0, -kCameraDistance, 0)), ToVec3(glm::vec3(0, 0, 1))));
    }
    for (const Variant& variant : variants) {
      for (const double tilt : variant.tilts) {
        for (const std::string& distance : variant.distances) {
          add_flat(tilt, "variants[" + variant.name + "].tilts_degrees", distance, variant.base, variant.name);
        }
      }
    }
  }
  return scenes;
}

}  // namespace loom::lab
