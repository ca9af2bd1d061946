#pragma once
// The tabulated method (core/methods/fabric_method.h): the acquired samples per
// level (tabulated_fabric.h), stored and rendered as they are.
//
// Asset directory:
//   table.exr      radiance, RGB: MIP level ℓ is level ℓ's (res_ℓ·k·k_l)² atlas,
//                  texel (x, y), view (vc, vr), light (lc, lr) at
//                  ((x·k + vc)·k_l + lc, (y·k + vr)·k_l + lr); lights on the k_l×k_l
//                  grid inside a view's block, so a GPU interpolates lights
//                  bilinearly by its texture filter.
//   views.exr      the view atlas (fabric_surface.glsl): ambient response RGB, alpha A.
//   manifest.json  method, asset version, key, settings, sizes, checksums (last).
// Half floats with settings.half_float, full floats otherwise, on disk and on the GPU.

#include "core/methods/fabric_method.h"
#include "core/methods/tabulated/tabulated_fabric.h"

namespace loom {

class TabulatedAsset final : public FabricAsset {
 public:
  explicit TabulatedAsset(TabulatedFabric fabric) : fabric_(std::move(fabric)) {}
  const TabulatedFabric& fabric() const { return fabric_; }

  const FabricMethod& method() const override;
  void WriteSheet(const v1::PrecomputeSettings& settings, const std::string& fabric_key,
                  const AssetSheet& directory) const override;
  std::unique_ptr<GpuFabric> Upload(bool half) const override;
  double build_seconds() const override { return fabric_.seconds; }
  nlohmann::json Figures() const override;
  std::vector<AssetPicture> Pictures() const override;

 private:
  TabulatedFabric fabric_;
};

const FabricMethod& TabulatedMethod();

}  // namespace loom
