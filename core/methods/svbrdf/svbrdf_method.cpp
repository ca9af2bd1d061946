#include "core/methods/svbrdf/svbrdf_method.h"

#include "core/fit/fabric_asset.h"
#include "core/render/fabric_textures.h"
#include "core/spec/fabric_key.h"

namespace loom {
namespace {

class Svbrdf final : public FabricMethod {
 public:
  v1::FabricMethod id() const override { return v1::FABRIC_METHOD_SVBRDF; }
  std::string_view name() const override { return "svbrdf"; }
  std::string_view cloth_shader() const override { return "svbrdf_cloth.frag"; }
  uint32_t asset_format_version() const override { return kAssetFormatVersion; }

  // svbrdf's keys predate methods: keyed without the method field, every svbrdf
  // asset cached before methods keeps its key.
  v1::PrecomputeSettings KeySettings(v1::PrecomputeSettings settings) const override {
    settings.clear_method();
    settings.clear_factored();
    settings.clear_neural();
    return settings;
  }

  std::unique_ptr<FabricAsset> Build(const RadianceSamples& samples,
                                     const v1::PrecomputeSettings& settings,
                                     const BuildProgress& progress) const override {
    return std::make_unique<SvbrdfAsset>(FitFabric(samples, settings, progress));
  }

  std::unique_ptr<FabricAsset> Read(const AssetSheet& directory) const override {
    return std::make_unique<SvbrdfAsset>(ReadFabricAsset(directory));
  }
};

}  // namespace

nlohmann::json SvbrdfFitFigures(const FittedFabric& fitted) {
  nlohmann::json levels = nlohmann::json::array();
  size_t texels = 0;
  for (const FittedLevel& level : fitted.levels) {
    const FitLevelStats& s = level.stats;
    texels += level.brdfs.size();
    levels.push_back({{"level", s.level},
                      {"resolution", s.resolution},
                      {"rmse_mean", s.rmse_mean},
                      {"rmse_p95", s.rmse_p95},
                      {"rmse_max", s.rmse_max},
                      {"relative_rmse", s.relative_rmse},
                      {"lm_iterations_per_texel", s.lm_iterations_per_texel},
                      {"mean_alternations", s.mean_alternations},
                      {"fallback_fewer_lobes", s.fewer_lobes},
                      {"fallback_diffuse", s.diffuse_only},
                      {"empty", s.empty},
                      {"black", s.black},
                      {"seconds", s.fit_seconds}});
  }
  return {{"method", "svbrdf"},
          {"seconds", fitted.seconds},
          {"texels", texels},
          {"texels_per_second", fitted.seconds > 0 ? static_cast<double>(texels) / fitted.seconds : 0.0},
          {"lobes", fitted.lobes},
          {"lookup_table", fitted.lookup_table},
          {"levels", levels}};
}

std::vector<AssetPicture> SvbrdfAsset::Pictures() const {
  std::vector<AssetPicture> pictures;
  const size_t views = fit_.view_directions.size();
  const size_t top = TopDirection(fit_.view_directions);
  for (uint32_t j = 0; j < fit_.levels.size(); ++j) {
    const FittedLevel& level = fit_.levels[j];
    const auto brdf = [&](size_t texel) -> const LafortuneBrdf& { return level.brdfs[texel]; };
    pictures.push_back({j, "albedo", "diffuse albedo ρ_d",
                        TexelPicture(
                            level.resolution, [&](size_t texel) { return brdf(texel).rho; },
                            PictureScale::kReflectance)});
    if (fit_.lobes > 0) {
      pictures.push_back({j, "lobe1", "lobe 1 strength |(C_x, C_y, C_z)|, scaled to its maximum",
                          TexelPicture(
                              level.resolution,
                              [&](size_t texel) {
                                const LafortuneLobe& lobe = brdf(texel).lobes[0];
                                return glm::sqrt(lobe.cx * lobe.cx + lobe.cy * lobe.cy + lobe.cz * lobe.cz);
                              },
                              PictureScale::kMaximum)});
    }
    if (fit_.lookup_table) {
      pictures.push_back(PerViewPicture(j, "lut", "lookup table T(v) seen from above, scaled to its maximum",
                                        level.resolution, level.lut, views, top));
    }
    pictures.push_back(CoveragePicture(j, level.resolution, level.alpha, views, top));
  }
  return pictures;
}

const FabricMethod& SvbrdfAsset::method() const { return SvbrdfMethod(); }

void SvbrdfAsset::WriteSheet(const v1::PrecomputeSettings& settings, const std::string& fabric_key,
                             const AssetSheet& directory) const {
  WriteFabricAsset(fit_, settings, fabric_key, directory);
}

std::unique_ptr<GpuFabric> SvbrdfAsset::Upload(bool half) const {
  return std::make_unique<FabricTextures>(FabricTextureData::FromFit(fit_), half);
}

v1::PrecomputeSettings WithoutSvbrdfFit(v1::PrecomputeSettings settings) {
  settings.clear_lobes();
  settings.clear_lookup_table();
  settings.clear_lut_change_threshold();
  settings.clear_max_alternations();
  settings.clear_max_lm_iterations();
  return settings;
}

const FabricMethod& SvbrdfMethod() {
  static const Svbrdf method;
  return method;
}

}  // namespace loom
