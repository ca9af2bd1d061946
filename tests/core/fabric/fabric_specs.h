#pragma once
// Test support: the fabric specs the fabric tests run over.

#include <string>
#include <vector>

#include "loom/v1/fabric.pb.h"

namespace loom {

struct NamedFabric {
  std::string name;
  v1::FabricSpec spec;  // defaults not applied
};

v1::FabricSpec KnitSpec(v1::KnitPattern pattern, float radius, uint32_t rib_knit = 0, uint32_t rib_purl = 0);
v1::FabricSpec WovenSpec(v1::WeavePattern pattern, uint32_t n = 0, uint32_t m = 0, float gap_ratio = 0.0f);

// Stockinette, reverse, garter, 2×2 rib, 1×1 rib and seed at the given yarn radius.
std::vector<NamedFabric> KnitFabrics(float radius);
// Plain, 3/1 twill, 5-satin (default move), 2-basket, at default yarns.
std::vector<NamedFabric> WovenFabrics(float gap_ratio);

}  // namespace loom
