// The Lafortune model of core/fit/lafortune_brdf.h (Daubert 2001 eq. 2), per RGB
// channel, for unit directions in the texel's local frame:
//   f_1(l, v) = l_z · (ρ + Σ_i [C_x,i l_x v_x + C_y,i l_y v_y + C_z,i l_z v_z]^{N_i}),
// [a]^N = 0 for a ≤ 0. The lookup table T(v) multiplies it outside.

const int kMaxLobes = 3;

// A lobe's value is capped at 2^64 (~1.8e19): the fit keeps no lobe peaking above
// 10·(N + 2)/2π (core/fit/texel_fit.cpp), so no fitted fabric comes near it, but a
// spike fitted between the sampled directions (assets fitted before that guard held
// lobes of 10^233) overflowed float to Inf, and Inf times a zero (shadow, a zero
// T(v), a covering fragment's 1 − alpha) made a NaN pixel. Capped, such a spike
// shows as a blown-out highlight and every product stays finite.
const float kMaxLobeLog2 = 64.0;

struct LafortuneBrdf {
  vec3 rho;
  vec3 cx[kMaxLobes];
  vec3 cy[kMaxLobes];
  vec3 cz[kMaxLobes];
  vec3 n[kMaxLobes];
};

vec3 EvaluateLafortune(LafortuneBrdf brdf, int lobes, vec3 l, vec3 v) {
  if (l.z <= 0.0) return vec3(0.0);
  vec3 sum = brdf.rho;
  vec3 a = l * v;
  for (int i = 0; i < lobes; ++i) {
    vec3 dot_c = brdf.cx[i] * a.x + brdf.cy[i] * a.y + brdf.cz[i] * a.z;
    // x^N = 2^(N·log2 x) for x > 0 only; max() keeps log2's argument in its domain.
    vec3 lobe = exp2(min(brdf.n[i] * log2(max(dot_c, vec3(1e-30))), vec3(kMaxLobeLog2)));
    sum += mix(vec3(0.0), lobe, greaterThan(dot_c, vec3(0.0)));
  }
  return l.z * sum;
}
