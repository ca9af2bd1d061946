#pragma once
// The lumislice paper's knit force laws (§4.1): springs with a balance
// interval, the thickness force field, and the angle forces of bending and
// shearing, as pure functions of a length, a distance or three points. Forces
// are in the simulation's units (docs/animation.md "Units": a mass point weighs
// 1, lengths in loops); each law is chosen continuous where the paper's text is
// not, and docs/animation.md derives each choice.

#include <array>
#include <glm/glm.hpp>

namespace loom::animate {

// A spring of rest length l between neighbouring loops: no force while its
// length lies in [balance_low·l, balance_high·l] (the paper's θ₂, θ₁ — its text
// swaps them); beyond, stretch·(e^{(x−θ₁)/θ₁} − 1) pulling its ends together,
// and below, compress·(e^{(θ₂−x)/θ₂} − 1) pushing them apart.
struct SpringLaw {
  float stretch = 0.0f;   // c₀
  float compress = 0.0f;  // c₁
  float balance_low = 0.95f;
  float balance_high = 1.05f;
};

// The force along the spring at `length`: positive pulls the ends together.
float SpringForce(const SpringLaw& law, float rest, float length);
// |dF/dlength| there (0 inside the interval): the spring's stiffness, for the
// step bound.
float SpringStiffness(const SpringLaw& law, float rest, float length);

// The thickness force field (eq. 1 and 2) of a knit of thickness 2T, as a
// function of the distance d from its centre surface: c₅(T − d)² for τ ≤ d < T,
// c₆e^{α/(d+β)} for 0 < d < τ, 0 beyond T. c₆, α, β are chosen so that the
// force and its slope are continuous at τ and the force grows without bound as
// d → 0 (β = 0); the paper's own constants give no such barrier
// (docs/animation.md).
class ThicknessField {
 public:
  ThicknessField() = default;
  // half_thickness T > core τ > 0, strength c₅ > 0.
  ThicknessField(float half_thickness, float core, float strength);
  float operator()(float d) const;  // the repulsion at d ≥ 0 (+∞ at 0)
  float Slope(float d) const;       // dF/dd there (≤ 0)
  float half_thickness() const { return half_thickness_; }
  float core() const { return core_; }
  float c6() const { return c6_; }
  float alpha() const { return alpha_; }
  // The distance at which the field's repulsion equals `force` (T for force ≤
  // 0).
  float DistanceOf(float force) const;

 private:
  float half_thickness_ = 0.0f, core_ = 0.0f, strength_ = 0.0f;
  float c6_ = 0.0f, alpha_ = 0.0f;
};

// Forces on three points a, b, c of a wale or a course (bending: the turn at b
// from a→b to b→c, at rest 0) or of a corner (shearing: the angle at b between
// b→a and b→c, at rest `rest_angle`): −constant · excess · arm · ∇(angle), the
// gradient of the energy ½·constant·arm·excess², so an arm at its rest length
// `arm` feels constant × excess, the paper's "proportional to the angle". They
// add up to zero and exert no torque. Zero where the angle's gradient is
// undefined (a straight corner).
std::array<glm::vec3, 3> BendForces(glm::vec3 a, glm::vec3 b, glm::vec3 c, float constant, float arm);
std::array<glm::vec3, 3> ShearForces(glm::vec3 a, glm::vec3 b, glm::vec3 c, float rest_angle, float constant,
                                     float arm);

}  // namespace loom::animate
