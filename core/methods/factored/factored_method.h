#pragma once
// The factored method (core/methods/fabric_method.h): per texel and level, the
// ambient response times K view tables times K light tables (factored_fabric.h),
// shaded by core/shaders/factored.glsl.
//
// Asset directory:
//   view_terms.exr   a_k, channel a<k>: MIP level ℓ is level ℓ's direction atlas over
//                    the views, (res_ℓ·k)² (asset_files.h DirectionAtlasPixel)
//   light_terms.exr  b_k, channel b<k>: the same over the lights, (res_ℓ·k_l)²
//   views.exr        the view atlas: ambient response (RGB), coverage alpha (A)
//   manifest.json    method, asset version, key, settings, rank, sizes, per-level
//                    factorisation error, checksums (last)
// Half floats with settings.half_float, full floats otherwise, on disk and on the GPU
// (there four terms to an RGBA layer of a texture array).

#include <functional>

#include "core/methods/factored/factored_fabric.h"
#include "core/methods/fabric_method.h"
#include "core/util/error.h"

namespace loom {

// The terms' files and GPU textures, which the neural method's factored base shares
// (core/methods/neural/neural_method.h).
//
// Writes every level's view and light terms (view_terms.exr, light_terms.exr) into
// `directory`; returns their manifest "files" entries.
nlohmann::json WriteFactoredTerms(const FactoredFabric& fabric, const AssetSheet& directory, bool half);
// Reads them (checked against `files`) into each level's view_terms and light_terms;
// `fabric`'s rank, directions and level resolutions must be set.
void ReadFactoredTerms(const AssetSheet& directory, const nlohmann::json& files, FactoredFabric& fabric,
                       const std::function<Error(const std::string&)>& invalid);

// The terms on the GPU, four to an RGBA layer of two texture arrays (MIP ℓ = level ℓ),
// read by core/shaders/factored_terms.glsl.
class FactoredTermTextures {
 public:
  FactoredTermTextures(const FactoredFabric& fabric, bool half);
  // The view terms to unit `unit`, the light terms to unit + 1.
  void Bind(const gl::ShaderProgram& program, int unit) const;
  // "#define LOOM_FACTORED_RANK K\n": the loop bound factored_terms.glsl is compiled with.
  std::string ShaderDefines() const;

 private:
  uint32_t rank_;
  LevelTexture view_terms_, light_terms_;
};

class FactoredAsset final : public FabricAsset {
 public:
  explicit FactoredAsset(FactoredFabric fabric) : fabric_(std::move(fabric)) {}
  const FactoredFabric& fabric() const { return fabric_; }

  const FabricMethod& method() const override;
  void WriteSheet(const v1::PrecomputeSettings& settings, const std::string& fabric_key,
                  const AssetSheet& directory) const override;
  std::unique_ptr<GpuFabric> Upload(bool half) const override;
  double build_seconds() const override { return fabric_.seconds; }
  nlohmann::json Figures() const override;
  std::vector<AssetPicture> Pictures() const override;

 private:
  FactoredFabric fabric_;
};

const FabricMethod& FactoredMethod();

}  // namespace loom
