// Diffuse (local subsurface) BRDF terms, RTR4 §9.9: Lambert (9.61), the (1 − F) couplings (9.62, 9.63),
// Shirley et al. 1997 (9.64), Ashikhmin-Shirley / Kelemen-Szirmay-Kalos (9.65), Disney diffuse with its
// subsurface term (Burley 2012; 9.66–9.67), Hammon 2017 (9.68–9.69), and Oren-Nayar 1994 (full and
// qualitative). Local frame, n = +z; l = wi (light), v = wo (view). All return the BRDF without the cosine,
// zero when either direction is at or below the horizon, finite for every unit input. C is the colour type (T
// or Rgb<T>).
#pragma once

#include <microshadow/bsdf/fresnel.h>
#include <microshadow/math/color.h>
#include <microshadow/math/vec.h>

namespace msh::bsdf {

namespace diffuse_terms {
template <class T>
bool both_above(const Vec3<T>& l, const Vec3<T>& v) {
  return l.z > T(0) && v.z > T(0);
}
// Half vector of two upper-hemisphere directions; +z when l = −v (only possible at grazing).
template <class T>
Vec3<T> half_vector(const Vec3<T>& l, const Vec3<T>& v) {
  return normalize(l + v, Vec3<T>(0, 0, 1));
}
}  // namespace diffuse_terms

// Lambert (RTR4 9.61): ρ_ss / π.
template <class T, class C>
C diffuse_lambert(const C& rho, const Vec3<T>& l, const Vec3<T>& v) {
  return diffuse_terms::both_above(l, v) ? rho * kInvPi<T> : C(T(0));
}

// (1 − F(n, l)) ρ/π with Schlick F (RTR4 9.62): coupling to a flat Fresnel mirror. Not reciprocal (it
// depends on l only).
template <class T, class C>
C diffuse_fresnel_n(const C& rho, const C& f0, const Vec3<T>& l, const Vec3<T>& v) {
  if (!diffuse_terms::both_above(l, v)) return C(T(0));
  return (C(T(1)) - fresnel_schlick(f0, l.z)) * rho * kInvPi<T>;
}

// (1 − F(h, l)) ρ/π with Schlick F (RTR4 9.63): coupling to a microfacet specular term. Reciprocal (h·l =
// h·v).
template <class T, class C>
C diffuse_fresnel_h(const C& rho, const C& f0, const Vec3<T>& l, const Vec3<T>& v) {
  if (!diffuse_terms::both_above(l, v)) return C(T(0));
  const Vec3<T> h = diffuse_terms::half_vector(l, v);
  return (C(T(1)) - fresnel_schlick(f0, dot(h, l))) * rho * kInvPi<T>;
}

// Shirley et al. 1997 coupled diffuse (RTR4 9.64): 21/(20π) (1 − F0) ρ (1 − (1 − n·l)⁵)(1 − (1 − n·v)⁵).
// Pairs with a flat Schlick mirror: diffuse albedo = ρ (1 − F_Schlick(n·v)), so the pair conserves energy.
template <class T, class C>
C diffuse_shirley(const C& rho, const C& f0, const Vec3<T>& l, const Vec3<T>& v) {
  if (!diffuse_terms::both_above(l, v)) return C(T(0));
  const T k = T(21) / (T(20) * kPi<T>)*(T(1) - schlick_weight(l.z)) * (T(1) - schlick_weight(v.z));
  return (C(T(1)) - f0) * rho * k;
}

// Kelemen & Szirmay-Kalos 2001 / Ashikhmin & Shirley 2000 coupled diffuse (RTR4 9.65):
// ρ (1 − R(l))(1 − R(v)) / (π (1 − R̄)), given the specular directional albedos R(l), R(v) and their cosine
// average R̄. Diffuse albedo = ρ (1 − R(v)): specular + diffuse = 1 at ρ = 1. R̄ → 1 (mirror with F = 1) is
// guarded: the numerator vanishes with it.
template <class T, class C>
C diffuse_ksk(const C& rho, const C& r_l, const C& r_v, const C& r_avg, const Vec3<T>& l, const Vec3<T>& v) {
  if (!diffuse_terms::both_above(l, v)) return C(T(0));
  const C one(T(1));
  C den = one - r_avg;
  if constexpr (std::is_same_v<C, T>) {
    den = std::max(den, T(1e-6));
  } else {
    den = C(std::max(den.r, T(1e-6)), std::max(den.g, T(1e-6)), std::max(den.b, T(1e-6)));
  }
  return rho * (one - r_l) * (one - r_v) / den * kInvPi<T>;
}

// Disney diffuse with the subsurface term (Burley 2012, "Physically-Based Shading at Disney";
// RTR4 9.66–9.67): ρ/π ((1 − k_ss) f_d + 1.25 k_ss f_ss). roughness = perceptual r (RTR4's √α), k_ss =
// subsurface in [0,1]. f_ss uses 1/(n·l + n·v) as in Burley's reference code (disney.brdf, BRDF Explorer);
// RTR4 prints 1/((n·l)(n·v)), which diverges at grazing — we follow the source. Reciprocal; not energy
// conserving (f_d retro-reflects up to F_D90 = 2.5).
template <class T, class C>
C diffuse_disney(const C& rho, T roughness, T subsurface, const Vec3<T>& l, const Vec3<T>& v) {
  if (!diffuse_terms::both_above(l, v)) return C(T(0));
  const Vec3<T> h = diffuse_terms::half_vector(l, v);
  const T hl2 = sqr(saturate(dot(h, l)));
  const T wl = schlick_weight(l.z), wv = schlick_weight(v.z);
  const T fd90 = T(0.5) + T(2) * roughness * hl2;
  const T fd = (T(1) + (fd90 - T(1)) * wl) * (T(1) + (fd90 - T(1)) * wv);
  const T fss90 = roughness * hl2;
  const T fss_f = (T(1) + (fss90 - T(1)) * wl) * (T(1) + (fss90 - T(1)) * wv);
  const T fss = (T(1) / (l.z + v.z) - T(0.5)) * fss_f + T(0.5);
  const T k = saturate(subsurface);
  return rho * (kInvPi<T> * ((T(1) - k) * fd + T(1.25) * k * fss));
}

// Hammon 2017, "PBR Diffuse Lighting for GGX+Smith Microsurfaces" (RTR4 9.68–9.69): a fit to a two-bounce
// simulation of a GGX/height-correlated-Smith microsurface whose facets carry the 9.64 coupled diffuse.
// alpha = GGX α. ρ enters twice (single bounce ρ/π, multi-bounce ρ²/π · 0.3641 α). Reciprocal.
template <class T, class C>
C diffuse_hammon(const C& rho, T alpha, const C& f0, const Vec3<T>& l, const Vec3<T>& v) {
  if (!diffuse_terms::both_above(l, v)) return C(T(0));
  const Vec3<T> h = diffuse_terms::half_vector(l, v);
  const T a = saturate(alpha);
  const T smooth_k = T(21) / T(20) * (T(1) - schlick_weight(l.z)) * (T(1) - schlick_weight(v.z));
  const C f_smooth = (C(T(1)) - f0) * smooth_k;
  const T facing = T(0.5) + T(0.5) * dot(l, v);
  const T nh = std::max(h.z, T(1e-4));  // n·h ≥ √(1/2)·… except when l ≈ −v at grazing
  const T f_rough = facing * (T(0.9) - T(0.4) * facing) * ((T(0.5) + nh) / nh);
  const T f_multi = T(0.3641) * a;
  return rho * kInvPi<T> * (f_smooth * (T(1) - a) + C(a * f_rough) + rho * f_multi);
}

namespace diffuse_terms {
// Oren-Nayar angles: α = max(θl, θv), β = min(θl, θv), and cos(φl − φv) (0 when either is at the pole).
template <class T>
void oren_nayar_angles(const Vec3<T>& l, const Vec3<T>& v, T& alpha, T& beta, T& cos_dphi) {
  const T tl = safe_acos(l.z), tv = safe_acos(v.z);
  alpha = std::max(tl, tv);
  beta = std::min(tl, tv);
  const T sl = sin_theta(l), sv = sin_theta(v);
  cos_dphi =
      (sl > T(1e-12) && sv > T(1e-12)) ? clamp((l.x * v.x + l.y * v.y) / (sl * sv), T(-1), T(1)) : T(0);
}
template <class T>
T tan_clamped(T theta) {
  return std::sin(theta) / std::max(std::cos(theta), T(1e-7));
}
// The angles and the σ-dependent coefficients shared by both Oren-Nayar models: A (= C1) = 1 − 0.5σ²/(σ² +
// 0.33) and B = 0.45σ²/(σ² + 0.09).
template <class T>
struct OrenNayarTerms {
  T a, b, cos_dphi, s2, A, B;
};
template <class T>
OrenNayarTerms<T> oren_nayar_terms(T sigma, const Vec3<T>& l, const Vec3<T>& v) {
  OrenNayarTerms<T> t;
  oren_nayar_angles(l, v, t.a, t.b, t.cos_dphi);
  t.s2 = sigma * sigma;
  t.A = T(1) - T(0.5) * t.s2 / (t.s2 + T(0.33));
  t.B = T(0.45) * t.s2 / (t.s2 + T(0.09));
  return t;
}
}  // namespace diffuse_terms

// Oren & Nayar 1994, "Generalization of Lambert's Reflectance Model" (SIGGRAPH), full model (their eqs. for
// L1 with C1, C2, C3, plus the interreflection term L2). sigma = standard deviation of the facet slope angle
// in radians (V-cavities, Gaussian slopes). Reciprocal. sigma = 0 gives Lambert.
template <class T, class C>
C diffuse_oren_nayar(const C& rho, T sigma, const Vec3<T>& l, const Vec3<T>& v) {
  if (!diffuse_terms::both_above(l, v)) return C(T(0));
  const diffuse_terms::OrenNayarTerms<T> t = diffuse_terms::oren_nayar_terms(sigma, l, v);
  const T a = t.a, b = t.b, cphi = t.cos_dphi, s2 = t.s2, c1 = t.A, k2 = t.B;
  const T c2 = cphi >= T(0) ? k2 * std::sin(a) : k2 * (std::sin(a) - std::pow(T(2) * b / kPi<T>, T(3)));
  const T c3 = T(0.125) * s2 / (s2 + T(0.09)) * sqr(T(4) * a * b / (kPi<T> * kPi<T>));
  const T l1 = c1 + cphi * c2 * diffuse_terms::tan_clamped(b) +
               (T(1) - std::abs(cphi)) * c3 * diffuse_terms::tan_clamped((a + b) / T(2));
  const T l2 = T(0.17) * s2 / (s2 + T(0.13)) * (T(1) - cphi * sqr(T(2) * b / kPi<T>));
  return rho * (kInvPi<T> * l1) + rho * rho * (kInvPi<T> * l2);
}

// Oren-Nayar "qualitative" model (same paper): ρ/π (A + B max(0, cos(φl − φv)) sin α tan β),
// A = 1 − 0.5 σ²/(σ² + 0.33), B = 0.45 σ²/(σ² + 0.09). Reciprocal.
template <class T, class C>
C diffuse_oren_nayar_qualitative(const C& rho, T sigma, const Vec3<T>& l, const Vec3<T>& v) {
  if (!diffuse_terms::both_above(l, v)) return C(T(0));
  const diffuse_terms::OrenNayarTerms<T> t = diffuse_terms::oren_nayar_terms(sigma, l, v);
  return rho * (kInvPi<T> *
                (t.A + t.B * std::max(T(0), t.cos_dphi) * std::sin(t.a) * diffuse_terms::tan_clamped(t.b)));
}

}  // namespace msh::bsdf
