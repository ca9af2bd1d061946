// loom-lab animate: an animation spec run by the knit model (docs/animation.md),
// written as a glTF sequence and OBJ frames, with its figures.

#include <algorithm>
#include <cstdio>
#include <filesystem>

#include "core/animate/animation.h"
#include "core/animate/cloth_sequence_io.h"
#include "core/scene/scene_geometry.h"
#include "core/spec/spec_json.h"
#include "core/util/progress_bar.h"
#include "lab/lab_command.h"

namespace loom::lab {
namespace {

// JSON has no infinity: a distance never measured is null.
nlohmann::json Distance(float d) { return std::isfinite(d) ? nlohmann::json(d) : nlohmann::json(nullptr); }

}  // namespace

LabCommand AddAnimateCommand(CLI::App& app, const LabFlags& flags) {
  struct Options {
    std::string spec, gltf, obj_dir;
    unsigned threads = 0;
  };
  auto options = std::make_shared<Options>();
  auto* command = app.add_subcommand("animate", "Simulate an animation spec's knit cloth and write its frames");
  command->add_option("spec", options->spec, "Animation spec file (JSON)")->required();
  command->add_option("--gltf", options->gltf, "Write the sequence as glTF 2.0 (.glb binary, .gltf JSON)");
  command->add_option("--obj-dir", options->obj_dir, "Write frame_NNNNN.obj per frame into this directory");
  command->add_option("--threads", options->threads, "Threads of the contact search (0: every core)");
  return {command, [&flags, options] {
            const auto spec = LoadSpecFile<v1::AnimationSpec>(options->spec, "animation");
            animate::ClothAnimation animation;
            {
              ProgressBar bar("animate");
              animation = animate::RunAnimation(
                  spec, [&](size_t done, size_t total) { bar.Update(double(done) / total, "frames"); },
                  options->threads, FileMeshResolver(std::filesystem::path(options->spec).parent_path()));
            }
            if (!options->gltf.empty() || !options->obj_dir.empty()) {
              const MeshSequence sequence = animate::ClothSequence(animation);
              if (!options->gltf.empty()) {
                animate::WriteGltfSequence(sequence, options->gltf, animate::SolidTracks(animation));
              }
              if (!options->obj_dir.empty()) animate::WriteObjSequence(sequence, options->obj_dir);
            }
            const auto& counts = animation.counts;
            const size_t triangles = 2 * size_t(animation.cloth.across - 1) * (animation.cloth.along - 1);
            // Each sphere's centre: its lowest height, the highest it rises to after
            // that (a rebound), and where it ends.
            nlohmann::json spheres = nlohmann::json::array();
            for (size_t k = 0; k < animation.colliders.size(); ++k) {
              if (!animation.colliders[k].sphere()) continue;
              const std::vector<glm::vec3>& track = animation.collider_tracks[k];
              const glm::vec3 centre = animation.colliders[k].centre();
              const auto lower = [](glm::vec3 a, glm::vec3 b) { return a.z < b.z; };
              const auto lowest = std::min_element(track.begin(), track.end(), lower);
              const float rebound = std::max_element(lowest, track.end(), lower)->z;
              const glm::vec3 end = centre + track.back();
              spheres.push_back({{"collider", k},
                                 {"lowest_centre_z", centre.z + lowest->z},
                                 {"rebound_centre_z", centre.z + rebound},
                                 {"final_centre", {end.x, end.y, end.z}}});
            }
            if (flags.json) {
              PrintJson({{"loops", animation.cloth.size()},
                         {"spheres", spheres},
                         {"triangles", triangles},
                         {"frames", animation.frames.size() - 1},
                         {"simulated_seconds", (animation.frames.size() - 1) / animation.frames_per_second},
                         {"simulation_seconds", animation.simulation_seconds},
                         {"steps", counts.steps},
                         {"halvings", counts.halvings},
                         {"penetrations", counts.penetrations},
                         {"contact_searches", counts.contact_searches},
                         {"min_collider_distance", Distance(animation.min_collider_distance)},
                         {"min_self_distance", Distance(animation.min_self_distance)}});
            } else {
              std::printf(
                  "%zu loops (%zu triangles), %zu frames at %g fps: simulated in %.2f s, %ld steps (%ld halved), "
                  "%ld penetrations, %ld contact searches; least distance to a collider %.4f, to itself %.4f "
                  "(loops)\n",
                  animation.cloth.size(), triangles, animation.frames.size() - 1, animation.frames_per_second,
                  animation.simulation_seconds, counts.steps, counts.halvings, counts.penetrations,
                  counts.contact_searches, animation.min_collider_distance, animation.min_self_distance);
            }
            return 0;
          }};
}

}  // namespace loom::lab
