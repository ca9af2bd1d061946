#pragma once
// The neural method (core/methods/fabric_method.h): per texel and level a latent
// vector, one decoder network (neural_fabric.h), shaded by core/shaders/neural.glsl.
//
// Asset directory:
//   latents.exr    z, channels z00, z01, …: MIP level ℓ is level ℓ's res_ℓ² latents
//   views.exr      the view atlas: the gain (the table's ambient response) RGB, alpha A
//   view_terms.exr, light_terms.exr
//                  with a factored base (decoder.base_rank > 0): its terms, as the
//                  factored method stores them (factored_method.h)
//   manifest.json  method, asset version, key, settings, the decoder's sizes and
//                  parameters, base_rank, per-level training error, checksums (last)
// Latents in half floats with settings.half_float, full floats otherwise; the
// decoder in full floats.

#include "core/methods/fabric_method.h"
#include "core/methods/neural/neural_fabric.h"

namespace loom {

class NeuralAsset final : public FabricAsset {
 public:
  explicit NeuralAsset(NeuralFabric fabric) : fabric_(std::move(fabric)) {}
  const NeuralFabric& fabric() const { return fabric_; }

  const FabricMethod& method() const override;
  void WriteSheet(const v1::PrecomputeSettings& settings, const std::string& fabric_key,
                  const AssetSheet& directory) const override;
  std::unique_ptr<GpuFabric> Upload(bool half) const override;
  double build_seconds() const override { return fabric_.seconds; }
  nlohmann::json Figures() const override;
  std::vector<AssetPicture> Pictures() const override;

 private:
  NeuralFabric fabric_;
};

const FabricMethod& NeuralMethod();

}  // namespace loom
