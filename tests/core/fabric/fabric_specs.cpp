#include "fabric_specs.h"

namespace loom {

v1::FabricSpec KnitSpec(v1::KnitPattern pattern, float radius, uint32_t rib_knit, uint32_t rib_purl) {
  v1::FabricSpec fabric;
  v1::KnitSpec& knit = *fabric.mutable_knit();
  knit.set_pattern(pattern);
  knit.set_rib_knit(rib_knit);
  knit.set_rib_purl(rib_purl);
  fabric.add_yarns()->set_radius(radius);
  return fabric;
}

v1::FabricSpec WovenSpec(v1::WeavePattern pattern, uint32_t n, uint32_t m, float gap_ratio) {
  v1::FabricSpec fabric;
  v1::WovenSpec& woven = *fabric.mutable_woven();
  woven.set_pattern(pattern);
  woven.set_n(n);
  woven.set_m(m);
  woven.set_gap_ratio(gap_ratio);
  fabric.add_yarns();
  return fabric;
}

std::vector<NamedFabric> KnitFabrics(float radius) {
  return {{"stockinette", KnitSpec(v1::KNIT_PATTERN_STOCKINETTE, radius)},
          {"reverse", KnitSpec(v1::KNIT_PATTERN_REVERSE, radius)},
          {"garter", KnitSpec(v1::KNIT_PATTERN_GARTER, radius)},
          {"rib2x2", KnitSpec(v1::KNIT_PATTERN_RIB, radius, 2, 2)},
          {"rib1x1", KnitSpec(v1::KNIT_PATTERN_RIB, radius, 1, 1)},
          {"seed", KnitSpec(v1::KNIT_PATTERN_SEED, radius)}};
}

std::vector<NamedFabric> WovenFabrics(float gap_ratio) {
  return {{"plain", WovenSpec(v1::WEAVE_PATTERN_PLAIN, 0, 0, gap_ratio)},
          {"twill3x1", WovenSpec(v1::WEAVE_PATTERN_TWILL, 3, 1, gap_ratio)},
          {"satin5", WovenSpec(v1::WEAVE_PATTERN_SATIN, 5, 0, gap_ratio)},
          {"basket2", WovenSpec(v1::WEAVE_PATTERN_BASKET, 2, 0, gap_ratio)}};
}

}  // namespace loom
