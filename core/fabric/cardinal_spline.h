#pragma once
// Cardinal splines through key points: how the lumislice paper (§3) joins a knit
// loop's six key points into a yarn path, and how a woven thread passes smoothly
// through its crossing heights. A cardinal spline is a Catmull-Rom spline whose
// tangents are scaled by (1 - tension): it interpolates every key point, is C¹, and
// needs no global solve, so moving one key point (a random loop offset) only
// changes the two segments on either side of it.

#include <glm/glm.hpp>
#include <span>
#include <vector>

namespace loom {

// T is glm::vec3 for a space curve or float for a profile (a woven thread's height
// along the thread).
template <typename T>
struct SplineSample {
  T position{};
  T derivative{};  // d position / d t, t advancing by 1 per segment
};

// Samples the cardinal spline through keys[0..n) continued periodically: key i + n
// is keys[i] + period. period = 0 gives a closed loop; a tile period such as (1,0,0)
// gives a yarn that continues into the neighbouring tile. Each segment
// [keys[i], keys[i+1]] contributes samples_per_segment samples starting at keys[i],
// and the result ends with keys[0] + period, so it spans exactly one period:
// n * samples_per_segment + 1 samples. tension in [0, 1): 0 is Catmull-Rom, values
// towards 1 pull the curve towards the key polygon; at 1 the curve stops (zero
// derivative) at every key: a profile then rests flat on each key value.
// Defined for T = float and T = glm::vec3.
template <typename T>
std::vector<SplineSample<T>> SamplePeriodicCardinalSpline(std::span<const T> keys, T period, float tension,
                                                          int samples_per_segment);

}  // namespace loom
