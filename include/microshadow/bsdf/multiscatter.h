// Multiple-bounce specular and the directional-albedo tables it needs.
//
// - GGX single-scattering albedo with F = 1, E(μ, r) = R_sF1 (RTR4 9.8/9.57), and its Fresnel-weighted twin
//   E_Fc(μ, r) = ∫ (1 − v·h)⁵ f_sF1 (n·l) dl: together they are the split-sum "DFG" table (Karis 2013) in the
//   Filament multiscatter layout, DFG = (E_Fc, E): E_Schlick(F0) = mix(DFG.x, DFG.y, F0) = F0 E + (1 − F0)
//   E_Fc. Karis' (scale, bias) = (E − E_Fc, E_Fc). Height-correlated Smith G2 (9.31).
// - Axes (docs/theory.md §1): μ = N·V and perceptual roughness r (α = r²), texel i of n holds i/(n − 1).
// - Imageworks / Kulla & Conty 2017 multiple-bounce lobe (RTR4 9.56–9.57) from those tables.
// Shipped 32×32 tables (tables_data.h, baked by `microshadow bake brdf-shipped`) make the runtime file-free.
#pragma once

#include <microshadow/bsdf/fresnel.h>
#include <microshadow/bsdf/qmc.h>
#include <microshadow/bsdf/specular.h>
#include <microshadow/bsdf/tables_data.h>
#include <microshadow/math/color.h>
#include <microshadow/microfacet/ggx.h>

namespace msh::bsdf {

// (E_Fc, E) at (μ, r) by QMC over n visible normals (Owen-scrambled Sobol, fixed seed): the estimator weight
// of VNDF sampling is G2/G1(v), finite at μ = 0. r = 0 uses the exact mirror limit ((1 − μ)⁵, 1) (Filament's
// DFG convention, docs/theory.md §2).
template <class T>
Vec2<T> ggx_dfg_reference(T mu, T r, uint32_t n, uint32_t seed = kAlbedoSeed) {
  mu = saturate(mu);
  r = saturate(r);
  if (r == T(0)) return {schlick_weight(mu), T(1)};
  const GGX<T> ggx(roughness_to_alpha(r));
  const Vec3<T> wo(safe_sqrt(T(1) - mu * mu), T(0), mu);
  T e = 0, efc = 0;
  for (uint32_t i = 0; i < n; ++i) {
    const Vec3<T> m = ggx.Sample_wm(wo, sobol_2d<T>(i, seed));
    const T c = dot(wo, m);
    if (!(c > T(0))) continue;
    const Vec3<T> wi = reflect(wo, m);
    if (!(wi.z > T(0))) continue;
    const T w = smith_g2_over_g1o(ggx.G1(wo), ggx.G1(wi), G2Form::HeightCorrelated);
    e += w;
    efc += w * schlick_weight(c);
  }
  return {efc / T(n), e / T(n)};
}

// ---- Lookups in the shipped tables (bilinear; clamps the arguments to [0,1]).

namespace table_lerp {
template <class T>
T lerp_table_1d(const float* t, int n, T x) {
  const T fx = saturate(x) * T(n - 1);
  const int i = std::min(int(fx), n - 2);
  const T a = fx - T(i);
  return (T(1) - a) * T(t[i]) + a * T(t[i + 1]);
}
// t[j * n + i], i along μ (x), j along r (y).
template <class T>
T lerp_table_2d(const float* t, int n, T mu, T r) {
  const T fx = saturate(mu) * T(n - 1), fy = saturate(r) * T(n - 1);
  const int i = std::min(int(fx), n - 2), j = std::min(int(fy), n - 2);
  const T a = fx - T(i), b = fy - T(j);
  const T v0 = (T(1) - a) * T(t[j * n + i]) + a * T(t[j * n + i + 1]);
  const T v1 = (T(1) - a) * T(t[(j + 1) * n + i]) + a * T(t[(j + 1) * n + i + 1]);
  return (T(1) - b) * v0 + b * v1;
}
}  // namespace table_lerp

// R_sF1 = E(μ, r): GGX directional albedo with F = 1 (shipped table).
template <class T>
T ggx_E(T mu, T r) {
  return table_lerp::lerp_table_2d(shipped::kGgxE, shipped::kGgxTableSize, mu, r);
}
// E_Fc(μ, r) (shipped table).
template <class T>
T ggx_E_fc(T mu, T r) {
  return table_lerp::lerp_table_2d(shipped::kGgxEFc, shipped::kGgxTableSize, mu, r);
}
// Cosine-weighted averages over μ: Ē(r) (RTR4 9.57) and Ē_Fc(r).
template <class T>
T ggx_E_avg(T r) {
  return table_lerp::lerp_table_1d(shipped::kGgxEAvg, shipped::kGgxTableSize, r);
}
template <class T>
T ggx_E_fc_avg(T r) {
  return table_lerp::lerp_table_1d(shipped::kGgxEFcAvg, shipped::kGgxTableSize, r);
}
// Single-scattering GGX albedo with Schlick Fresnel, R_spec = F0 E + (1 − F0) E_Fc (Karis 2013 split sum).
template <class T, class C>
C ggx_albedo_schlick(const C& f0, T mu, T r) {
  const T e = ggx_E(mu, r), efc = ggx_E_fc(mu, r);
  return f0 * (e - efc) + C(efc);
}
template <class T, class C>
C ggx_albedo_schlick_avg(const C& f0, T r) {
  const T e = ggx_E_avg(r), efc = ggx_E_fc_avg(r);
  return f0 * (e - efc) + C(efc);
}

// ---- Kulla & Conty 2017 multiple-bounce lobe (RTR4 9.56).

// F = 1 lobe: (1 − E(l))(1 − E(v)) / (π (1 − Ē)); its albedo is exactly 1 − E(v), so single + multiple = 1.
// Ē → 1 (smooth surface) is guarded: the numerator vanishes faster.
template <class T>
T ms_lobe_f1(T e_l, T e_v, T e_avg) {
  return (T(1) - e_l) * (T(1) - e_v) / (kPi<T> * std::max(T(1) - e_avg, T(1e-6)));
}
// Fresnel factor of the multiple-bounce lobe: the energy that survives k ≥ 2 bounces, Σ F̄ᵏ Ē (1 − Ē)^(k−1),
// relative to the F = 1 case: F̄² Ē / (1 − F̄ (1 − Ē)) (Kulla & Conty 2017). RTR4 9.56 prints F̄ Ē in the
// numerator; we follow the source's geometric-series derivation (documented in docs/brdf.md).
template <class T, class C>
C ms_fresnel_factor(const C& f_avg, T e_avg) {
  return f_avg * f_avg * e_avg / (C(T(1)) - f_avg * (T(1) - e_avg));
}
// Full multiple-bounce lobe f_ms(l, v) for GGX at perceptual roughness r with average Fresnel F̄, from the
// shipped tables. Anisotropic GGX: pass an intermediate roughness (Imageworks; we use r of 9.55, whose α is
// the mean of αx and αy).
template <class T, class C>
C ggx_multiscatter(const C& f_avg, T r, const Vec3<T>& l, const Vec3<T>& v) {
  if (!(l.z > T(0)) || !(v.z > T(0))) return C(T(0));
  const T e_avg = ggx_E_avg(r);
  return ms_fresnel_factor(f_avg, e_avg) * ms_lobe_f1(ggx_E(l.z, r), ggx_E(v.z, r), e_avg);
}
// Directional albedo of ggx_multiscatter at n·v = μ (closed form: F_ms (1 − E(μ)) (1 − Ē)/(1 − Ē) with the
// table's own Ē, up to the bilinear interpolation error).
template <class T, class C>
C ggx_multiscatter_albedo(const C& f_avg, T r, T mu) {
  const T e_avg = ggx_E_avg(r);
  return ms_fresnel_factor(f_avg, e_avg) * (T(1) - ggx_E(mu, r));
}

// Engine-style energy compensation from the multiscatter DFG (Fdez-Agüera 2019; Filament): scale the
// single-scattering specular by 1 + F0 (1/E − 1), E = DFG.y.
template <class T, class C>
C dfg_energy_compensation(const C& f0, T e) {
  return C(T(1)) + f0 * (T(1) / std::max(e, T(1e-4)) - T(1));
}

}  // namespace msh::bsdf
