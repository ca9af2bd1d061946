#pragma once
// A fabric method (DESIGN.md "Methods"): how a fabric's radiance samples become an
// asset, how that asset is stored, and the GL program that shades cloth with it.
// The cache key, the worker, the service, loom-lab and the renderer know methods
// only through this interface; a method is chosen per fabric binding by
// PrecomputeSettings.method, so one frame can hold objects of different methods.
//
// Every method's GPU asset shares the view atlas of core/shaders/fabric_surface.glsl
// (per level, texel and view: RGB for the method, A the coverage alpha) at its first
// texture unit: the shadow pass reads coverage from it whatever the method.
// docs/methods.md is the interface's page, docs/methods/NAME.md each method's model and figures.

#include <filesystem>
#include <functional>
#include <glm/glm.hpp>
#include <memory>
#include <optional>
#include <nlohmann/json.hpp>
#include <string>
#include <string_view>
#include <vector>

#include "core/acquire/radiance_samples.h"
#include "core/gl/shader_program.h"
#include "core/methods/asset_files.h"
#include "core/methods/asset_pictures.h"
#include "core/methods/colour_sheets.h"
#include "core/methods/level_texture.h"
#include "loom/v1/precompute.pb.h"

namespace loom {

class FabricMethod;
class FabricAsset;

// What fabric_surface.glsl needs of any method's asset on the GPU: the view atlas's
// dimensions and each view's sampling height (RadianceSamples::view_heights, a k×k
// texture).
class FabricSurface {
 public:
  // levels, level-0 texels per tile side, the view atlas's k, k_l of a method with
  // light tables (LOOM_FABRIC_LIGHT_GRID) or 0, and k² view heights.
  FabricSurface(int levels, int resolution, int view_side, int light_side, const std::vector<float>& view_heights);

  int levels() const { return levels_; }
  int resolution() const { return resolution_; }
  int view_side() const { return view_side_; }
  int light_side() const { return light_side_; }

  // Binds the view atlas `views` to `first_unit` and the view heights to the next
  // unit, and sets the surface's uniforms and the repeat on `program`. A method's own
  // textures take the units from first_unit + kUnits on.
  void Bind(const gl::ShaderProgram& program, GLuint views, int first_unit, glm::vec2 repeat) const;
  static constexpr int kUnits = 2;

 private:
  int levels_, resolution_, view_side_, light_side_;
  LevelTexture heights_;
};

// A fabric asset in GPU memory, bound for the draws of one cloth object.
class GpuFabric {
 public:
  virtual ~GpuFabric() = default;
  virtual const FabricMethod& method() const = 0;
  // Binds the asset's textures to units first_unit, first_unit + 1, … (the view
  // atlas first) and sets the fabric uniforms of `program`, the method's cloth
  // program or the shadow pass's.
  virtual void Bind(const gl::ShaderProgram& program, int first_unit, glm::vec2 repeat) const = 0;
  // "#define NAME VALUE\n" lines the method's cloth program is compiled with for this
  // asset (a loop bound the compiler may then unroll); one program per distinct set.
  virtual std::string ShaderDefines() const { return {}; }
  // The back sheet's (FabricAsset::back) upload, or null.
  const GpuFabric* back() const { return back_.get(); }
  // The colour sheets' (FabricAsset::colour_channels): what this sheet's channels
  // carry, and the further sheets.
  const std::optional<SheetChannels>& colour_channels() const { return colour_channels_; }
  const std::vector<std::unique_ptr<GpuFabric>>& colour_sheets() const { return colour_sheets_; }

 private:
  friend std::unique_ptr<GpuFabric> UploadSheets(const FabricAsset& asset, bool half);
  std::unique_ptr<GpuFabric> back_;
  std::optional<SheetChannels> colour_channels_;
  std::vector<std::unique_ptr<GpuFabric>> colour_sheets_;
};

// A fabric asset in CPU memory: built from samples, or read from an asset directory.
// With PrecomputeSettings.transmission it has a back sheet: an asset of the same
// method built alike from the light behind the cloth, its lights mirrored above the
// surface (MirroredLights), its files in the same directory named with
// kBackSheetPrefix; the renderer shades lights behind the surface with it.
// With PrecomputeSettings.colour_components its RGB are colour components
// (core/methods/colour_sheets.h), and the fabric's further components are further
// sheets, each an asset of the same method with its own back sheet, files named
// with ColourSheetPrefix; the channels of every sheet are in kColourSheetsFile.
class FabricAsset {
 public:
  virtual ~FabricAsset() = default;
  virtual const FabricMethod& method() const = 0;
  // Writes the further colour sheets' files, then the back sheet's, then the asset's
  // with its manifest last, into `directory`, creating it.
  void Write(const v1::PrecomputeSettings& settings, const std::string& fabric_key,
             const std::filesystem::path& directory) const;
  // One sheet's files and manifest (last).
  virtual void WriteSheet(const v1::PrecomputeSettings& settings, const std::string& fabric_key,
                          const AssetSheet& sheet) const = 0;
  const FabricAsset* back() const { return back_.get(); }
  void set_back(std::unique_ptr<FabricAsset> back) { back_ = std::move(back); }
  const std::optional<SheetChannels>& colour_channels() const { return colour_channels_; }
  void set_colour_channels(const SheetChannels& channels) { colour_channels_ = channels; }
  const std::vector<std::unique_ptr<FabricAsset>>& colour_sheets() const { return colour_sheets_; }
  void add_colour_sheet(std::unique_ptr<FabricAsset> sheet) { colour_sheets_.push_back(std::move(sheet)); }
  // On the calling thread's current GL context; `half` stores what the method
  // allows in 16-bit floats.
  virtual std::unique_ptr<GpuFabric> Upload(bool half) const = 0;
  // Wall time of the build (the fit, for svbrdf), acquisition excluded.
  virtual double build_seconds() const = 0;
  // What the build made and what it cost, for people and scripts: at least
  // "method", "seconds" and "levels" (per level at least "level" and "resolution";
  // "relative_rmse" where the method approximates its samples).
  virtual nlohmann::json Figures() const = 0;
  // Per level, pictures of the maps the method stores per texel
  // (core/methods/asset_pictures.h), finest level first.
  virtual std::vector<AssetPicture> Pictures() const = 0;

 private:
  // This sheet's back sheet's files, then its own.
  void WriteSides(const v1::PrecomputeSettings& settings, const std::string& fabric_key, const AssetSheet& sheet) const;

  std::unique_ptr<FabricAsset> back_;
  std::optional<SheetChannels> colour_channels_;
  std::vector<std::unique_ptr<FabricAsset>> colour_sheets_;
};

// The file prefix of further colour sheet `index` (≥ 1; sheet 0 is the asset), and the
// file beside the manifest listing every sheet's channels (ColourSheetsJson).
std::string ColourSheetPrefix(size_t index);
inline constexpr const char* kColourSheetsFile = "colour_sheets.json";

// `asset` with its back sheet and colour sheets on the calling thread's GL context.
std::unique_ptr<GpuFabric> UploadSheets(const FabricAsset& asset, bool half);

// Back-lit samples (acquisition's LightSide::kBack) with every light mirrored
// through the surface (z negated): what a method builds a back sheet from, as if
// the light came from above.
RadianceSamples MirroredLights(RadianceSamples samples);

// fraction in [0, 1], non-decreasing; throwing from it cancels the build.
using BuildProgress = std::function<void(double fraction, std::string_view stage)>;

class FabricMethod {
 public:
  virtual ~FabricMethod() = default;
  virtual v1::FabricMethod id() const = 0;
  virtual std::string_view name() const = 0;  // "svbrdf", as in manifests and the CLI
  // The embedded fragment shader of the method's cloth program.
  virtual std::string_view cloth_shader() const = 0;
  // Version of the method's asset layout and of what its build computes: part of the
  // cache key, so bumping it invalidates the method's cached assets.
  virtual uint32_t asset_format_version() const = 0;
  // `settings` (defaults applied) with the fields that do not reach this method's
  // asset cleared: the cache key hashes what is left.
  virtual v1::PrecomputeSettings KeySettings(v1::PrecomputeSettings settings) const = 0;
  // The method's own settings in `settings` (defaults applied; e.g. factored's rank)
  // as compact JSON, "" for a method without any: what a sweep row records beside
  // the settings every method shares, so that two configurations of one method
  // are told apart.
  virtual std::string OwnSettings(const v1::PrecomputeSettings& settings) const {
    static_cast<void>(settings);
    return {};
  }
  // `settings` with defaults applied and validated.
  virtual std::unique_ptr<FabricAsset> Build(const RadianceSamples& samples,
                                             const v1::PrecomputeSettings& settings,
                                             const BuildProgress& progress) const = 0;
  // Error(kNotFound) if a file is missing, Error(kInvalidArgument) if one is
  // corrupted or inconsistent.
  virtual std::unique_ptr<FabricAsset> Read(const AssetSheet& sheet) const = 0;
};

// The method of an id; FABRIC_METHOD_UNSPECIFIED is svbrdf. Error(kInvalidArgument)
// for an id no method has.
const FabricMethod& MethodOf(v1::FabricMethod id);

// The method named `name` ("svbrdf"), or null; every name, comma-separated.
const FabricMethod* MethodNamed(std::string_view name);
std::string MethodNames();

// The asset in `directory`, read by the method its manifest names (a manifest
// without "method" is svbrdf's, as written before methods), with its back sheet
// when its settings have transmission and its colour sheets when they have colour
// components (Error(kNotFound) if one is missing).
std::unique_ptr<FabricAsset> ReadAnyFabricAsset(const std::filesystem::path& directory);

}  // namespace loom
