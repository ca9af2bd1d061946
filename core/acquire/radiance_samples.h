#pragma once
// The output of acquisition and the input of fitting (Daubert 2001 §4-§5): for one
// fabric tile, per texel an average normal and tangent, per (texel, view) a
// coverage alpha, and per (texel, view, light) an RGB radiance.
//
// Layout. Texel (x, y) covers tile space [x/res, (x+1)/res) × [y/res, (y+1)/res);
// its index is y·res + x. Views and lights are HemisphereGridDirections order
// (core/acquire/hemisphere_directions.h), unit vectors in tile space pointing away
// from the fabric (towards the viewer / the light); lights behind the cloth are that
// grid mirrored (z negated, acquisition's LightSide::kBack). The arrays are texel-major, so a
// texel's samples are contiguous (fitting works per texel, and a mip level pools
// 2×2 texels):
//   alpha[texel·V + view]                      coverage in [0, 1]
//   radiance[(texel·V + view)·L + light]       RGB; 0 where alpha is 0
//   normals[texel], tangents[texel]            unit; tangent ⟂ normal, in the plane
//                                              of the normal and +x, with t·x ≥ 0
//   normal_lengths[texel]                      |mean of the hit normals| in [0, 1]:
//                                              1 where every ray met yarn facing one
//                                              way; with alpha it weights the texel's
//                                              normal when a mip level averages them
//   view_heights[view]                         tile z of the plane the view's texels
//                                              are indexed on: texel (x, y) holds the
//                                              view's rays that cross that plane
//                                              inside it (PrecomputeSettings.sampling_plane)
// Radiance is per unit irradiance of a directional light at normal incidence (the
// convention of core/acquire/acquisition.h). Every value is finite.
//
// File (version 3), little-endian, no padding:
//   offset 0   char[8]  magic "LOOMRSMP"
//          8   u32      version (3)
//         12   u32      resolution
//         16   u32      V (view count)
//         20   u32      L (light count)
//         24   f32      view_directions[V][3], light_directions[L][3], view_heights[V],
//                       normals[res²][3], tangents[res²][3], normal_lengths[res²],
//                       alpha[res²][V], radiance[res²][V][L][3]
//   end − 64   char[64] SHA-256 (lowercase hex) of every byte before it
// Reading verifies the checksum, the dimensions against the caps of
// core/spec/limits.h, the exact size and that every number is finite; a file that
// fails any of these is Error(kInvalidArgument) saying which.

#include <cstdint>
#include <filesystem>
#include <glm/glm.hpp>
#include <string>
#include <string_view>
#include <vector>

namespace loom {

struct RadianceSamples {
  uint32_t resolution = 0;
  std::vector<glm::vec3> view_directions;
  std::vector<glm::vec3> light_directions;
  std::vector<float> view_heights;
  std::vector<glm::vec3> normals;
  std::vector<glm::vec3> tangents;
  std::vector<float> normal_lengths;
  std::vector<float> alpha;
  std::vector<glm::vec3> radiance;

  RadianceSamples() = default;
  // Zero samples with the given directions; normals +z, tangents +x, lengths 1,
  // every view indexed on the plane z = 0.
  RadianceSamples(uint32_t resolution, std::vector<glm::vec3> views, std::vector<glm::vec3> lights);

  size_t texel_count() const { return size_t{resolution} * resolution; }
  size_t view_count() const { return view_directions.size(); }
  size_t light_count() const { return light_directions.size(); }

  size_t AlphaIndex(size_t texel, size_t view) const { return texel * view_count() + view; }
  size_t RadianceIndex(size_t texel, size_t view, size_t light) const {
    return AlphaIndex(texel, view) * light_count() + light;
  }

  // Mean coverage over every texel and view (a figure the CLI reports).
  double MeanAlpha() const;

  bool operator==(const RadianceSamples&) const = default;
};

// The texel tangent convention above (Daubert §4): the binormal n × x is
// perpendicular to the normal and the x axis, and the tangent b × n = x − n (n·x)
// lies in the plane of n and x. Where n is along x the plane is undefined and y
// takes the x axis's place. Fitted mip levels re-derive it from averaged normals.
glm::vec3 TexelTangent(glm::vec3 normal);

// The file bytes above, and back. `source` names the data in error messages.
// Encoding throws Error(kInvalidArgument) if the arrays disagree with the dimensions.
std::string EncodeRadianceSamples(const RadianceSamples& samples);
RadianceSamples DecodeRadianceSamples(std::string_view bytes, const std::string& source);

// Atomic write (temp name, then rename) and a verified read; a missing file is
// Error(kNotFound).
void WriteRadianceSamples(const RadianceSamples& samples, const std::filesystem::path& path);
RadianceSamples ReadRadianceSamples(const std::filesystem::path& path);

}  // namespace loom
