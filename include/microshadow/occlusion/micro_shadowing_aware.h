// Micro-BRDF-aware micro-shadowing (docs/micro-shadowing-aware.md): the visibility-cone model of Zurita 2026,
// "Improving Direct Lighting Material Occlusion – Part 2", applied to the light that each facet actually
// sends toward v, for the specular lobe (only the facet m = h) and for a Lambertian micro-BRDF (every facet,
// weighted by its own cosine). Engine-facing, header-only: the specular term (closed form, at full vectors
// and as a BRDF-weighted azimuth mean), the Lambertian cap fraction, the diffuse per-microfacet function and
// its Owen-scrambled Sobol estimator. Exact references: reference/micro_shadowing_aware_exact.h.
// Conventions as occlusion/micro_shadowing.h: n = (0,0,1), v and l unit and pointing away, V ∈ [0,1] in
// projected solid angle, cone cos_t = sqrt(1 − V); V and N·L saturate (NaN → 0), every term is finite in
// [0,1].
#pragma once

#include <microshadow/occlusion/micro_shadowing.h>

#include <algorithm>
#include <cmath>
#include <cstdint>

namespace msh::micro_shadowing {

// Specular-aware term at full vectors: only the facet m = h = normalize(l + v) reflects l into v, so the
// ratio of the cone-limited to the hemisphere-limited specular lobe is one facet's indicator,
//   S = χ⁺(n·h − c) χ⁺(h·l − c),   c = cos_t = sqrt(1 − V)
// (h·v = h·l: the reflected direction passes the facet's cone with the light). The Smith weight G2/G1 and
// D(h) are the same in both and cancel. l or v at or below the horizon, or l = −v: 0. V = 1: 1 (for l, v
// above).
template <class T>
T specular_aware(T V, const Vec3<T>& v, const Vec3<T>& l) {
  const T vis = saturate(V);
  if (!(v.z > T(0)) || !(l.z > T(0))) return T(0);
  if (vis >= T(1)) return T(1);
  const Vec3<T> hs = v + l;
  const T len2 = dot(hs, hs);
  if (!(len2 > T(0))) return T(0);
  const T c = cone_cos_from_visibility(vis);
  // n·h > c ⇔ (n·l + n·v) > c |l + v|;  h·l > c ⇔ (1 + l·v) > c |l + v| (both sides ≥ 0).
  const T len = std::sqrt(len2);
  return (hs.z > c * len && T(1) + dot(l, v) > c * len) ? T(1) : T(0);
}

// Specular-aware term averaged over the relative azimuth φ ∈ [0, π] with the specular lobe's own weight:
//   S̄ = ∫ S(φ) D(h(φ)) dφ / ∫ D(h(φ)) dφ,
// isotropic GGX (α), l = (sin θl cos φ, sin θl sin φ, N·L), v = (sin θv, 0, N·V). This is what a table
// without an azimuth axis must store so that the φ-averaged specular radiance is right. Assumptions: the
// Fresnel factor is constant in φ (it varies with v·h); G2(l, v) and 1/(4 N·L N·V) do not depend on φ for
// isotropic Smith and cancel. Closed form (docs/micro-shadowing-aware.md §2):
//   with u = 1 + l·v = 1 + A + B cos φ (A = N·L N·V, B = sin θl sin θv), n·h² = K/u (K = (N·L + N·V)²/2),
//   D ∝ u²/(u + β)² with β = (α² − 1)K, and S = 1 on the interval x1 < cos φ < x2 where
//   x1 = (2c² − 1 − A)/B (h·l > c) and x2 = (K/c² − 1 − A)/B (n·h > c); the integral of u²/(u + β)² over an
//   interval of φ is Δφ − 2β J1 + β² J2 with J1, J2 the closed-form integrals of (a + b cos φ)^−1, ^−2.
// Domain: V, N·L, N·V ∈ [0, 1] (saturated), α ∈ [1e-4, 1] (clamped). In float the cancellation in the closed
// form grows like 1/α²: use double below α ≈ 0.1 (measured in docs/micro-shadowing-aware.md).
template <class T>
T specular_aware_azimuth_mean(T V, T alpha, T n_dot_l, T n_dot_v) {
  const T vis = saturate(V), cl = saturate(n_dot_l), cv = saturate(n_dot_v);
  if (!(cl > T(0)) || !(cv > T(0))) return T(0);
  if (vis >= T(1)) return T(1);
  if (exact_zero(vis, cl) || vis == T(0)) return T(0);
  const T a2 = sqr(input_domain::clamp_nan(alpha, T(1e-4), T(1), T(1)));
  const T c = cone_cos_from_visibility(vis), c2 = c * c;
  const T A = cl * cv, B = std::sqrt(std::max(T(0), (T(1) - cl * cl) * (T(1) - cv * cv)));
  const T K = T(0.5) * sqr(cl + cv);
  const T x1n = T(2) * c2 - T(1) - A, x2n = K / c2 - T(1) - A;
  if (!(B > T(1e-7))) return (x1n < T(0) && x2n > T(0)) ? T(1) : T(0);  // φ-independent
  const T x1 = x1n / B, x2 = x2n / B;
  // S = 1 on φ ∈ (acos x2, acos x1) ∩ [0, π].
  const T p_lo = x2 >= T(1) ? T(0) : (x2 <= T(-1) ? kPi<T> : std::acos(x2));
  const T p_hi = x1 <= T(-1) ? kPi<T> : (x1 >= T(1) ? T(0) : std::acos(x1));
  if (!(p_hi > p_lo)) return T(0);
  const T beta = (a2 - T(1)) * K;
  const T a = T(1) + A + beta, b = B;  // u + β = a + b cos φ ≥ α² K > 0
  const T s2 = std::max((a - b) * (a + b), std::numeric_limits<T>::min());
  const T s = std::sqrt(s2), ra = std::sqrt(std::max(a - b, T(0))), rb = std::sqrt(a + b);
  auto W = [&](T phi) {  // ∫_0^φ u²/(u + β)² dφ'
    const T j1 = T(2) / s * std::atan2(ra * std::sin(T(0.5) * phi), rb * std::cos(T(0.5) * phi));
    const T j2 = (a * j1 - b * std::sin(phi) / (a + b * std::cos(phi))) / s2;
    return phi - T(2) * beta * j1 + beta * beta * j2;
  };
  const T total = W(kPi<T>);
  if (!(total > T(0))) return T(0);
  return saturate((W(p_hi) - W(p_lo)) / total);
}

// Fraction of a Lambertian facet's reflected flux that leaves through the visibility cone {ω: n·ω > c}:
//   T_c(θm) = (1/π) ∫_{n·ω > c} (m·ω)⁺ dω,   cos θm = n·m,
// the form factor of a spherical cap (half-angle σ = acos c) to a tilted receiver, clipped by its horizon
// (Snyder 1996, "Area Light Sources for Real-Time Graphics"; the same expression as Lagarde & de Rousiers
// 2014, "Moving Frostbite to Physically Based Rendering", sphere-light illuminance with horizon):
//   θm + σ ≤ π/2: cos θm sin²σ;  θm − σ ≥ π/2: 0;  else, with x = cot σ, y = −x cot θm,
//   [ (cos θm acos y − x sin θm √(1 − y²)) sin²σ + atan(sin θm √(1 − y²) / x) ] / π.
// c = 0 gives the hemisphere's (1 + cos θm)/2. Domain: cos θm ∈ [−1, 1], c ∈ [0, 1] (clamped).
template <class T>
T lambert_cap_fraction(T cos_m, T c) {
  const T cm = input_domain::clamp_nan(cos_m, T(-1), T(1)), cc = input_domain::clamp_nan(c, T(0), T(1));
  const T s2 = T(1) - cc * cc;  // sin²σ
  const T sm = std::sqrt(std::max(T(0), T(1) - cm * cm));
  // θm + σ ≤ π/2 ⇔ cos θm ≥ sin σ;  θm − σ ≥ π/2 ⇔ cos θm ≤ −sin σ.
  const T ss = std::sqrt(s2);
  if (cm >= ss) return cm * s2;
  if (cm <= -ss) return T(0);
  const T y =
      input_domain::clamp_nan(-cc * cm / std::max(ss * sm, std::numeric_limits<T>::min()), T(-1), T(1));
  const T r = sm * std::sqrt(std::max(T(0), T(1) - y * y));
  const T e = (cm * std::acos(y) - (cc / std::max(ss, std::numeric_limits<T>::min())) * r) * s2 +
              std::atan2(r * ss, cc);  // atan(r / x) with x = c / sin σ
  return std::clamp(e / kPi<T>, T(0), T(1));
}

// The two ways the diffuse lobe's micro-BRDF enters (docs/micro-shadowing-aware.md §3):
//   Reciprocal: radiance toward v of Lambertian facets; facet weight (m·l)⁺, and the cone test of the
//     generic term applied to both directions the facet exchanges: n·m > c, m·l > c and m·v > c.
//   Flux: the facet's whole reflected flux, weight (m·l)⁺ T_c(n·m) in the cone and (m·l)⁺ T_0(n·m) in the
//     hemisphere (the fraction leaving through the cone; Lambertian cap fraction above); n·m > c, m·l > c.
enum class DiffuseAwareForm { Reciprocal, Flux };

// The facet micro-BRDF of the reciprocal form, as a weight π f_facet(l, v about m) that multiplies (m·l)⁺
// in the cone and in the hemisphere alike: LambertFacet (1) here; the Oren–Nayar facets of
// docs/micro-shadowing-aware.md §3.1 are reference/micro_shadowing_aware_exact.h's OrenNayarFacet (the
// occlusion area does not depend on bsdf/). Any callable w(m, l, v) ≥ 0 works.
struct LambertFacet {
  template <class T>
  T operator()(const Vec3<T>&, const Vec3<T>&, const Vec3<T>&) const {
    return T(1);
  }
};

// One VNDF sample of the diffuse-aware term: m from the Dupuy–Benyoub 2023 sampler of v; returns the cone
// and hemisphere weights (the Smith G2/G1 depends on (v, l) only and cancels; it is left out). facet: the
// facet micro-BRDF's weight in the Reciprocal form (LambertFacet above); the Flux form keeps Lambert facets
// (its cap fraction is the Lambertian one).
template <class T, class FacetWeight = LambertFacet>
GenericSample<T> diffuse_aware_sample(T cos_t, const GGX<T>& ggx, const Vec3<T>& v, const Vec3<T>& l,
                                      Vec2<T> u, DiffuseAwareForm form, const FacetWeight& facet = {}) {
  const Vec3<T> m = ggx.Sample_wm(v, u);
  const T c = input_domain::clamp_nan(cos_t, T(0), T(1), T(1));
  const T ml = dot(m, l), nm = m.z;
  GenericSample<T> s{T(0), T(0), T(1)};
  if (!(ml > T(0)) || !(nm > T(0))) return s;
  const bool in_cone = nm > c && ml > c;
  if (form == DiffuseAwareForm::Reciprocal) {
    s.hemisphere = ml * facet(m, l, v);
    s.cone = (in_cone && dot(m, v) > c) ? s.hemisphere : T(0);
  } else {
    s.hemisphere = ml * T(0.5) * (T(1) + nm);
    s.cone = in_cone ? ml * lambert_cap_fraction(nm, c) : T(0);
  }
  return s;
}

// The diffuse-aware term estimated with n Owen-scrambled Sobol points (seed 0: plain Sobol): Σcone / Σhemi.
// Exact 0 at the generic term's early-out 2V + N·L < 1 (the diffuse-aware cone region is a subset of the
// generic one); V = 1 → 1. facet: as diffuse_aware_sample (LambertFacet: Lambert facets).
template <class T, class FacetWeight = LambertFacet>
T diffuse_aware_estimate(T V, const GGX<T>& ggx, const Vec3<T>& v, const Vec3<T>& l, int n,
                         DiffuseAwareForm form, uint32_t seed = 1, const FacetWeight& facet = {}) {
  const T vis = saturate(V);
  if (exact_zero(vis, l.z) || vis == T(0)) return T(0);
  if (vis >= T(1)) return T(1);
  const T c = cone_cos_from_visibility(vis);
  T cone = 0, hemi = 0;
  for (int i = 0; i < n; ++i) {
    const GenericSample<T> s =
        diffuse_aware_sample(c, ggx, v, l, sobol_2d<T>(uint32_t(i), seed), form, facet);
    cone += s.cone;
    hemi += s.hemisphere;
  }
  return hemi > T(0) ? std::min(T(1), cone / hemi) : T(0);
}

}  // namespace msh::micro_shadowing
