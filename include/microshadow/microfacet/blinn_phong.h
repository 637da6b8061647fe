// Blinn-Phong microfacet distribution, RTR4 eq. 9.40: D(m) = (αp + 2)/(2π) (n·m)^αp, isotropic.
// Not shape-invariant, so Smith Λ has no closed form: Λ is the Beckmann Λ at the equivalent αb = sqrt(2/(αp +
// 2)) (the relation αp = 2αb⁻² − 2, Walter et al. 2007, RTR4 p. 340). Consequently the projected-area
// identity ∫ G1 D (v·m)⁺ dm = n·v holds only approximately (measured error in docs/microfacet.md) and there
// is no exact visible-normal sampler: only plain NDF sampling (exact inverse CDF).
//
// Domain: αp ≥ 0 (αp = 0 is the uniform hemisphere NDF; large αp is smooth, capped at kMaxExponent so D stays
// finite in float; NaN is a precondition violation and propagates). Same member names as GGX<T> except
// Sample_wm and PDF; the Smith members (G1, G2, D(w, m), pdf_ndf) are smith.h's.
#pragma once

#include <microshadow/math/sampling.h>
#include <microshadow/math/vec.h>
#include <microshadow/microfacet/beckmann.h>
#include <microshadow/microfacet/smith.h>

namespace msh {

// αp = 2αb⁻² − 2 (RTR4 p. 340); αb → 0 gives the largest finite T.
template <class T>
T blinn_phong_exponent_from_beckmann(T alpha_b) {
  const T a2 = alpha_b * alpha_b;
  if (!(a2 > T(2) / std::numeric_limits<T>::max())) return std::numeric_limits<T>::max();
  return std::max(T(0), T(2) / a2 - T(2));
}
// αb = sqrt(2/(αp + 2)), the inverse relation; αp < 0 is treated as 0.
template <class T>
T beckmann_alpha_from_blinn_phong(T alpha_p) {
  return std::sqrt(T(2) / (std::max(alpha_p, T(0)) + T(2)));
}

template <class T>
class BlinnPhong : public SmithMicrofacet<BlinnPhong<T>, T> {
  using Smith = SmithMicrofacet<BlinnPhong<T>, T>;

 public:
  using Smith::D;

  // D at the pole is (αp+2)/(2π): 1e7 keeps it well inside float range and is sharper than any measured
  // material.
  static constexpr T kMaxExponent = T(1e7);

  BlinnPhong() = default;
  explicit BlinnPhong(T alpha_p)
      : ap_(alpha_p > T(0) || std::isnan(alpha_p) ? std::min(alpha_p, kMaxExponent) : T(0)),
        beckmann_(beckmann_alpha_from_blinn_phong(ap_)) {}

  T exponent() const { return ap_; }
  // The Beckmann distribution whose Λ this one uses.
  const Beckmann<T>& beckmann() const { return beckmann_; }

  // D(m) (9.40); zero for m.z ≤ 0.
  T D(const Vec3<T>& wm) const {
    if (!(wm.z > T(0))) return T(0);
    return (ap_ + T(2)) * (T(0.5) * kInvPi<T>)*std::pow(std::min(wm.z, T(1)), ap_);
  }
  // Λ and G1/|cos θ| via the Beckmann equivalence (Walter et al. 2007); G1, G2 and the visible normals
  // (which integrate to 1 only up to that approximation) follow from them in smith.h.
  T Lambda(const Vec3<T>& w) const { return beckmann_.Lambda(w); }
  T G1_over_cos(const Vec3<T>& w) const { return beckmann_.G1_over_cos(w); }

  // Plain NDF sampling, pdf D(m)(n·m): cos θ = (1 − u.x)^(1/(αp + 2)), φ = 2π u.y (exact inverse CDF).
  Vec3<T> sample_ndf(Vec2<T> u) const {
    const T cos_t = std::exp(std::log1p(-std::min(u.x, kOneMinusEpsilon<T>)) / (ap_ + T(2)));
    return spherical_direction(std::min(cos_t, T(1)), T(2) * kPi<T> * u.y);
  }

 private:
  T ap_ = T(30);
  Beckmann<T> beckmann_{beckmann_alpha_from_blinn_phong(T(30))};
};
static_assert(SmithDistribution<BlinnPhong<double>> && !VisibleNormalSampler<BlinnPhong<double>>);

}  // namespace msh
