#pragma once
// The weave matrix of a woven fabric (neural woven paper §3.1, §5.1): for each weft
// (row) and warp (column) of one pattern repeat, whether the warp passes over the
// weft there.

#include <cstdint>
#include <vector>

#include "loom/v1/fabric.pb.h"

namespace loom {

class WeaveMatrix {
 public:
  // woven has WithDefaults applied. The repeat is
  //   plain: 2; twill n over m under: n + m, each weft shifted by one warp;
  //   satin n with move m: n, the warp of weft j goes under it at warp (m·j) mod n
  //     (a warp-faced satin: every warp floats over n - 1 wefts);
  //   basket n: 2n, a plain weave of n-yarn groups.
  explicit WeaveMatrix(const v1::WovenSpec& woven);

  uint32_t size() const { return size_; }  // warps = wefts per repeat
  // Warp `warp` passes over weft `weft`; indices wrap around the repeat.
  bool WarpOver(uint32_t warp, uint32_t weft) const { return over_[(weft % size_) * size_ + warp % size_]; }

 private:
  uint32_t size_ = 0;
  std::vector<bool> over_;  // row-major: weft × warp
};

}  // namespace loom
