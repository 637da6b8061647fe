// Directional micro-occlusion that filters linearly (docs/directional-occlusion.md). Header-only, templated
// on the scalar (works in float), no I/O.
//
// Conventions: tangent space of the normal map (render/texture_gen.h normal_map_from_height): x = +u
// (columns), y = +v (rows, top to bottom), z = the flat surface normal (the height map's +z, not the
// texel's own normal). Azimuth φ from +x towards +y, elevation e above the flat tangent plane. Every stored
// channel is linear in the fine texel's data, so the box mean of a channel (a mip level) is exactly the
// channel of the coarse texel; every nonlinear step happens after the fetch.
//
// Shipped representation ("poly2-lsq", the measured winner): per fine texel x, the diffuse transport
// f_x(l) = lit(x, l) · (n_x · l)⁺ (lit: the exact horizon along l's azimuth is below l; n_x: the fine
// normal) is fitted over the upper hemisphere by weighted least squares with the 9 polynomials of degree
// ≤ 2 (the span of the real spherical harmonics of bands 0–2 restricted to the hemisphere),
//   b(l) = (1, x, y, z, x z, y z, x² − y², x y, z²),
// with a weight that counts relative error, so grazing light is fitted. (SSBump, Green 2007 "Efficient
// self-shadowed radiosity normal mapping", stores a visibility-weighted projection on 3 directions; this is
// the same idea with 9 functions and the cast shadows of the exact horizon.) The fit is a fixed linear map
// of f_x, so the coefficients' box mean over a footprint is the fit of the footprint's mean transport: the
// mip chain is right by construction, at every scale. At run time T̃(l) = max(0, Σ_i c_i b_i(l)) is the
// mean over the texel's footprint of lit · N·L: the diffuse radiance is albedo/π · E · T̃(l), in place of
// (n_coarse · l)⁺ · micro-shadowing (directional_term gives the factor for engines that keep N·L).
#pragma once

#include <microshadow/math/vec.h>

#include <algorithm>
#include <cmath>

namespace msh::directional {

// ---- Shipped: degree-2 least-squares transport (9 channels) ----

inline constexpr int kPoly2Terms = 9;
inline constexpr int kDirectionalChannels = kPoly2Terms;

// b(l) = (1, x, y, z, x z, y z, x² − y², x y, z²): the channel order.
template <class T>
void poly2_basis(Vec3<T> l, T out[kPoly2Terms]) {
  out[0] = T(1), out[1] = l.x, out[2] = l.y, out[3] = l.z;
  out[4] = l.x * l.z, out[5] = l.y * l.z, out[6] = l.x * l.x - l.y * l.y, out[7] = l.x * l.y,
  out[8] = l.z * l.z;
}

// The fit that defines the channels (render/directional_bake.h bakes exactly this): directions at the bake's
// N_φ azimuths (32 by default; up to 64, grid steps within 0.5° of 2π(a + ½)/N_φ, each weighted by its share
// of the circle: render::directional_bake_azimuths) and elevations
// e_j = (j + ½)/kFitElevations · π/2, each with weight cos e_j · fit_weight(sin e_j);
// c = argmin Σ w (Σ_i c_i b_i(l) − f(l))².
inline constexpr int kFitElevations = 16;
inline constexpr double kFitEpsilon = 0.03;
template <class T>
T fit_weight(T sin_e) {
  const T d = T(kFitEpsilon) + sin_e;
  return T(1) / (d * d);
}

// The mean diffuse transport over the texel's footprint, lit · (n_fine · l)⁺, of a directional light l
// (unit, tangent space), from the 9 channels (fetched from the box-filtered mips). 0 below the tangent
// plane; ≥ 0.
template <class T>
T directional_transport(const T* channels, Vec3<T> l_local) {
  if (!(l_local.z > T(0))) return T(0);
  T b[kPoly2Terms];
  poly2_basis(l_local, b);
  T s = 0;
  for (int i = 0; i < kPoly2Terms; ++i) s += channels[i] * b[i];
  return std::max(s, T(0));
}

// The same as a factor on the engine's (n_coarse · l)⁺: T̃ / (n_c · l), 0 where n_c · l ≤ 1e-4. Not clamped
// to 1: near the coarse terminator lit facets can exceed the coarse cosine.
template <class T>
T directional_term(const T* channels, Vec3<T> l_local, Vec3<T> n_coarse_local) {
  const T nl = dot(n_coarse_local, l_local);
  if (!(nl > T(1e-4))) return T(0);
  return directional_transport(channels, l_local) / nl;
}

// The view correction (docs/directional-occlusion.md, "The view–light correlation floor"; the renderer's
// `directional-view` method). A camera along v sees each facet with its projected area (n · v)⁺/n_z; without
// masking, the mean it averages is E[f (n · v)/(n_z v_z)] = T(l) + (G_x(l) v_x + G_y(l) v_y)/v_z, G = E[f
// n_x/n_z], E[f n_y/n_z] (render::bake_directional_slope_channels: 12 channels, x then y, each the same
// weighted least-squares fit as T with the first kSlopeTerms = 6 functions of b, (1, x, y, z, xz, yz): the
// measured choice, as close as all 9 and 6 channels fewer). v: unit, tangent space, toward the camera; v_z
// is taken ≥ kMinViewZ = 0.5: beyond 60° off the normal masking toward the camera, which this leaves out,
// dominates and the linear correction overshoots (the study's 1024² rock, gravel, brick at 85°: diffuse mean
// |bias − 1| 0.95 / 0.70 at k = 4 / 16 with 0.1, 0.12 / 0.12 with 0.5; 60° and nearer unchanged; the
// grazing-view section of docs/study.md). 0 for l.z ≤ 0; ≥ 0.
inline constexpr int kSlopeTerms = 6;
inline constexpr int kSlopeChannels = 2 * kSlopeTerms;
inline constexpr double kMinViewZ = 0.5;
// T, G_x and G_y at l from the 9 and the 12 channels (each sum in channel order; both view forms read them).
template <class T>
void view_sums(const T* channels, const T* slope_channels, Vec3<T> l_local, T& t, T& gx, T& gy) {
  T b[kPoly2Terms];
  poly2_basis(l_local, b);
  t = 0, gx = 0, gy = 0;
  for (int i = 0; i < kPoly2Terms; ++i) t += channels[i] * b[i];
  for (int i = 0; i < kSlopeTerms; ++i)
    gx += slope_channels[i] * b[i], gy += slope_channels[kSlopeTerms + i] * b[i];
}
template <class T>
T directional_view_transport(const T* channels, const T* slope_channels, Vec3<T> l_local, Vec3<T> v_local) {
  if (!(l_local.z > T(0))) return T(0);
  T t, gx, gy;
  view_sums(channels, slope_channels, l_local, t, gx, gy);
  const T vz = std::max(v_local.z, T(kMinViewZ));
  return std::max(t + (gx * v_local.x + gy * v_local.y) / vz, T(0));
}

// The view correction with masking toward the camera, Smith-normalised: measured and not shipped (rendered,
// it is worse than the v_z clamp at 75° and 85°: docs/study.md, "Grazing views"). Without masking, a camera
// along v weighs each facet by m = (n · v)/n_z, whose footprint mean is v_z; the unmasked transport is E[f
// m]/v_z = T + g/v_z, g = G_x v_x + G_y v_y. Smith's masking (Smith 1967, "Geometrical shadowing of a random
// rough surface"; Heitz 2014, "Understanding the masking-shadowing function in microfacet-based BRDFs", eq.
// 72–73) replaces the mean of m by that of m⁺: with slopes of covariance Σ, m = v_z + s Z along the view
// azimuth, s² = v_hᵀ Σ v_h (v_h = (v_x, v_y)), Z a unit normal, so the mean visible projected area is R(v_z,
// s), R(m, s) = E[(m + s Z)⁺] = m Φ(m/s) + s φ(m/s). The lit part's mean projected area is modelled the same
// way, T v_z + g spread by T⁺ s (the lit facets' share of the area): transport = R(T v_z + g, T⁺ s) / R(v_z,
// s). s = 0 (a flat material) gives max(0, T + g/v_z), the form without the v_z clamp; it stays finite at v_z
// = 0 when s > 0 (R(0, s) = s φ(0)). Σ = E[n_h n_hᵀ]/E[n_z²] over the material's fine normals (3 numbers:
// Σ_xx, Σ_xy, Σ_yy; the texels' slope channels cannot give it), a per-material constant at every scale. A v_z
// below 1e-4 is taken as 1e-4 (normal-mapped shading can put the camera under the tangent plane). 0 for l.z ≤
// 0; ≥ 0; finite for finite channels.
template <class T>
T ramp_mean(T m, T s) {
  if (!(s > T(1e-12))) return std::max(m, T(0));
  const T x = m / s;
  const T pdf = T(0.3989422804014327) * std::exp(T(-0.5) * x * x);
  const T cdf = T(0.5) * std::erfc(-x * T(0.7071067811865476));
  return m * cdf + s * pdf;
}
template <class T>
T directional_view_masked_transport(const T* channels, const T* slope_channels, Vec3<T> l_local,
                                    Vec3<T> v_local, const T slope_cov[3]) {
  if (!(l_local.z > T(0))) return T(0);
  T t, gx, gy;
  view_sums(channels, slope_channels, l_local, t, gx, gy);
  const T vz = std::max(v_local.z, T(1e-4));
  const T s2 = slope_cov[0] * v_local.x * v_local.x + T(2) * slope_cov[1] * v_local.x * v_local.y +
               slope_cov[2] * v_local.y * v_local.y;
  const T s = std::sqrt(std::max(s2, T(0)));
  const T seen = ramp_mean(vz, s);
  return std::max(ramp_mean(t * vz + gx * v_local.x + gy * v_local.y, std::max(t, T(0)) * s) / seen, T(0));
}

// The view-corrected data as one texel: the 9 transport channels, then the 12 slope channels (21;
// render::bake_directional_view_channels).
inline constexpr int kViewChannels = kDirectionalChannels + kSlopeChannels;

// directional_view_transport from the 21 channels as a factor on the engine's (n_coarse · l)⁺, as
// directional_term: 0 where n_c · l ≤ 1e-4; not clamped to 1.
template <class T>
T directional_view_term(const T* channels21, Vec3<T> l_local, Vec3<T> v_local, Vec3<T> n_coarse_local) {
  const T nl = dot(n_coarse_local, l_local);
  if (!(nl > T(1e-4))) return T(0);
  return directional_view_transport(channels21, channels21 + kDirectionalChannels, l_local, v_local) / nl;
}
// The masked form as the same factor (the `directional-view-masked` method).
template <class T>
T directional_view_masked_term(const T* channels21, Vec3<T> l_local, Vec3<T> v_local, Vec3<T> n_coarse_local,
                               const T slope_cov[3]) {
  const T nl = dot(n_coarse_local, l_local);
  if (!(nl > T(1e-4))) return T(0);
  return directional_view_masked_transport(channels21, channels21 + kDirectionalChannels, l_local, v_local,
                                           slope_cov) /
         nl;
}

// Compact forms (render/directional_codec.h, docs/directional-occlusion.md "Compact forms"): K UNORM
// coefficients u_k per texel (fetched and filtered like any texture) decode to the C channels through the
// material's folded code, channel_i = fm_i + Σ_k fb[i K + k] u_k, fm_i = mean_i + Σ_k B_ik lo_k, fb_ik = B_ik
// (hi_k − lo_k) (the code's affine decode of each coefficient folded into its basis); then the channels are
// evaluated as above. Linear, so it commutes with the box mean of the coefficients.
template <class T>
void decode_folded_code(const T* u, int K, const T* folded_mean, const T* folded_basis, int C, T* channels) {
  for (int i = 0; i < C; ++i) {
    T s = folded_mean[i];
    for (int k = 0; k < K; ++k) s += folded_basis[i * K + k] * u[k];
    channels[i] = s;
  }
}

// 8-bit storage: channel i as UNORM between a per-material range [lo_i, hi_i] (the fine level's min and max,
// kept with the material; every mip level uses the same range).
template <class T>
T decode_unorm8(T unorm, T lo, T hi) {
  return lo + (hi - lo) * unorm;
}

// ---- Alternatives measured against it (docs/directional-occlusion.md) ----
//
// Horizon moments ("hm"): per fine texel x and azimuth φ, the signed horizon sine s_x(φ) = sin h_x(φ), where
// h is the exact horizon elevation (Max 1988 "Horizon mapping") and, where nothing rises above the tangent
// plane, the (negative) elevation of the facet itself along φ. A light at (φ, e) reaches x iff sin e >
// s_x(φ). Stored: the second-order Fourier series in φ of s and of s² (Sloan & Cohen 2000 "Interactive
// horizon mapping" store the horizon per azimuth; the Fourier form is the usual compact variant), 10
// channels: c[0..4] = Fourier(s): a0, a1 (cos φ), b1 (sin φ), a2 (cos 2φ), b2 (sin 2φ); c[5..9] =
// Fourier(s²). Their box means are the footprint's first two moments of s per azimuth; the coarse texel
// models s as uniform with them. hm_transport takes E[sin(e − h)⁺] (exact for texels not shadowed by
// distant relief, in the plane of the light), hm_lit_cosine P[lit] · (n_coarse · l)⁺.

inline constexpr int kHorizonOrder = 2;      // Fourier order in azimuth
inline constexpr int kHorizonTerms = 5;      // 1, cos φ, sin φ, cos 2φ, sin 2φ
inline constexpr int kHorizonChannels = 10;  // Fourier(s), Fourier(s²)

// Fourier basis (1, cos φ, sin φ, cos 2φ, sin 2φ) at the azimuth of the horizontal direction (c, s)
// (need not be unit; a zero vector, a light at the zenith, gives φ = 0: every term is then independent of φ
// up to the data at φ = 0, where it does not matter since sin e = 1).
template <class T>
void fourier_basis(T c, T s, T out[kHorizonTerms]) {
  const T r2 = c * c + s * s;
  if (!(r2 > T(0))) {
    c = T(1), s = T(0);
  } else {
    const T inv = T(1) / std::sqrt(r2);
    c *= inv, s *= inv;
  }
  out[0] = T(1), out[1] = c, out[2] = s, out[3] = c * c - s * s, out[4] = T(2) * c * s;
}

// Weights that turn N uniformly spaced samples g(φ_k) into Fourier coefficients: coefficient m =
// Σ_k w_m(φ_k) g(φ_k) with w = (1, 2 cos φ, 2 sin φ, 2 cos 2φ, 2 sin 2φ) / N.
template <class T>
void fourier_analysis_weights(T c, T s, int n_samples, T out[kHorizonTerms]) {
  fourier_basis(c, s, out);
  const T inv = T(1) / T(n_samples);
  out[0] *= inv;
  for (int m = 1; m < kHorizonTerms; ++m) out[m] *= T(2) * inv;
}

// Signed horizon sine of one texel along one azimuth from the exact horizon tan H ≥ 0 (0 = nothing above the
// tangent plane) and the slope of the texel's facet along that azimuth, dz/ds = −(n_x cos φ + n_y sin φ)/n_z.
template <class T>
T signed_horizon_sine(T tan_h, T facet_slope) {
  const T t = tan_h > T(0) ? tan_h : std::min(facet_slope, T(0));
  return t / std::sqrt(T(1) + t * t);
}

namespace detail {
// ∫ (sin e √(1 − s²) − cos e s) ds, an antiderivative in s.
template <class T>
T horizon_cosine_antiderivative(T s, T sin_e, T cos_e) {
  s = std::clamp(s, T(-1), T(1));
  return T(0.5) * (sin_e * (s * std::sqrt(std::max(T(1) - s * s, T(0))) + std::asin(s)) - cos_e * s * s);
}
}  // namespace detail

// E[(sin e cos h − cos e sin h)⁺] = E[sin(e − h)⁺] for sin h uniform with the given mean and variance
// (clamped to [−1, 1]); sin_e, cos_e of the light's elevation (cos_e ≥ 0).
template <class T>
T horizon_transport(T mean, T variance, T sin_e, T cos_e) {
  const T half = std::sqrt(T(3) * std::max(variance, T(0)));  // uniform: half-width √3 σ
  const T a = std::max(mean - half, T(-1)), b = std::min(mean + half, T(1));
  if (!(b - a > T(2e-3))) {  // (nearly) one horizon: the point value
    const T s = std::clamp(mean, T(-1), T(1));
    return std::max(sin_e * std::sqrt(T(1) - s * s) - cos_e * s, T(0));
  }
  if (!(sin_e > a)) return T(0);
  const T top = std::min(b, sin_e);
  const T g = detail::horizon_cosine_antiderivative(top, sin_e, cos_e) -
              detail::horizon_cosine_antiderivative(a, sin_e, cos_e);
  return std::max(g / (b - a), T(0));
}

// P[sin h < sin e] for sin h uniform with the given mean and variance: the lit fraction of the footprint.
template <class T>
T horizon_lit_fraction(T mean, T variance, T sin_e) {
  const T half = std::sqrt(T(3) * std::max(variance, T(0)));
  if (!(half > T(1e-3))) return sin_e > mean ? T(1) : T(0);
  return std::clamp((sin_e - (mean - half)) / (T(2) * half), T(0), T(1));
}

// Mean and variance of the horizon sine at the light's azimuth from the 10 channels.
template <class T>
void horizon_moments(const T* channels, Vec3<T> l_local, T* mean, T* variance) {
  T f[kHorizonTerms];
  fourier_basis(l_local.x, l_local.y, f);
  T m1 = 0, m2 = 0;
  for (int m = 0; m < kHorizonTerms; ++m) m1 += channels[m] * f[m], m2 += channels[kHorizonTerms + m] * f[m];
  m1 = std::clamp(m1, T(-1), T(1));
  *mean = m1;
  *variance = std::max(m2 - m1 * m1, T(0));
}

// Horizon-moment estimate of the diffuse transport (see the top of this file; measured as "hm-transport").
template <class T>
T hm_transport(const T* channels, Vec3<T> l_local) {
  if (!(l_local.z > T(0))) return T(0);
  T mean, variance;
  horizon_moments(channels, l_local, &mean, &variance);
  const T sin_e = std::min(l_local.z, T(1));
  return horizon_transport(mean, variance, sin_e, std::sqrt(std::max(T(1) - sin_e * sin_e, T(0))));
}

// Variant that keeps the engine's coarse-normal cosine and takes only the lit fraction from the channels:
// P[lit] · (n_coarse · l)⁺ (measured as "hm-lit-cos").
template <class T>
T hm_lit_cosine(const T* channels, Vec3<T> l_local, Vec3<T> n_coarse_local) {
  if (!(l_local.z > T(0))) return T(0);
  T mean, variance;
  horizon_moments(channels, l_local, &mean, &variance);
  return horizon_lit_fraction(mean, variance, std::min(l_local.z, T(1))) *
         std::max(dot(n_coarse_local, l_local), T(0));
}

// Degree-2 basis plus three cubic terms (z³, x z², y z²), for the 12-channel variant.
inline constexpr int kPoly12Terms = 12;
template <class T>
void poly12_basis(Vec3<T> l, T out[kPoly12Terms]) {
  poly2_basis(l, out);
  out[9] = l.z * l.z * l.z, out[10] = l.x * l.z * l.z, out[11] = l.y * l.z * l.z;
}

// Bent cone from the exact horizon (projected-solid-angle weighting about +z), per azimuth φ with horizon
// elevation H ≥ 0: ∫_H^{π/2} ω (sin e cos e) de = (cos³H/3 · (cos φ, sin φ), (1 − sin³H)/3); its azimuth
// mean is the unnormalised bent normal (its direction is the bent normal) and V = mean cos² H.
template <class T>
Vec3<T> bent_vector_azimuth(T tan_h, T c, T s) {
  const T ch = T(1) / std::sqrt(T(1) + tan_h * tan_h), sh = tan_h * ch;
  const T h = ch * ch * ch / T(3);
  return {h * c, h * s, (T(1) - sh * sh * sh) / T(3)};
}

}  // namespace msh::directional
