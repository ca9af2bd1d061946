#include "core/fabric/knit_tile.h"

#include <algorithm>
#include <array>
#include <cmath>
#include <random>

#include "core/fabric/cardinal_spline.h"

namespace loom {
namespace {

// The paper's six key points per loop, the sinker k0 split in two (knit_tile.h).
constexpr int kKeysPerLoop = 7;

// +1 where loop (wale, course) is a knit stitch (pulled through the loop below from
// the back to the front, the face +z), -1 where it is a purl stitch.
int StitchSign(const v1::KnitSpec& knit, uint32_t wale, uint32_t course) {
  switch (knit.pattern()) {
    case v1::KNIT_PATTERN_REVERSE: return -1;
    case v1::KNIT_PATTERN_GARTER: return course % 2 == 0 ? 1 : -1;
    case v1::KNIT_PATTERN_RIB: return wale % (knit.rib_knit() + knit.rib_purl()) < knit.rib_knit() ? 1 : -1;
    case v1::KNIT_PATTERN_SEED: return (wale + course) % 2 == 0 ? 1 : -1;
    default: return 1;
  }
}

uint32_t LoopYarn(const v1::KnitSpec& knit, uint32_t wale, uint32_t course) {
  if (knit.colour_pattern().empty()) return 0;
  const uint64_t loop = uint64_t{course} * knit.wales() + wale;
  return knit.colour_pattern(static_cast<int>(loop % knit.colour_pattern_size()));
}

// Random key-point offsets, uniform in [-√3σ, √3σ]³ per key point so each component has
// standard deviation σ and the offset is bounded. Drawn from the raw 64-bit engine
// output (std::uniform_real_distribution is implementation-defined), in a fixed order
// over the tile's loops, so a seed gives the same tile on every platform.
std::vector<glm::vec3> KeyPointOffsets(const v1::KnitSpec& knit, float sigma) {
  const size_t count = size_t{knit.wales()} * knit.courses() * kKeysPerLoop;
  std::vector<glm::vec3> offsets(count, glm::vec3(0.0f));
  if (sigma <= 0) return offsets;
  std::mt19937_64 engine(knit.seed());
  const double half_range = std::sqrt(3.0) * sigma;
  auto next = [&] {
    const double unit = static_cast<double>(engine() >> 11) * 0x1.0p-53;  // [0, 1)
    return static_cast<float>((2.0 * unit - 1.0) * half_range);
  };
  for (glm::vec3& offset : offsets) {
    offset.x = next();
    offset.y = next();
    offset.z = next();
  }
  return offsets;
}

// The key points of a knit stitch's left half (the right half mirrors them about the
// cell's centre line x = 0.5): x in loop widths from the cell's left edge; y in loop
// widths from the loop's course line (sinker, foot) or from the course line above
// (shoulder, head), since they place the interlock, whose size is set by the loop
// width; z in yarn radii, knit stitch.
struct KnitLoopShape {
  glm::vec3 sinker;    // k0, split in two at x = ±sinker.x about the cell edge
  glm::vec3 foot;      // k1
  glm::vec3 shoulder;  // k2
  glm::vec3 head;      // k3; x = 0.5
  float tension;       // of the cardinal spline
};

// Results of the clearance search (knit_tile.h), one per loop aspect 0.5, 0.75, ..., 2.
constexpr float kFirstAspect = 0.5f, kAspectStep = 0.25f;
constexpr KnitLoopShape kLoopShapes[] = {
    {{0.182f, -0.578f, -4.888f}, {0.390f, 0.143f, -0.500f}, {0.150f, 0.035f, -0.375f}, {0.5f, 0.347f, -5.250f}, -0.339f},  // 0.5
    {{0.163f, -0.563f, -2.813f}, {0.390f, 0.152f, -0.125f}, {0.110f, -0.107f, 0.000f}, {0.5f, 0.317f, -3.900f}, -0.218f},  // 0.75
    {{0.163f, -0.423f, -2.901f}, {0.390f, 0.152f, -0.125f}, {0.110f, -0.087f, 0.000f}, {0.5f, 0.320f, -3.900f}, -0.183f},  // 1.0
    {{0.196f, -0.387f, -3.076f}, {0.390f, 0.142f, -0.125f}, {0.110f, -0.107f, 0.000f}, {0.5f, 0.307f, -3.900f}, -0.183f},  // 1.25
    {{0.163f, -0.287f, -4.138f}, {0.390f, 0.142f, 0.125f}, {0.110f, -0.107f, 0.850f}, {0.5f, 0.317f, -4.200f}, -0.423f},  // 1.5
    {{0.163f, -0.248f, -5.426f}, {0.390f, 0.152f, -0.787f}, {0.110f, -0.107f, 0.000f}, {0.5f, 0.317f, -3.987f}, -0.447f},  // 1.75
    {{0.156f, -0.203f, -5.626f}, {0.390f, 0.152f, -0.825f}, {0.110f, -0.063f, -0.237f}, {0.5f, 0.317f, -3.188f}, -0.423f},  // 2.0
};

KnitLoopShape LoopShapeForAspect(float aspect) {
  constexpr int last = static_cast<int>(std::size(kLoopShapes)) - 1;
  const float position = std::clamp((aspect - kFirstAspect) / kAspectStep, 0.0f, static_cast<float>(last));
  const int below = std::min(static_cast<int>(position), last - 1);
  const float w = position - static_cast<float>(below);
  const KnitLoopShape& a = kLoopShapes[below];
  const KnitLoopShape& b = kLoopShapes[below + 1];
  return {glm::mix(a.sinker, b.sinker, w), glm::mix(a.foot, b.foot, w), glm::mix(a.shoulder, b.shoulder, w),
          glm::mix(a.head, b.head, w), glm::mix(a.tension, b.tension, w)};
}

}  // namespace

TileYarns BuildKnitYarns(const v1::FabricSpec& fabric, int samples_per_segment) {
  const v1::KnitSpec& knit = fabric.knit();
  const uint32_t wales = knit.wales(), courses = knit.courses();
  const float h = 1.0f / knit.loop_aspect();
  const KnitLoopShape shape = LoopShapeForAspect(knit.loop_aspect());
  float layout_radius = 0.0f;
  for (uint32_t course = 0; course < courses; ++course) {
    for (uint32_t wale = 0; wale < wales; ++wale) {
      layout_radius = std::max(layout_radius, fabric.yarns(LoopYarn(knit, wale, course)).radius());
    }
  }
  const std::vector<glm::vec3> offsets = KeyPointOffsets(knit, knit.loop_jitter() * layout_radius);

  TileYarns tile;
  tile.model_to_tile = glm::vec3(1.0f / wales, 1.0f / (courses * h), 1.0f / wales);
  for (uint32_t course = 0; course < courses; ++course) {
    std::vector<glm::vec3> keys;
    keys.reserve(size_t{wales} * kKeysPerLoop);
    for (uint32_t wale = 0; wale < wales; ++wale) {
      const float x = static_cast<float>(wale), y = static_cast<float>(course) * h;
      const int sign = StitchSign(knit, wale, course);
      const int sign_left = StitchSign(knit, (wale + wales - 1) % wales, course);
      const int sign_above = StitchSign(knit, wale, (course + 1) % courses);
      // A purl stitch mirrors a knit stitch in z. The lower half of a loop (feet, and
      // the sinker's half next to it) follows its own stitch; the upper half
      // (shoulders, head) wraps around the loop above and follows that loop's stitch.
      auto at = [&](float cell_x, glm::vec3 key, float line, int z_sign) {
        return glm::vec3(x + cell_x, line + key.y, static_cast<float>(z_sign) * key.z * layout_radius);
      };
      const std::array<glm::vec3, kKeysPerLoop> loop = {
          at(-shape.sinker.x, shape.sinker, y, sign_left),
          at(shape.sinker.x, shape.sinker, y, sign),
          at(shape.foot.x, shape.foot, y, sign),
          at(shape.shoulder.x, shape.shoulder, y + h, sign_above),
          at(0.5f, shape.head, y + h, sign_above),
          at(1.0f - shape.shoulder.x, shape.shoulder, y + h, sign_above),
          at(1.0f - shape.foot.x, shape.foot, y, sign),
      };
      const size_t first = (size_t{course} * wales + wale) * kKeysPerLoop;
      for (int k = 0; k < kKeysPerLoop; ++k) keys.push_back(loop[k] + offsets[first + k]);
    }
    const glm::vec3 period(static_cast<float>(wales), 0.0f, 0.0f);
    const std::vector<SplineSample<glm::vec3>> samples =
        SamplePeriodicCardinalSpline<glm::vec3>(keys, period, shape.tension, samples_per_segment);

    PeriodicYarn yarn;
    yarn.period = period;
    for (const SplineSample<glm::vec3>& sample : samples) {
      yarn.points.push_back(sample.position);
      yarn.tangents.push_back(glm::normalize(sample.derivative));
    }
    const size_t per_loop = size_t{kKeysPerLoop} * samples_per_segment;
    for (size_t i = 0; i + 1 < samples.size(); ++i) {
      yarn.segment_yarn.push_back(LoopYarn(knit, static_cast<uint32_t>(i / per_loop), course));
    }
    // A point takes the radius of the loop its segment belongs to; the closing point
    // repeats the first.
    for (size_t i = 0; i + 1 < samples.size(); ++i) {
      yarn.section.emplace_back(glm::vec2(fabric.yarns(yarn.segment_yarn[i]).radius()));
    }
    yarn.section.push_back(yarn.section.front());
    tile.yarns.push_back(std::move(yarn));
  }
  return tile;
}

}  // namespace loom
