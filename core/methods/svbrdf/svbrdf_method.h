#pragma once
// The svbrdf method (core/methods/fabric_method.h; Daubert 2001): the fitted BRDF
// array of core/fit (Lafortune lobes × T(v), fitted mip levels), stored by
// core/fit/fabric_asset.h, uploaded by core/render/fabric_textures.h and shaded by
// core/shaders/svbrdf.glsl.

#include "core/fit/fabric_fit.h"
#include "core/methods/fabric_method.h"

namespace loom {

// The fit's figures: its time, texels, lobes and per level the fit error, LM
// iterations, alternations, fallbacks, empty and black texels.
nlohmann::json SvbrdfFitFigures(const FittedFabric& fit);

class SvbrdfAsset final : public FabricAsset {
 public:
  explicit SvbrdfAsset(FittedFabric fit) : fit_(std::move(fit)) {}
  const FittedFabric& fit() const { return fit_; }

  const FabricMethod& method() const override;
  void WriteSheet(const v1::PrecomputeSettings& settings, const std::string& fabric_key,
                  const AssetSheet& directory) const override;
  std::unique_ptr<GpuFabric> Upload(bool half) const override;
  double build_seconds() const override { return fit_.seconds; }
  nlohmann::json Figures() const override { return SvbrdfFitFigures(fit_); }
  std::vector<AssetPicture> Pictures() const override;

 private:
  FittedFabric fit_;
};

const FabricMethod& SvbrdfMethod();

// `settings` without svbrdf's fit (lobes, lookup_table, lut_change_threshold,
// max_alternations, max_lm_iterations): what other methods' keys leave out.
v1::PrecomputeSettings WithoutSvbrdfFit(v1::PrecomputeSettings settings);

}  // namespace loom
