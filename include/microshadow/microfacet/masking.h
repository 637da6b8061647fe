// Masking-shadowing forms built on any Smith NDF class (GGX, Beckmann, BlinnPhong, GTR: anything with
// Lambda(w) and G1(w)), and the closed-form GGX visibility terms used by real-time engines.
// RTR4 eqs. 9.24–9.32 (Heitz 2014, "Understanding the Masking-Shadowing Function in Microfacet-Based BRDFs"),
// 9.43 (Lagarde 2014), 9.44 (Karis 2013), 9.45 (Hammon 2017).
//
// Convention: wo = view v, wi = light l, wm = microfacet normal, all unit vectors in the shading frame. The
// χ⁺ factors use the sign convention of GGX<T>::G1(w, m): a direction sees a microfacet iff (w·m)(w·n) > 0.
// Every function is finite for any unit input (grazing, backfacing, zero-length vectors give 0 or a bound).
#pragma once

#include <microshadow/math/vec.h>

#include <algorithm>
#include <cmath>
#include <limits>

namespace msh {

// χ⁺ of the microfacet for direction w (9.25): 1 if w is on the same side of the facet as of the
// macrosurface.
template <class T>
constexpr T chi_plus_facet(const Vec3<T>& w, const Vec3<T>& wm) {
  return dot(w, wm) * w.z > T(0) ? T(1) : T(0);
}

// Relative azimuth φ ∈ [0, π] between the tangent-plane projections of a and b (0 when either is along n).
template <class T>
T relative_azimuth(const Vec3<T>& a, const Vec3<T>& b) {
  const T la = std::sqrt(a.x * a.x + a.y * a.y), lb = std::sqrt(b.x * b.x + b.y * b.y);
  if (!(la > T(0)) || !(lb > T(0))) return T(0);
  return safe_acos((a.x * b.x + a.y * b.y) / (la * lb));
}

// Direction-correlation weights λ(φ), increasing from 0 at φ = 0 to ~1: Ashikhmin et al. 2000 (9.29), a
// Gaussian with σ = 15°, and van Ginneken et al. 1998 (9.30). Domain φ ∈ [0, π].
template <class T>
T lambda_ashikhmin(T phi) {
  return T(1) - std::exp(T(-7.3) * phi * phi);
}
template <class T>
T lambda_van_ginneken(T phi) {
  const T x = T(4.41) * std::max(phi, T(0));
  return x / (x + T(1));
}

// Separable (uncorrelated) Smith G2 (9.27): G1(v, m) G1(l, m).
template <class T, class NDF>
T G2_separable(const NDF& ndf, const Vec3<T>& wo, const Vec3<T>& wi, const Vec3<T>& wm) {
  return ndf.G1(wo, wm) * ndf.G1(wi, wm);
}

// Height-correlated Smith G2 (9.31): χ⁺χ⁺ / (1 + Λ(v) + Λ(l)), evaluated through G1 (finite at grazing).
template <class T, class NDF>
T G2_height_correlated(const NDF& ndf, const Vec3<T>& wo, const Vec3<T>& wi, const Vec3<T>& wm) {
  if (chi_plus_facet(wo, wm) * chi_plus_facet(wi, wm) == T(0)) return T(0);
  return ndf.G2(wo, wi);
}

// Direction-correlated G2 (9.28): λ(φ) G1(v,m)G1(l,m) + (1 − λ(φ)) min(G1(v,m), G1(l,m)), φ the relative
// azimuth of v and l; λ is lambda_ashikhmin or lambda_van_ginneken (any callable T → [0,1]).
template <class T, class NDF, class LambdaPhi>
T G2_direction_correlated(const NDF& ndf, const Vec3<T>& wo, const Vec3<T>& wi, const Vec3<T>& wm,
                          LambdaPhi&& lambda_phi) {
  const T go = ndf.G1(wo, wm), gi = ndf.G1(wi, wm);
  const T l = saturate(T(lambda_phi(relative_azimuth(wo, wi))));
  return l * go * gi + (T(1) - l) * std::min(go, gi);
}

// Height-direction-correlated G2 (9.32): χ⁺χ⁺ / (1 + max(Λv, Λl) + λ(φ) min(Λv, Λl)). Evaluated through
// G1 = 1/(1 + Λ): with gmax = G1 of the larger Λ (the smaller G1) and gmin = the other,
// G2 = gmin·gmax / (gmin + λ(1 − gmin)·gmax), finite at grazing.
template <class T, class NDF, class LambdaPhi>
T G2_height_direction_correlated(const NDF& ndf, const Vec3<T>& wo, const Vec3<T>& wi, const Vec3<T>& wm,
                                 LambdaPhi&& lambda_phi) {
  if (chi_plus_facet(wo, wm) * chi_plus_facet(wi, wm) == T(0)) return T(0);
  const T go = ndf.G1(wo), gi = ndf.G1(wi);
  const T small = std::min(go, gi), large = std::max(go, gi);  // small ↔ max Λ, large ↔ min Λ
  const T l = saturate(T(lambda_phi(relative_azimuth(wo, wi))));
  const T den = large + l * (T(1) - large) * small;
  return den > T(0) ? small * large / den : T(0);
}

// ---- GGX closed forms on μ = cos θ (isotropic α). μ is clamped to [0, 1] (μ⁺ in RTR4's notation).

// Combined height-correlated GGX visibility G2/(4 μo μi) (9.43, Lagarde 2014):
// 0.5 / (μo sqrt(α² + μi(μi − α²μi)) + μi sqrt(α² + μo(μo − α²μo))). Returns 0 when the denominator vanishes
// (μo = μi = 0, or a grazing direction with α = 0), where the product with the BRDF's D is not defined
// anyway.
template <class T>
T ggx_visibility_height_correlated(T mu_o, T mu_i, T alpha) {
  const T mo = saturate(mu_o), mi = saturate(mu_i), a2 = alpha * alpha;
  const T den = mo * std::sqrt(a2 + mi * (mi - a2 * mi)) + mi * std::sqrt(a2 + mo * (mo - a2 * mo));
  return den > T(0) ? T(0.5) / den : T(0);
}

// Karis 2013 approximation of the GGX G1 (9.44): 2μ / (μ(2 − α) + α). Domain μ ∈ [0,1], α ∈ [0,1].
template <class T>
T karis_G1(T mu, T alpha) {
  const T m = saturate(mu);
  const T den = m * (T(2) - alpha) + alpha;
  return den > T(0) ? T(2) * m / den : T(1);
}

// Hammon 2017 approximation of the combined visibility (9.45): 0.5 / lerp(2 μo μi, μo + μi, α).
template <class T>
T hammon_visibility(T mu_o, T mu_i, T alpha) {
  const T mo = saturate(mu_o), mi = saturate(mu_i);
  const T den = lerp(alpha, T(2) * mo * mi, mo + mi);
  return den > T(0) ? T(0.5) / den : T(0);
}

}  // namespace msh
