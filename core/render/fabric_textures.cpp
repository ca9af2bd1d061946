#include "core/render/fabric_textures.h"

#include <cmath>
#include <string>

#include "core/methods/svbrdf/svbrdf_method.h"
#include "core/util/error.h"

namespace loom {

void FabricTextureData::Allocate(uint32_t resolution_, uint32_t lobes_, uint32_t view_side_, uint32_t levels) {
  resolution = resolution_;
  lobes = lobes_;
  view_side = view_side_;
  view_heights.assign(size_t{view_side} * view_side, 0.0f);
  params.assign(levels, {});
  lut.assign(levels, {});
  for (uint32_t level = 0; level < levels; ++level) {
    const size_t r = LevelResolution(level);
    params[level].assign(kFabricParamLayers * r * r, glm::vec4(0.0f));
    lut[level].assign(r * view_side * r * view_side, glm::vec4(0.0f));
  }
}

FabricTextureData FabricTextureData::FromFit(const FittedFabric& fit) {
  FabricTextureData data;
  const auto views = static_cast<uint32_t>(fit.view_directions.size());
  const auto view_side = static_cast<uint32_t>(std::lround(std::sqrt(static_cast<double>(views))));
  if (fit.levels.empty() || view_side * view_side != views) {
    throw Error(ErrorCode::kInvalidArgument, "fitted fabric: no levels, or a view count that is not k²");
  }
  data.Allocate(fit.levels[0].resolution, fit.lobes, view_side, static_cast<uint32_t>(fit.levels.size()));
  data.view_heights = fit.view_heights;
  for (uint32_t level = 0; level < data.levels(); ++level) {
    const FittedLevel& fitted = fit.levels[level];
    if (fitted.resolution != data.LevelResolution(level)) {
      throw Error(ErrorCode::kInvalidArgument, "fitted fabric: level " + std::to_string(level) + " has resolution " +
                                                   std::to_string(fitted.resolution) + ", expected " +
                                                   std::to_string(data.LevelResolution(level)));
    }
    for (uint32_t y = 0; y < fitted.resolution; ++y) {
      for (uint32_t x = 0; x < fitted.resolution; ++x) {
        const size_t texel = size_t{y} * fitted.resolution + x;
        const LafortuneBrdf& brdf = fitted.brdfs[texel];
        data.Param(level, 0, x, y) = glm::vec4(brdf.rho, 0.0f);
        data.Param(level, 1, x, y) = glm::vec4(fitted.normals[texel], 0.0f);
        data.Param(level, 2, x, y) = glm::vec4(fitted.tangents[texel], 0.0f);
        for (uint32_t i = 0; i < kMaxLafortuneLobes; ++i) {
          const LafortuneLobe& lobe = brdf.lobes[i];
          data.Param(level, 3 + 3 * i, x, y) = glm::vec4(lobe.cx, lobe.n.r);
          data.Param(level, 4 + 3 * i, x, y) = glm::vec4(lobe.cy, lobe.n.g);
          data.Param(level, 5 + 3 * i, x, y) = glm::vec4(lobe.cz, lobe.n.b);
        }
        for (uint32_t view = 0; view < views; ++view) {
          data.Lut(level, x, y, view) = glm::vec4(fitted.lut[texel * views + view], fitted.alpha[texel * views + view]);
        }
      }
    }
  }
  return data;
}

FabricTextures::FabricTextures(const FabricTextureData& data, bool half)
    : resolution_(data.resolution),
      lobes_(data.lobes),
      view_side_(data.view_side),
      levels_(data.levels()),
      surface_(static_cast<int>(levels_), static_cast<int>(resolution_), static_cast<int>(view_side_), 0,
               data.view_heights) {
  if (levels_ == 0 || resolution_ == 0 || view_side_ == 0 || (resolution_ >> (levels_ - 1)) == 0) {
    throw Error(ErrorCode::kInvalidArgument, "fabric textures: empty or inconsistent levels");
  }
  const GLenum lut_format = half ? GL_RGBA16F : GL_RGBA32F;
  const auto r = static_cast<GLsizei>(resolution_);
  const auto k = static_cast<GLsizei>(view_side_);
  const auto levels = static_cast<GLsizei>(levels_);

  glCreateTextures(GL_TEXTURE_2D_ARRAY, 1, &params_);
  glTextureStorage3D(params_, levels, GL_RGBA32F, r, r, kFabricParamLayers);
  glCreateTextures(GL_TEXTURE_2D, 1, &lut_);
  glTextureStorage2D(lut_, levels, lut_format, r * k, r * k);
  glPixelStorei(GL_UNPACK_ALIGNMENT, 1);
  for (GLint level = 0; level < levels; ++level) {
    const GLsizei side = r >> level;
    glTextureSubImage3D(params_, level, 0, 0, 0, side, side, kFabricParamLayers, GL_RGBA, GL_FLOAT,
                        data.params[static_cast<size_t>(level)].data());
    glTextureSubImage2D(lut_, level, 0, 0, side * k, side * k, GL_RGBA, GL_FLOAT,
                        data.lut[static_cast<size_t>(level)].data());
  }
  // Parameters are fetched texel by texel (a BRDF is not linear in them); the LUT
  // is filtered linearly inside one level, and levels are chosen by the shader.
  glTextureParameteri(params_, GL_TEXTURE_MIN_FILTER, GL_NEAREST_MIPMAP_NEAREST);
  glTextureParameteri(params_, GL_TEXTURE_MAG_FILTER, GL_NEAREST);
  glTextureParameteri(lut_, GL_TEXTURE_MIN_FILTER, GL_LINEAR_MIPMAP_NEAREST);
  glTextureParameteri(lut_, GL_TEXTURE_MAG_FILTER, GL_LINEAR);
  glTextureParameteri(lut_, GL_TEXTURE_WRAP_S, GL_CLAMP_TO_EDGE);
  glTextureParameteri(lut_, GL_TEXTURE_WRAP_T, GL_CLAMP_TO_EDGE);
  glTextureParameteri(lut_, GL_TEXTURE_MAX_LEVEL, levels - 1);
  glTextureParameteri(params_, GL_TEXTURE_MAX_LEVEL, levels - 1);
}

FabricTextures::~FabricTextures() {
  glDeleteTextures(1, &params_);
  glDeleteTextures(1, &lut_);
}

const FabricMethod& FabricTextures::method() const { return SvbrdfMethod(); }

void FabricTextures::Bind(const gl::ShaderProgram& program, int first_unit, glm::vec2 repeat) const {
  surface_.Bind(program, lut_, first_unit, repeat);
  glBindTextureUnit(static_cast<GLuint>(first_unit + FabricSurface::kUnits), params_);
  program.Set("u_fabric_params", first_unit + FabricSurface::kUnits);
  program.Set("u_fabric_lobes", static_cast<int>(lobes_));
}

}  // namespace loom
