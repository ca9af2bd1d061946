#include "core/methods/neural/neural_method.h"

#include <GL/glcorearb.h>

#include <algorithm>
#include <cmath>
#include <limits>

#include <nlohmann/json.hpp>

#include "core/acquire/hemisphere_directions.h"
#include "core/methods/asset_files.h"
#include "core/methods/direction_grid.h"
#include "core/methods/factored/factored_method.h"
#include "core/methods/level_texture.h"
#include "core/methods/svbrdf/svbrdf_method.h"
#include "core/spec/defaults.h"
#include "core/spec/limits.h"
#include "core/spec/spec_json.h"
#include "core/util/error.h"
#include "core/util/file_io.h"

namespace loom {
namespace {

using nlohmann::json;

constexpr const char* kLatentsFile = "latents.exr";
constexpr const char* kViewsFile = "views.exr";
constexpr const char* kManifestFile = "manifest.json";
// 1: the first layout; 2: every level drawn equally often in training; 3: the
// view atlas's RGB is the per-view gain A (radiance A/π ⊙ f); 4: the Fourier
// encoding's frequencies; 5: the factored base (decoder.base_rank, its terms' files);
// 6: acquisition shades a facet facing the view even where the shading normal does not.
constexpr uint32_t kNeuralFormatVersion = 6;
// The uniform buffer binding of the decoder's parameters.
constexpr GLuint kDecoderBinding = 0;

std::vector<std::string> LatentChannels(uint32_t channels) {
  std::vector<std::string> names;
  for (uint32_t c = 0; c < channels; ++c) names.push_back((c < 10 ? "z0" : "z") + std::to_string(c));
  return names;
}

// Latent numbers 4·layer … 4·layer + 3 of every texel of a level, RGBA.
std::vector<float> LatentLayer(const NeuralLevel& level, uint32_t channels, uint32_t layer) {
  std::vector<float> pixels(level.texel_count() * 4);
  for (size_t texel = 0; texel < level.texel_count(); ++texel) {
    std::copy_n(&level.latents[texel * channels + 4 * layer], 4, &pixels[texel * 4]);
  }
  return pixels;
}

class NeuralTextures final : public GpuFabric {
 public:
  NeuralTextures(const NeuralFabric& fabric, bool half)
      : surface_{static_cast<int>(fabric.levels.size()), static_cast<int>(fabric.levels.at(0).resolution),
                 static_cast<int>(GridSide(fabric.view_count())), static_cast<int>(GridSide(fabric.light_count())),
                 fabric.view_heights},
        channels_(fabric.decoder.channels),
        hidden_(fabric.decoder.hidden),
        frequencies_(fabric.decoder.frequencies),
        views_(surface_.levels(), surface_.resolution() * surface_.view_side(), 4, half),
        latents_(surface_.levels(), surface_.resolution(), 4, half, static_cast<int>(channels_ / 4)),
        base_(fabric.base.rank > 0 ? std::make_unique<FactoredTermTextures>(fabric.base, half) : nullptr) {
    // The latents repeat with the tile: the filter blends texels across its edges.
    glTextureParameteri(latents_.id(), GL_TEXTURE_WRAP_S, GL_REPEAT);
    glTextureParameteri(latents_.id(), GL_TEXTURE_WRAP_T, GL_REPEAT);
    for (int level = 0; level < surface_.levels(); ++level) {
      const NeuralLevel& data = fabric.levels[static_cast<size_t>(level)];
      views_.Upload(level, AmbientAlphaAtlas(data.ambient, data.alpha, data.resolution, fabric.view_count()).data());
      for (uint32_t layer = 0; layer < channels_ / 4; ++layer) {
        latents_.Upload(level, LatentLayer(data, channels_, layer).data(), static_cast<int>(layer));
      }
    }
    // std140 vec4s: the parameters as they are, padded to a whole vec4.
    std::vector<float> block = fabric.decoder.parameters;
    block.resize((block.size() + 3) / 4 * 4, 0.0f);
    const auto bytes = static_cast<GLsizeiptr>(block.size() * sizeof(float));
    GLint max_bytes = 0;
    glGetIntegerv(GL_MAX_UNIFORM_BLOCK_SIZE, &max_bytes);
    if (bytes > max_bytes) {
      throw Error(ErrorCode::kFailedPrecondition,
                  "the neural decoder's " + std::to_string(bytes) + " bytes of parameters exceed this GL's uniform "
                  "block size, " + std::to_string(max_bytes) + ": precompute with fewer neural.hidden or channels");
    }
    glCreateBuffers(1, &decoder_);
    glNamedBufferStorage(decoder_, bytes, block.data(), 0);
  }
  ~NeuralTextures() override { glDeleteBuffers(1, &decoder_); }
  NeuralTextures(const NeuralTextures&) = delete;
  NeuralTextures& operator=(const NeuralTextures&) = delete;

  const FabricMethod& method() const override { return NeuralMethod(); }

  void Bind(const gl::ShaderProgram& program, int first_unit, glm::vec2 repeat) const override {
    glBindTextureUnit(static_cast<GLuint>(first_unit + FabricSurface::kUnits), latents_.id());
    surface_.Bind(program, views_.id(), first_unit, repeat);
    program.Set("u_fabric_latents", first_unit + FabricSurface::kUnits);
    if (base_) base_->Bind(program, first_unit + FabricSurface::kUnits + 1);
    // The shadow pass reads coverage alone and has no decoder block.
    const GLuint block = glGetUniformBlockIndex(program.id(), "NeuralDecoder");
    if (block != GL_INVALID_INDEX) {
      glUniformBlockBinding(program.id(), block, kDecoderBinding);
      glBindBufferBase(GL_UNIFORM_BUFFER, kDecoderBinding, decoder_);
    }
  }

  std::string ShaderDefines() const override {
    return "#define LOOM_NEURAL_CHANNELS " + std::to_string(channels_) + "\n#define LOOM_NEURAL_HIDDEN " +
           std::to_string(hidden_) + "\n#define LOOM_NEURAL_FREQUENCIES " + std::to_string(frequencies_) + "\n" +
           (base_ ? "#define LOOM_NEURAL_BASE\n" + base_->ShaderDefines() : std::string());
  }

 private:
  FabricSurface surface_;
  uint32_t channels_, hidden_, frequencies_;
  LevelTexture views_, latents_;
  std::unique_ptr<FactoredTermTextures> base_;  // null without a factored base
  GLuint decoder_ = 0;
};

NeuralFabric ReadNeural(const AssetSheet& directory) {
  const std::filesystem::path manifest_path = directory / kManifestFile;
  const auto invalid = [&manifest_path](const std::string& what) {
    return Error(ErrorCode::kInvalidArgument, manifest_path.string() + ": " + what);
  };
  try {
    const json manifest = json::parse(ReadFile(manifest_path));
    const TableAssetHeader header = CheckTableManifest(manifest, "neural", kNeuralFormatVersion, invalid);
    NeuralFabric fabric;
    const json& decoder = manifest.at("decoder");
    // A whole number in [min, max] that is a multiple of `of`; read as a double, as a
    // cast of an out-of-range float to an integer is undefined.
    const auto count = [&](const char* field, uint32_t min, uint32_t max, uint32_t of) {
      const auto value = decoder.at(field).get<double>();
      if (!(value >= min && value <= max && value == std::floor(value) && static_cast<uint32_t>(value) % of == 0)) {
        throw invalid(std::string("decoder.") + field + " is not " + (of > 1 ? "a multiple of 4 " : "a whole number ") +
                      "in [" + std::to_string(min) + ", " + std::to_string(max) + "]");
      }
      return static_cast<uint32_t>(value);
    };
    fabric.decoder.channels = count("channels", 4, kMaxNeuralChannels, 4);
    fabric.decoder.hidden = count("hidden", 4, kMaxNeuralHidden, 4);
    fabric.decoder.frequencies = count("frequencies", 0, kMaxNeuralFrequencies, 1);
    fabric.steps = count("steps", 1, kMaxNeuralSteps, 1);
    fabric.base.rank = count("base_rank", 0, kMaxFactoredRank, 1);
    const json& parameters = decoder.at("parameters");
    const size_t expected =
        NeuralDecoder::ParameterCount(fabric.decoder.channels, fabric.decoder.hidden, fabric.decoder.frequencies);
    if (!parameters.is_array() || parameters.size() != expected) {
      throw invalid("decoder.parameters must be " + std::to_string(expected) + " numbers");
    }
    for (const json& value : parameters) {
      // As a double first: a float cast of a number past float's range is undefined.
      const auto number = value.get<double>();
      if (!(std::abs(number) <= std::numeric_limits<float>::max())) {
        throw invalid("decoder.parameters holds a number that is not a finite float");
      }
      fabric.decoder.parameters.push_back(static_cast<float>(number));
    }
    const uint32_t views = header.views;
    CheckLevelChain(manifest.at("levels"),
                    uint64_t{views} * 4 + fabric.decoder.channels + uint64_t{views + header.lights} * fabric.base.rank,
                    kMaxRadianceSamples / kMinDirections, invalid);
    fabric.view_directions = HemisphereGridDirections(views);
    fabric.light_directions = HemisphereGridDirections(header.lights);
    fabric.view_heights = header.view_heights;
    fabric.seconds = header.build_seconds;
    std::vector<int> sides, view_sides;
    for (const json& entry : manifest.at("levels")) {
      NeuralLevel& level = fabric.levels.emplace_back();
      level.resolution = entry.at("resolution");
      level.relative_rmse = entry.at("relative_rmse");
      sides.push_back(static_cast<int>(level.resolution));
      view_sides.push_back(static_cast<int>(level.resolution * GridSide(views)));
    }
    const json& files = manifest.at("files");
    const auto latents = ReadLevelImage(VerifiedFile(directory, files, kLatentsFile, sides[0]), sides,
                                        LatentChannels(fabric.decoder.channels));
    const auto atlases = ReadLevelImage(VerifiedFile(directory, files, kViewsFile, view_sides[0]), view_sides,
                                        {"R", "G", "B", "A"});
    for (size_t j = 0; j < fabric.levels.size(); ++j) {
      NeuralLevel& level = fabric.levels[j];
      if (!std::all_of(latents[j].begin(), latents[j].end(), [](float value) { return std::isfinite(value); })) {
        throw invalid("level " + std::to_string(j) + " holds a non-finite latent");
      }
      level.latents = latents[j];
      ReadAmbientAlphaAtlas(atlases[j], level.resolution, views, level.ambient, level.alpha, invalid);
    }
    if (fabric.base.rank > 0) {
      fabric.base.view_directions = fabric.view_directions;
      fabric.base.light_directions = fabric.light_directions;
      for (const NeuralLevel& level : fabric.levels) fabric.base.levels.emplace_back().resolution = level.resolution;
      ReadFactoredTerms(directory, files, fabric.base, invalid);
    }
    return fabric;
  } catch (const json::exception& e) {
    throw Error(ErrorCode::kInvalidArgument, manifest_path.string() + " is not a valid manifest: " + e.what());
  }
}

class Neural final : public FabricMethod {
 public:
  v1::FabricMethod id() const override { return v1::FABRIC_METHOD_NEURAL; }
  std::string_view name() const override { return "neural"; }
  std::string_view cloth_shader() const override { return "neural_cloth.frag"; }
  uint32_t asset_format_version() const override { return kNeuralFormatVersion; }

  v1::PrecomputeSettings KeySettings(v1::PrecomputeSettings settings) const override {
    settings.clear_factored();
    return WithoutSvbrdfFit(std::move(settings));
  }

  std::string OwnSettings(const v1::PrecomputeSettings& settings) const override {
    return SpecToJson(settings.neural(), false);
  }

  std::unique_ptr<FabricAsset> Build(const RadianceSamples& samples,
                                     const v1::PrecomputeSettings& settings,
                                     const BuildProgress& progress) const override {
    if (progress) progress(0.0, "tabulate");
    const TabulatedFabric table =
        TabulateFabric(samples, settings.mip_levels() != v1::MIP_LEVELS_NONE);
    const v1::NeuralSettings& neural = settings.neural();
    const NeuralTraining training{neural.channels(), neural.hidden(), neural.frequencies(), neural.steps(),
                                  settings.seed(), neural.base_rank()};
    NeuralFabric fabric = TrainNeural(table, training, 0, [&progress](double fraction) {
      if (progress) progress(fraction, "train");
    });
    fabric.seconds += table.seconds;
    return std::make_unique<NeuralAsset>(std::move(fabric));
  }

  std::unique_ptr<FabricAsset> Read(const AssetSheet& directory) const override {
    return std::make_unique<NeuralAsset>(ReadNeural(directory));
  }
};

}  // namespace

const FabricMethod& NeuralAsset::method() const { return NeuralMethod(); }

void NeuralAsset::WriteSheet(const v1::PrecomputeSettings& settings, const std::string& fabric_key,
                             const AssetSheet& directory) const {
  const v1::PrecomputeSettings resolved = WithDefaults(settings);
  const bool half = resolved.half_float();
  std::filesystem::create_directories(directory.directory);
  const uint32_t channels = fabric_.decoder.channels;
  LevelImage latents{LatentChannels(channels), {}, {}};
  for (const NeuralLevel& level : fabric_.levels) {
    latents.pixels.push_back(level.latents);
    latents.sides.push_back(static_cast<int>(level.resolution));
  }
  const std::string latents_sha = WriteLevelImage(latents, directory / kLatentsFile, half);
  const std::string views_sha =
      WriteLevelImage(AmbientAlphaImage(fabric_.levels, fabric_.view_count()), directory / kViewsFile, half);
  const TableAssetHeader header{static_cast<uint32_t>(fabric_.view_count()),
                                static_cast<uint32_t>(fabric_.light_count()), fabric_.levels.front().resolution,
                                fabric_.view_heights, fabric_.seconds};
  json manifest =
      TableManifest("neural", kNeuralFormatVersion, fabric_key, resolved, header, Figures().at("levels"));
  manifest["decoder"] = {{"channels", channels},
                         {"hidden", fabric_.decoder.hidden},
                         {"frequencies", fabric_.decoder.frequencies},
                         {"steps", fabric_.steps},
                         {"base_rank", fabric_.base.rank},
                         {"parameters", fabric_.decoder.parameters}};
  json files = fabric_.base.rank > 0 ? WriteFactoredTerms(fabric_.base, directory, half) : json::object();
  files[kLatentsFile] = FileEntry(directory / kLatentsFile, latents_sha);
  files[kViewsFile] = FileEntry(directory / kViewsFile, views_sha);
  manifest["files"] = files;
  WriteFileAtomic(directory / kManifestFile, manifest.dump(2) + "\n");
}

json NeuralAsset::Figures() const {
  json levels = json::array();
  for (size_t j = 0; j < fabric_.levels.size(); ++j) {
    levels.push_back({{"level", j},
                      {"resolution", fabric_.levels[j].resolution},
                      {"relative_rmse", fabric_.levels[j].relative_rmse}});
  }
  return {{"method", "neural"},
          {"seconds", fabric_.seconds},
          {"channels", fabric_.decoder.channels},
          {"hidden", fabric_.decoder.hidden},
          {"frequencies", fabric_.decoder.frequencies},
          {"steps", fabric_.steps},
          {"base_rank", fabric_.base.rank},
          {"view_directions", fabric_.view_count()},
          {"light_directions", fabric_.light_count()},
          {"levels", levels}};
}

std::vector<AssetPicture> NeuralAsset::Pictures() const {
  std::vector<AssetPicture> pictures;
  const size_t views = fabric_.view_count(), channels = fabric_.decoder.channels;
  const size_t view = TopDirection(fabric_.view_directions);
  for (uint32_t j = 0; j < fabric_.levels.size(); ++j) {
    const NeuralLevel& level = fabric_.levels[j];
    if (channels >= 3) {
      pictures.push_back({j, "latents", "latents z_0, z_1, z_2 as red, green, blue, each smallest to largest",
                          TexelPicture(
                              level.resolution,
                              [&](size_t texel) {
                                const float* z = &level.latents[texel * channels];
                                return glm::vec3(z[0], z[1], z[2]);
                              },
                              PictureScale::kRange)});
    }
    pictures.push_back(AmbientPicture(j, level.resolution, level.ambient, views, view));
    pictures.push_back(CoveragePicture(j, level.resolution, level.alpha, views, view));
  }
  return pictures;
}

std::unique_ptr<GpuFabric> NeuralAsset::Upload(bool half) const {
  return std::make_unique<NeuralTextures>(fabric_, half);
}

const FabricMethod& NeuralMethod() {
  static const Neural method;
  return method;
}

}  // namespace loom
