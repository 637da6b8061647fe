// Micro-shadowing terms: how much of a light survives the micro-occlusion cone of a texel. Engine-facing,
// header-only: the closed-form terms, the early-out, the per-microfacet function of the generic VNDF-based
// term and its Sobol estimator. The exact (converged, double-precision) reference evaluation of the generic
// term lives in reference/micro_shadowing_exact.h.
// Conventions (docs/theory.md §1, §3): local shading frame n = (0,0,1), tangent = x; v, l unit vectors
// pointing away from the surface; visibility V ∈ [0,1] is visibility in projected solid angle, so the
// visibility cone has cos_t = sqrt(1 − V) (Nusselt analog).
//
// Input handling, shared by every function here: V and N·L are clamped to [0,1] and NaN maps to 0
// (saturate semantics), so every term returns a finite value in [0,1] for any input, including ±Inf and NaN.
#pragma once

#include <microshadow/math/sampling.h>
#include <microshadow/math/vec.h>
#include <microshadow/microfacet/ggx.h>
#include <microshadow/microfacet/smith.h>
#include <microshadow/occlusion/micro_shadowing_early_out.h>

#include <algorithm>
#include <array>
#include <cmath>
#include <cstdint>
#include <utility>

namespace msh::micro_shadowing {

// Form of the Smith masking-shadowing function used for the per-sample weight G2/G1 (Zurita 2026b).
using msh::G2Form;  // microfacet/smith.h: HeightCorrelated, Uncorrelated (= Separable)

namespace input_domain {
// x clamped to [lo, hi]; NaN maps to `nan_value`.
template <class T>
T clamp_nan(T x, T lo, T hi, T nan_value = T(0)) {
  if (std::isnan(x)) return nan_value;
  return x < lo ? lo : (x > hi ? hi : x);
}
}  // namespace input_domain

// Cosine of the visibility cone's half-angle, sqrt(1 − V) (Nusselt analog, docs/theory.md §1). V ∈ [0,1].
template <class T>
T cone_cos_from_visibility(T V) {
  return std::sqrt(T(1) - saturate(V));
}

// Reference term (Zurita 2026b): step(cos_t, N·L), lit iff N·L > cos_t (strict χ⁺, as in Zurita 2026b).
template <class T>
T reference_step(T V, T n_dot_l) {
  return saturate(n_dot_l) > cone_cos_from_visibility(V) ? T(1) : T(0);
}

// Brinck & Maximov 2016 (Uncharted 4), AO = V: saturate(N·L + 2V² − 1).
template <class T>
T brinck_maximov_2016(T V, T n_dot_l) {
  const T v = saturate(V);
  return saturate(saturate(n_dot_l) + T(2) * v * v - T(1));
}

// Chan 2018 (CoD WWII; Filament's computeMicroShadowing): saturate(N·L / sqrt(1 − V))².
// At V = 1 the cone is the hemisphere: 1 for N·L > 0, else 0 (the limit, without a 0/0).
template <class T>
T chan_2018(T V, T n_dot_l) {
  const T nl = saturate(n_dot_l);
  const T c = cone_cos_from_visibility(V);
  if (!(c > T(0))) return nl > T(0) ? T(1) : T(0);
  const T x = saturate(nl / c);
  return x * x;
}

// Part 1 "analytical alternative" (Zurita 2026, as reported by third-party copies, docs/theory.md §3):
// V ∈ {0, 1} returns V; else pow(saturate(N·L / sqrt(1 − V⁵)), 0.75 / V).
template <class T>
T part1_analytic(T V, T n_dot_l) {
  const T v = saturate(V);
  if (v == T(0) || v == T(1)) return v;
  const T v2 = v * v;
  const T cp = std::sqrt(T(1) - v2 * v2 * v);
  if (!(cp > T(0))) return saturate(n_dot_l) > T(0) ? T(1) : T(0);  // V⁵ rounded to 1
  return std::pow(saturate(saturate(n_dot_l) / cp), T(0.75) / v);
}

// exact_zero(V, N·L), the exact early-out 2V + N·L < 1: occlusion/micro_shadowing_early_out.h.

template <class T>
struct GenericSample {
  T cone, hemisphere, weight;
};

// G2(v,l,m)/G1(v,m) for the Smith profile given m·l > 0 and m·v > 0 (Zurita 2026b, table of weights):
// uncorrelated G1(l), height-correlated G1(l)/(G1(l) + G1(v) − G1(l)G1(v)). Anisotropy via the projected
// roughness, which is what the distributions' G1 does. Depends on (v, l) only. Any Smith NDF (GGX, Beckmann).
template <class T, SmithDistribution Dist>
T smith_g2_over_g1(const Dist& dist, const Vec3<T>& v, const Vec3<T>& l, G2Form form) {
  return smith_g2_over_g1o(dist.G1(v), dist.G1(l), form);
}

// G2(v,l,m)/G1(v,m) for any microsurface profile, given m·l > 0 (Zurita 2026b). Smith: smith_g2_over_g1 (no
// m dependence). A profile whose masking depends on m (the V-cavity, microfacet/vcavity.h): its own
// G2(v, l, m) (Cook–Torrance min) for G2Form::HeightCorrelated — the correlated form of that profile — and
// G1(v, m) G1(l, m) for G2Form::Uncorrelated, both divided by G1(v, m); 0 where G1(v, m) = 0.
template <class T, class Dist>
T profile_g2_over_g1(const Dist& dist, const Vec3<T>& v, const Vec3<T>& l, const Vec3<T>& m, G2Form form) {
  if constexpr (SmithDistribution<Dist>) {
    (void)m;
    return smith_g2_over_g1(dist, v, l, form);
  } else {
    const T gv = dist.G1(v, m);
    if (!(gv > T(0))) return T(0);
    const T g2 = form == G2Form::Uncorrelated ? gv * dist.G1(l, m) : dist.G2(v, l, m);
    return g2 / gv;
  }
}

// The per-microfacet function GenericM_m (Zurita 2026b, MicroShadowingTermPZGenericVNDFBased) at a given
// visible normal m of v, weight G2/G1 in the chosen form. cos_t ∈ [0,1].
template <class T, class Dist>
GenericSample<T> generic_vndf_at(T cos_t, const Dist& dist, const Vec3<T>& v, const Vec3<T>& l,
                                 const Vec3<T>& m, G2Form form) {
  const T n_dot_m = saturate(m.z);
  const T m_dot_l = saturate(dot(m, l));
  const T c = input_domain::clamp_nan(cos_t, T(0), T(1), T(1));
  GenericSample<T> s;
  s.weight = m_dot_l > T(0) ? profile_g2_over_g1(dist, v, l, m, form) : T(0);
  s.hemisphere = (n_dot_m > T(0) && m_dot_l > T(0)) ? s.weight : T(0);
  s.cone = (n_dot_m - c > T(0) && m_dot_l - c > T(0)) ? s.weight : T(0);
  return s;
}

// GenericM_m with m from the distribution's VNDF sampler of v (GGX: Dupuy–Benyoub 2023; Beckmann: Heitz &
// d'Eon 2014).
template <class T, class Dist>
GenericSample<T> generic_vndf_sample(T cos_t, const Dist& dist, const Vec3<T>& v, const Vec3<T>& l, Vec2<T> u,
                                     G2Form form) {
  return generic_vndf_at(cos_t, dist, v, l, dist.Sample_wm(v, u), form);
}

// Visible normal number i of v for the estimator: Sample_wm(v, u) with the 2D Owen-scrambled Sobol point, or,
// for a sampler that takes a third uniform (the V-cavity's groove choice), Sobol dimension 2 as that number.
template <class T, class Dist>
Vec3<T> estimator_visible_normal(const Dist& dist, const Vec3<T>& v, uint32_t i, uint32_t seed) {
  const Vec2<T> u = sobol_2d<T>(i, seed);
  if constexpr (requires { dist.Sample_wm(v, u, T(0)); }) {
    const T u3 = seed == 0 ? u32_to_unit<T>(sobol_u32(i, 2)) : sobol_scrambled<T>(i, 2, seed);
    return dist.Sample_wm(v, u, u3);
  } else {
    return dist.Sample_wm(v, u);
  }
}

// GenericM_g (Zurita 2026b) estimated with n Owen-scrambled Sobol samples (seed 0: plain Sobol), Σcone /
// Σhemisphere; 0 when no sample reaches the hemisphere or when exact_zero holds (exact, no samples taken).
// Dist: GGX, Beckmann (Smith: the weight cancels) or VCavity (the weight depends on m: it does not cancel).
template <class T, class Dist>
T generic_vndf_estimate(T V, const Dist& dist, const Vec3<T>& v, const Vec3<T>& l, int n, G2Form form,
                        uint32_t seed = 1) {
  const T vis = saturate(V);
  if (exact_zero(vis, l.z)) return T(0);
  const T c = cone_cos_from_visibility(vis);
  T cone = 0, hemi = 0;
  for (int i = 0; i < n; ++i) {
    const Vec3<T> m = estimator_visible_normal<T>(dist, v, uint32_t(i), seed);
    const GenericSample<T> s = generic_vndf_at(c, dist, v, l, m, form);
    cone += s.cone;
    hemi += s.hemisphere;
  }
  return hemi > T(0) ? std::min(T(1), cone / hemi) : T(0);
}

}  // namespace msh::micro_shadowing
