#include "core/fabric/weave_pattern.h"

#include <functional>

namespace loom {

WeaveMatrix::WeaveMatrix(const v1::WovenSpec& woven) {
  const uint32_t n = woven.n(), m = woven.m();
  std::function<bool(uint32_t warp, uint32_t weft)> over;
  switch (woven.pattern()) {
    case v1::WEAVE_PATTERN_TWILL:
      size_ = n + m;
      over = [&](uint32_t warp, uint32_t weft) { return (warp + weft) % size_ < n; };
      break;
    case v1::WEAVE_PATTERN_SATIN:
      size_ = n;
      over = [&](uint32_t warp, uint32_t weft) { return warp != (m * weft) % n; };
      break;
    case v1::WEAVE_PATTERN_BASKET:
      size_ = 2 * n;
      over = [&](uint32_t warp, uint32_t weft) { return (warp / n + weft / n) % 2 == 0; };
      break;
    default:  // plain
      size_ = 2;
      over = [](uint32_t warp, uint32_t weft) { return (warp + weft) % 2 == 0; };
      break;
  }
  over_.resize(size_t{size_} * size_);
  for (uint32_t weft = 0; weft < size_; ++weft) {
    for (uint32_t warp = 0; warp < size_; ++warp) over_[size_t{weft} * size_ + warp] = over(warp, weft);
  }
}

}  // namespace loom
