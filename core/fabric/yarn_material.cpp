#include "core/fabric/yarn_material.h"

#include <algorithm>

namespace loom {

float SpecularExponentFromRoughness(float roughness) {
  const float alpha = std::max(roughness, 1e-4f);
  return std::max(1.0f, 2.0f / (alpha * alpha) - 2.0f);
}

YarnMaterial MakeYarnMaterial(const v1::YarnSpec& yarn) {
  YarnMaterial material;
  const v1::Rgb& diffuse = yarn.diffuse_albedo();
  const v1::Rgb& specular = yarn.specular_albedo();
  material.diffuse_albedo = glm::vec3(diffuse.r(), diffuse.g(), diffuse.b());
  material.specular_albedo = glm::vec3(specular.r(), specular.g(), specular.b());
  material.specular_exponent = SpecularExponentFromRoughness(yarn.roughness());
  if (yarn.shading() == v1::YARN_SHADING_MICROFLAKE) {
    material.model = YarnShadingModel::kMicroflake;
    material.roughness = yarn.roughness();
    material.height_scale = yarn.height_scale();
    material.lambert_blend = yarn.lambert_blend();
    material.diffuse_transmission = yarn.diffuse_transmission();
  }
  return material;
}

}  // namespace loom
