#include "core/acquire/fibre_microflake_brdf.h"

#include <gtest/gtest.h>

#include <cmath>
#include <cstdio>
#include <glm/gtc/constants.hpp>
#include <random>

#include "core/acquire/hemisphere_directions.h"

namespace loom {
namespace {

// The paper's equations (Chen et al. 2024 §3.1 eq. 1–2) written out with matrices, in
// double precision, independently of the closed forms the BRDF uses: S = Rᵀ diag(1, 1,
// α²) R with R's rows an orthonormal basis ending in the fibre, S⁻¹ by inversion, the
// height-field scaling as the linear map M = diag(1, 1, β) on directions and its
// cofactor matrix on normals.
glm::dvec3 PaperBrdf(const YarnMaterial& m, glm::dvec3 n, glm::dvec3 t, glm::dvec3 l, glm::dvec3 v) {
  const double cos_l = glm::dot(l, n), cos_v = glm::dot(v, n);
  if (cos_l <= 0) return glm::dvec3(0.0);
  const double beta = m.height_scale, alpha = m.roughness, w = m.lambert_blend;
  const glm::dmat3 scale(glm::dvec3(1, 0, 0), glm::dvec3(0, 1, 0), glm::dvec3(0, 0, beta));
  const glm::dmat3 cofactor(glm::dvec3(beta, 0, 0), glm::dvec3(0, beta, 0), glm::dvec3(0, 0, 1));  // det(M)·M⁻ᵀ
  const glm::dvec3 n_p = glm::normalize(cofactor * n);
  const glm::dvec3 t_p = glm::normalize(scale * glm::normalize(t - n * glm::dot(n, t)));
  const glm::dvec3 e1 = glm::normalize(glm::cross(t_p, std::abs(t_p.x) < 0.9 ? glm::dvec3(1, 0, 0) : glm::dvec3(0, 1, 0)));
  const glm::dvec3 e2 = glm::cross(t_p, e1);
  const glm::dmat3 r = glm::transpose(glm::dmat3(e1, e2, t_p));  // rows e1, e2, t_p: R t_p = z
  const glm::dmat3 s = glm::transpose(r) * glm::dmat3(glm::dvec3(1, 0, 0), glm::dvec3(0, 1, 0), glm::dvec3(0, 0, alpha * alpha)) * r;
  const glm::dvec3 h = glm::normalize(l + v);
  const double q = glm::dot(h, glm::inverse(s) * h);
  const double d = 1.0 / (glm::pi<double>() * alpha * q * q);
  const auto sigma = [&](glm::dvec3 x) { return std::sqrt(glm::dot(x, s * x)); };
  const double sum = sigma(l) / cos_l + sigma(v) / cos_v;
  // A view below n's horizon takes the limit cos_v → 0⁺: G·cos_v → 1/σ(v).
  const glm::dvec3 specular =
      cos_v > 0 ? glm::dvec3(m.specular_albedo) * d * ((1.0 - std::exp(-2.0 * sum)) / sum) / (4.0 * cos_l * cos_v)
                : glm::dvec3(m.specular_albedo) * d / (4.0 * cos_l * sigma(v));
  const glm::dvec3 diffuse = w * glm::dvec3(m.diffuse_albedo) * std::max(glm::dot(l, n_p), 0.0) /
                                 (glm::pi<double>() * std::max(cos_l, 0.0)) +
                             (1 - w) * glm::dvec3(m.diffuse_albedo) / glm::pi<double>();
  return specular + diffuse;
}

// The transmission of the same layer (SpongeCake's single scattering, Wang et al.
// 2022, written out from the layer integral, not from the BRDF's closed form): light
// from l behind the layer scatters once at optical depth τ' below the top and leaves
// towards v, attenuated by e^{−(Tρ − τ')Λ_l} on the way in and e^{−τ'Λ_v} on the way
// out; ∫₀^{Tρ} dτ' by Simpson's rule on 2000 intervals.
glm::dvec3 PaperBtdf(const YarnMaterial& m, glm::dvec3 n, glm::dvec3 t, glm::dvec3 l, glm::dvec3 v) {
  const double cos_l = -glm::dot(l, n), cos_v = glm::dot(v, n);
  if (cos_l <= 0 || cos_v <= 0) return glm::dvec3(0.0);
  const double beta = m.height_scale, alpha = m.roughness;
  const glm::dmat3 scale(glm::dvec3(1, 0, 0), glm::dvec3(0, 1, 0), glm::dvec3(0, 0, beta));
  const glm::dvec3 t_p = glm::normalize(scale * glm::normalize(t - n * glm::dot(n, t)));
  const glm::dvec3 e1 = glm::normalize(glm::cross(t_p, std::abs(t_p.x) < 0.9 ? glm::dvec3(1, 0, 0) : glm::dvec3(0, 1, 0)));
  const glm::dvec3 e2 = glm::cross(t_p, e1);
  const glm::dmat3 r = glm::transpose(glm::dmat3(e1, e2, t_p));
  const glm::dmat3 s = glm::transpose(r) * glm::dmat3(glm::dvec3(1, 0, 0), glm::dvec3(0, 1, 0), glm::dvec3(0, 0, alpha * alpha)) * r;
  const glm::dvec3 h = glm::normalize(l + v);
  const double q = glm::dot(h, glm::inverse(s) * h);
  const double d = 1.0 / (glm::pi<double>() * alpha * q * q);
  const auto sigma = [&](glm::dvec3 x) { return std::sqrt(glm::dot(x, s * x)); };
  const double lambda_l = sigma(l) / cos_l, lambda_v = sigma(v) / cos_v;
  // Radiance towards v per unit irradiance E from l: ∫ (dτ'/cos_v) σ_s(l) p(l→v) e^{…},
  // with σ_s(l) p = σ(l) · D(h)/(4σ(l)) = D(h)/4; f_t = that / cos_l.
  constexpr int kIntervals = 2000;
  const double depth = 2.0, step = depth / kIntervals;
  double integral = 0.0;
  for (int i = 0; i <= kIntervals; ++i) {
    const double tau = i * step;
    const double weight = (i == 0 || i == kIntervals) ? 1.0 : (i % 2 ? 4.0 : 2.0);
    integral += weight * std::exp(-(depth - tau) * lambda_l - tau * lambda_v);
  }
  integral *= step / 3.0;
  const double specular = d / 4.0 * integral / cos_v / cos_l;
  return glm::dvec3(m.specular_albedo) * specular +
         glm::dvec3(m.diffuse_albedo) * (m.diffuse_transmission / glm::pi<double>());
}

YarnMaterial Microflake(float roughness, float height_scale, float blend, glm::vec3 diffuse, glm::vec3 specular,
                        float transmission = 0.0f) {
  YarnMaterial m;
  m.diffuse_transmission = transmission;
  m.model = YarnShadingModel::kMicroflake;
  m.roughness = roughness;
  m.height_scale = height_scale;
  m.lambert_blend = blend;
  m.diffuse_albedo = diffuse;
  m.specular_albedo = specular;
  return m;
}

glm::vec3 RandomUnit(std::mt19937& rng) {
  std::normal_distribution<float> normal;
  return glm::normalize(glm::vec3(normal(rng), normal(rng), normal(rng)));
}

// Compares a float evaluation with its double-precision twin, channel by channel:
// where the twin is 0 the evaluation must be too; elsewhere `worst` keeps the largest
// relative difference and `compared` counts the inputs with a nonzero red channel.
void Compare(const glm::vec3& f, const glm::dvec3& expected, double& worst, int& compared) {
  for (int c = 0; c < 3; ++c) {
    if (expected[c] == 0.0) {
      EXPECT_EQ(f[c], 0.0f);
      continue;
    }
    worst = std::max(worst, std::abs(f[c] - expected[c]) / expected[c]);
  }
  compared += expected.x > 0.0;
}

TEST(FibreMicroflakeBrdf, EqualsThePapersEquationsWrittenOutWithMatrices) {
  std::mt19937 rng(7);
  std::uniform_real_distribution<float> unit(0.0f, 1.0f);
  int compared = 0;
  double worst = 0.0;
  for (int i = 0; i < 20000; ++i) {
    // β > 0 here: the matrix form of the flattening needs β's inverse (β = 0 is tested below).
    const YarnMaterial m = Microflake(0.05f + 0.95f * unit(rng), 0.05f + 1.95f * unit(rng), unit(rng),
                                      glm::vec3(0.3f, 0.5f, 0.7f), glm::vec3(0.2f, 0.1f, 0.04f));
    const FibreMicroflakeBrdf brdf(m);
    const glm::vec3 n = RandomUnit(rng), t = RandomUnit(rng), l = RandomUnit(rng), v = RandomUnit(rng);
    if (glm::length(glm::cross(n, t)) < 0.05f) continue;  // a fibre (nearly) along the normal
    // Float against double: relative 1e-3 covers the rounding of q² at α = 0.05.
    Compare(brdf.Evaluate(n, t, l, v), PaperBrdf(m, n, t, l, v), worst, compared);
  }
  EXPECT_GT(compared, 7000);  // about half have l above the horizon
  EXPECT_LT(worst, 1e-3) << "worst relative difference";
}

// ∫_{S²} g(ω) dω over an equal-area grid of both hemispheres.
template <typename F>
double OverTheSphere(F g, uint32_t per_hemisphere) {
  double sum = 0.0;
  for (const glm::vec3& w : HemisphereGridDirections(per_hemisphere)) sum += g(w) + g(glm::vec3(w.x, w.y, -w.z));
  return sum * glm::two_pi<double>() / per_hemisphere;
}

TEST(FibreMicroflakeBrdf, DistributionsProjectedAreaIsSigma) {
  // SGGX's normalisation (Heitz et al. 2015 eq. 6): ∫ ⟨ω·m⟩ D(m) dm = σ(ω), the
  // projected area the attenuation uses; what makes the phase function D(h)/(4σ(ω_i))
  // integrate to 1.
  const glm::vec3 fibre = glm::normalize(glm::vec3(0.3f, -0.5f, 0.8f));
  for (float alpha : {0.1f, 0.3f, 0.6f, 1.0f}) {
    for (const glm::vec3& w : {fibre, glm::vec3(0, 0, 1), glm::normalize(glm::vec3(1, 1, 0.2f))}) {
      const double projected = OverTheSphere(
          [&](glm::vec3 m) { return std::max(glm::dot(w, m), 0.0f) * FibreMicroflakeD(m, fibre, alpha); },
          1024 * 1024);
      EXPECT_NEAR(projected, FibreMicroflakeSigma(w, fibre, alpha), 2e-3) << alpha;
    }
  }
}

// ∫ f_r(l, v) ⟨v·n⟩ dω_v over n's hemisphere (f_r is 0 below it), red channel.
double DirectionalAlbedo(const FibreMicroflakeBrdf& brdf, glm::vec3 n, glm::vec3 t, glm::vec3 l, uint32_t count) {
  return OverTheSphere([&](glm::vec3 v) { return brdf.Evaluate(n, t, l, v).r * std::max(glm::dot(v, n), 0.0f); },
                       count);
}

TEST(FibreMicroflakeBrdf, WhiteFurnaceSpecularLayerReflectsAtMostWhatItsFirstScatteringTakes) {
  // One scattering in a layer of optical depth Tρσ(l)/μ_l along the light: at most
  // 1 − e^{−Tρσ(l)/μ_l} of the light is scattered, and only part of it leaves upwards.
  // On a tilted surface, so that the height scale moves the fibre.
  const glm::vec3 n = glm::normalize(glm::vec3(0.5f, 0.0f, 1.0f));
  const auto lights = HemisphereGridDirections(6 * 6);
  for (float alpha : {0.1f, 0.3f, 1.0f}) {
    for (float beta : {0.0f, 1.0f, 2.0f}) {
      const FibreMicroflakeBrdf brdf(Microflake(alpha, beta, 1.0f, glm::vec3(0.0f), glm::vec3(1.0f)));
      double largest = 0.0, slack = 1.0;
      for (const glm::vec3& t : {glm::vec3(0, 1, 0), glm::vec3(1, 0, 0), glm::normalize(glm::vec3(1, 1, 0))}) {
        const glm::vec3 fibre = ScaledPlyFrame(n, t, beta).fibre;
        for (const glm::vec3& light : lights) {
          const glm::vec3 l = glm::normalize(light + n * 0.2f);  // above n's horizon
          const double albedo = DirectionalAlbedo(brdf, n, t, l, 192 * 192);
          const double scattered =
              -std::expm1(-kMicroflakeOpticalDepth * FibreMicroflakeSigma(l, fibre, alpha) / glm::dot(l, n));
          largest = std::max(largest, albedo);
          slack = std::min(slack, scattered - albedo);
        }
      }
      EXPECT_LE(largest, 1.0) << "alpha " << alpha << " beta " << beta;
      EXPECT_GE(slack, -2e-3) << "alpha " << alpha << " beta " << beta;
      EXPECT_GT(largest, 0.2) << "alpha " << alpha << " beta " << beta;  // it does reflect
      std::printf("alpha %.1f beta %.0f: largest albedo %.4f, least slack %.4f\n", alpha, beta, largest, slack);
    }
  }
}

TEST(FibreMicroflakeBrdf, TransmissionEqualsTheLayersSingleScatteringIntegrated) {
  std::mt19937 rng(11);
  std::uniform_real_distribution<float> unit(0.0f, 1.0f);
  int compared = 0;
  double worst = 0.0;
  for (int i = 0; i < 4000; ++i) {
    const YarnMaterial m = Microflake(0.05f + 0.95f * unit(rng), 0.05f + 1.95f * unit(rng), unit(rng),
                                      glm::vec3(0.3f, 0.5f, 0.7f), glm::vec3(0.2f, 0.1f, 0.04f), unit(rng));
    const FibreMicroflakeBrdf brdf(m);
    const glm::vec3 n = RandomUnit(rng), t = RandomUnit(rng), l = RandomUnit(rng), v = RandomUnit(rng);
    if (glm::length(glm::cross(n, t)) < 0.05f || glm::dot(v, n) < 0.02f || glm::length(l + v) < 0.05f) continue;
    EXPECT_EQ(brdf.Evaluate(n, t, l, v) == glm::vec3(0.0f), glm::dot(l, n) <= 0.0f);  // one or the other
    Compare(brdf.Transmit(n, t, l, v), PaperBtdf(m, n, t, l, v), worst, compared);
  }
  EXPECT_GT(compared, 1000);
  EXPECT_LT(worst, 2e-3) << "worst relative difference";
}

TEST(FibreMicroflakeBrdf, TransmissionIsReciprocal) {
  // Swapping light and view swaps the sides: f_t(l, v; n) = f_t(v, l; −n).
  std::mt19937 rng(13);
  const FibreMicroflakeBrdf brdf(Microflake(0.3f, 1.0f, 1.0f, glm::vec3(0.2f), glm::vec3(0.7f)));
  int compared = 0;
  for (int i = 0; i < 2000; ++i) {
    const glm::vec3 n = RandomUnit(rng), t = RandomUnit(rng), l = RandomUnit(rng), v = RandomUnit(rng);
    if (glm::dot(l, n) > -0.05f || glm::dot(v, n) < 0.05f || glm::length(glm::cross(n, t)) < 0.05f) continue;
    const float forward = brdf.Transmit(n, t, l, v).r, backward = brdf.Transmit(-n, t, v, l).r;
    EXPECT_NEAR(forward, backward, 1e-4f * forward) << i;
    ++compared;
  }
  EXPECT_GT(compared, 300);
}

TEST(FibreMicroflakeBrdf, WhiteFurnaceReflectedAndTransmittedTogetherStayWithinTheFirstScattering) {
  // Light l from above the layer: its single scattering leaves upwards (f_r) and
  // downwards (f_t with the layer turned over: light behind −n, view in front of it);
  // together at most 1 − e^{−Tρσ(l)/μ_l} of it.
  const glm::vec3 n(0, 0, 1);
  for (float alpha : {0.1f, 0.3f, 1.0f}) {
    const FibreMicroflakeBrdf brdf(Microflake(alpha, 1.0f, 1.0f, glm::vec3(0.0f), glm::vec3(1.0f)));
    double least_slack = 1.0, largest_transmitted = 0.0;
    for (const glm::vec3& t : {glm::vec3(1, 0, 0), glm::normalize(glm::vec3(1, 1, 0))}) {
      for (const glm::vec3& light : HemisphereGridDirections(5 * 5)) {
        const glm::vec3 l = glm::normalize(light + n * 0.2f);
        const double reflected = DirectionalAlbedo(brdf, n, t, l, 160 * 160);
        const double transmitted =
            OverTheSphere([&](glm::vec3 v) { return brdf.Transmit(-n, t, l, v).r * std::max(-glm::dot(v, n), 0.0f); },
                          160 * 160);
        const glm::vec3 fibre = ScaledPlyFrame(n, t, 1.0f).fibre;
        const double scattered = -std::expm1(-kMicroflakeOpticalDepth * FibreMicroflakeSigma(l, fibre, alpha) / l.z);
        least_slack = std::min(least_slack, scattered - (reflected + transmitted));
        largest_transmitted = std::max(largest_transmitted, transmitted);
      }
    }
    EXPECT_GE(least_slack, -2e-3) << alpha;
    EXPECT_GT(largest_transmitted, 0.04) << alpha;  // it does transmit
    std::printf("alpha %.1f: largest transmitted %.4f, least slack %.4f\n", alpha, largest_transmitted, least_slack);
  }
}

TEST(FibreMicroflakeBrdf, IsotropicLayerTransmitsWhatRadiativeTransferSays) {
  // α = 1 is an isotropic phase function (specular flakes over a sphere of normals,
  // D = 1/π, σ = 1). Light at normal incidence on a slab of optical depth 2, scattered
  // once, leaves the far side with ½∫₀¹dμ ∫₀² e^{−τ} e^{−(2−τ)/μ} dτ = 0.061512 of its
  // power (a 400 × 400 midpoint sum), and the near side with the same integral of
  // e^{−τ} e^{−τ/μ}, 0.152302.
  const glm::vec3 n(0, 0, 1), t(1, 0, 0);
  const FibreMicroflakeBrdf brdf(Microflake(1.0f, 1.0f, 1.0f, glm::vec3(0.0f), glm::vec3(1.0f)));
  const double transmitted =
      OverTheSphere([&](glm::vec3 v) { return brdf.Transmit(-n, t, n, v).r * std::max(-v.z, 0.0f); }, 256 * 256);
  EXPECT_NEAR(transmitted, 0.061512, 1e-3);
  EXPECT_NEAR(DirectionalAlbedo(brdf, n, t, n, 256 * 256), 0.152302, 1e-3);
}

TEST(FibreMicroflakeBrdf, DiffuseTransmissionTakesItsShareFromTheDiffuseReflection) {
  const glm::vec3 n(0, 0, 1), t(1, 0, 0), l = glm::normalize(glm::vec3(0.2f, 0.1f, 1.0f));
  for (float share : {0.0f, 0.25f, 1.0f}) {
    const FibreMicroflakeBrdf brdf(Microflake(0.5f, 1.0f, 0.5f, glm::vec3(0.8f), glm::vec3(0.0f), share));
    EXPECT_NEAR(brdf.Evaluate(n, t, l, n).r, (1.0f - share) * 0.8f / glm::pi<float>(), 1e-6f);
    EXPECT_NEAR(brdf.Transmit(n, t, -l, n).r, share * 0.8f / glm::pi<float>(), 1e-6f);
    EXPECT_NEAR(brdf.diffuse().r, (1.0f - share) * 0.8f / glm::pi<float>(), 1e-6f);
  }
}

TEST(FibreMicroflakeBrdf, DiffuseAtTheGeometrysOwnHeightIsLambertianWhateverTheBlend) {
  // β = 1: the ply normal is the surface's, so both Lambertians are k_d/π.
  const glm::vec3 n = glm::normalize(glm::vec3(0.4f, -0.3f, 0.9f)), t = glm::vec3(0, 1, 0);
  for (float blend : {0.0f, 0.5f, 1.0f}) {
    const FibreMicroflakeBrdf brdf(Microflake(0.5f, 1.0f, blend, glm::vec3(0.8f), glm::vec3(0.0f)));
    for (const glm::vec3& l : HemisphereGridDirections(64)) {
      if (glm::dot(l, n) < 0.05f) continue;
      EXPECT_NEAR(brdf.Evaluate(n, t, l, n).r, 0.8f / glm::pi<float>(), 1e-5f);
    }
  }
}

TEST(FibreMicroflakeBrdf, HeightScaleFlattensThePlyFrame) {
  const glm::vec3 n = glm::normalize(glm::vec3(0.6f, 0.0f, 0.8f));
  const glm::vec3 t = glm::normalize(glm::vec3(0.8f, 0.0f, -0.6f) + glm::vec3(0, 0.5f, 0));  // in the surface, tilted
  const PlyFrame flat = ScaledPlyFrame(n, t, 0.0f);
  EXPECT_NEAR(glm::distance(flat.normal, glm::vec3(0, 0, 1)), 0.0f, 1e-6f);
  EXPECT_TRUE(flat.has_fibre);
  EXPECT_NEAR(flat.fibre.z, 0.0f, 1e-6f);
  const PlyFrame same = ScaledPlyFrame(n, t, 1.0f);
  EXPECT_NEAR(glm::distance(same.normal, n), 0.0f, 1e-6f);
  EXPECT_NEAR(glm::dot(same.fibre, n), 0.0f, 1e-6f);
  const PlyFrame steeper = ScaledPlyFrame(n, t, 2.0f);
  EXPECT_LT(steeper.normal.z, n.z);
  EXPECT_NEAR(glm::dot(steeper.fibre, steeper.normal), 0.0f, 1e-6f);  // still a frame
  // A vertical wall flattened: its normal has nowhere to go and stays.
  EXPECT_EQ(ScaledPlyFrame({1, 0, 0}, {0, 0, 1}, 0.0f).normal, glm::vec3(1, 0, 0));
  EXPECT_FALSE(ScaledPlyFrame({1, 0, 0}, {0, 0, 1}, 0.0f).has_fibre);
  EXPECT_FALSE(ScaledPlyFrame({0, 0, 1}, {0, 0, 1}, 1.0f).has_fibre);
}

TEST(FibreMicroflakeBrdf, HighlightLiesAcrossTheFibreAndNarrowsWithRoughness) {
  // The microflake normals lie across the fibre: with the fibre along x, the half
  // vector of a mirror pair about z has no x and D is largest; tilted along x it falls,
  // the faster the smoother the fibre.
  const glm::vec3 n(0, 0, 1), t(1, 0, 0);
  const glm::vec3 l = glm::normalize(glm::vec3(0, 0.5f, 1));
  const glm::vec3 mirror = glm::normalize(glm::vec3(0, -0.5f, 1));
  const glm::vec3 off = glm::normalize(glm::vec3(0.4f, -0.5f, 1));
  float previous_ratio = 1.0f;
  for (float alpha : {0.6f, 0.3f, 0.1f}) {
    const FibreMicroflakeBrdf brdf(Microflake(alpha, 1.0f, 1.0f, glm::vec3(0.0f), glm::vec3(1.0f)));
    const float ratio = brdf.Evaluate(n, t, l, off).r / brdf.Evaluate(n, t, l, mirror).r;
    EXPECT_LT(ratio, previous_ratio) << alpha;
    previous_ratio = ratio;
  }
  EXPECT_LT(previous_ratio, 0.1f);
}

TEST(FibreMicroflakeBrdf, DegenerateInputsStayFinite) {
  const glm::vec3 n(0, 0, 1);
  // A roughness the spec allows (above 0) but float cannot invert: the fibre exactly
  // across the half vector made 1/α² · 0 a NaN.
  for (float roughness : {1e-30f, 1e-10f}) {
    const FibreMicroflakeBrdf tiny(Microflake(roughness, 1.0f, 1.0f, glm::vec3(0.5f), glm::vec3(0.5f)));
    const glm::vec3 f = tiny.Evaluate(n, {1, 0, 0}, glm::normalize(glm::vec3(0, 1, 1)), glm::normalize(glm::vec3(0, -1, 1)));
    EXPECT_TRUE(std::isfinite(f.r) && f.r > 0.0f) << roughness;
  }
  const FibreMicroflakeBrdf brdf(Microflake(0.01f, 0.0f, 0.5f, glm::vec3(0.5f), glm::vec3(0.5f)));
  for (const glm::vec3& t : {glm::vec3(0.0f), glm::vec3(0, 0, 1), glm::vec3(1, 0, 0)}) {
    for (const glm::vec3& l : {glm::vec3(0, 0, 1), glm::vec3(1, 0, 1e-7f), glm::vec3(0, 1, 1e-7f)}) {
      const glm::vec3 f = brdf.Evaluate(n, t, l, l);
      EXPECT_TRUE(std::isfinite(f.r) && f.r >= 0.0f);
    }
  }
  EXPECT_EQ(brdf.Evaluate(n, glm::vec3(0.0f), {0, 0, 1}, {0, 0, 1}), brdf.diffuse());
  EXPECT_EQ(brdf.Evaluate(n, {1, 0, 0}, {0, 0, -1}, {0, 0, 1}), glm::vec3(0.0f));
}

}  // namespace
}  // namespace loom
