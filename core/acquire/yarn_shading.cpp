#include "core/acquire/yarn_shading.h"

namespace loom {
namespace {

std::variant<KajiyaKayBrdf, FibreMicroflakeBrdf> MakeBrdf(const YarnMaterial& material) {
  if (material.model == YarnShadingModel::kMicroflake) return FibreMicroflakeBrdf(material);
  return KajiyaKayBrdf(material);
}

}  // namespace

YarnBrdf::YarnBrdf(const YarnMaterial& material) : brdf_(MakeBrdf(material)) {}

}  // namespace loom
