// Runtime sampler for the micro-shadowing LUT (Zurita 2026, "Improving Direct Lighting Material Occlusion -
// Part 2", "LUT-Based Approximation"; layout docs/lut.md). Header-only, no allocation, no I/O: an engine
// points a MicroShadowingLutView at its own copy of the table.
//
// Table layout (what bake_micro_shadowing_lut writes, what io::read_volume returns):
//   data[((z * n_nl + y) * n_vis + x) * channels + c], x = Visibility, y = N·L, z = N·V (+ harmonic slab),
//   channel c = roughness[c]; texel i of an axis of size n holds the parameter i/(n − 1).
//   harmonics = 0: the plain LUT, the mean over φ ∈ [0, π] of the exact term. harmonics = H ≥ 1: the
//   azimuth-aware LUT, H + 1 slabs of n_nv slices stacked along z; slab h holds the Fourier cosine
//   coefficient a_h of φ ↦ term(φ), so term(φ) ≈ a_0 + Σ_h a_h cos(hφ) (slab 0 is the plain LUT). The 2D LUT
//   (N·V = 1 slice) has n_nv = 1.
#pragma once

#include <microshadow/math/vec.h>
#include <microshadow/occlusion/micro_shadowing_early_out.h>

#include <array>
#include <cmath>

namespace msh::lut {

// Roughness of the channels r, g, b, a of the default table (docs/lut.md).
inline constexpr std::array<float, 4> kDefaultRoughness = {0.1f, 0.4f, 0.7f, 1.0f};

// Table layouts. Seed: the layout above (Zurita 2026). Cone: the default (what bake micro-shadowing writes and
// the package installs), see "Cone layout".
enum class LutLayout { Seed, Cone };

// Parameters of the cone layout (recorded in the sidecar; the defaults are what `bake` writes).
struct ConeLayoutParams {
  float roughness_min = 0.1f, roughness_max = 1.0f;  // roughness range of the slabs (clamped outside)
  float roughness_power = 0.5f;  // slab q holds roughness r with r^p uniform in q (p = 0: log r uniform)
  float warp_scale = 2.0f;       // warp width a = warp_scale · α, α = roughness²
  int nl_warp = 4, nv_warp = 3;  // axis warps (cone_axis_warp::axis_coord; 3: cone_nv_coord)
  float nv_scale = 3.0f;         // warp 3: width b = nv_scale · α
  float top_scale = 3.0f;        // end of the t axis for grazing light (cone_d_top)
};

// Non-owning view of a baked table (see the layout above). 1 ≤ channels ≤ 4, strictly increasing roughness.
struct MicroShadowingLutView {
  const float* data = nullptr;
  LutLayout layout = LutLayout::Seed;
  int n_vis = 0, n_nl = 0, n_nv = 1;  // n_nv = 1: the 2D LUT (N·V = 1). Cone layout: n_vis = n_t
  int channels = 4;
  std::array<float, 4> roughness = kDefaultRoughness;
  int harmonics = 0;  // seed: extra cos(hφ) slabs along z; cone: channels 1..H (0: plain LUT)
  int n_rough = 1;    // cone layout: roughness slabs along z
  ConeLayoutParams cone;
  // Quantize the linear-filter weights to this many fractional bits, as GPU texture units do (0: exact).
  int filter_weight_bits = 0;
  int depth() const { return layout == LutLayout::Cone ? n_nv * n_rough : n_nv * (harmonics + 1); }
};

// Continuous texel coordinate of parameter u ∈ [0, 1] on an axis of n texels, computed the way a GPU does it:
// the shader remaps u' = (u·(n − 1) + 0.5)/n (docs/lut.md), the sampler takes x = u'·n − 0.5.
template <class T>
T gpu_texel_coord(T u, int n) {
  const T un = (saturate(u) * T(n - 1) + T(0.5)) / T(n);
  return un * T(n) - T(0.5);
}

namespace texel_taps {
// Linear-filter footprint on one axis with clamp-to-edge addressing.
struct Tap {
  int i0, i1;
  float f;
};
// weight_bits > 0: the fraction is rounded down to a multiple of 2^-bits (GPU filter precision, see
// docs/lut.md "GPU filter precision").
template <class T>
Tap tap(T u, int n, int weight_bits = 0) {
  const T x = clamp(gpu_texel_coord(u, n), T(0), T(n - 1));
  const int i0 = std::min(int(x), n - 1);
  float f = float(x - T(i0));
  if (weight_bits > 0) {
    const float scale = float(1 << weight_bits);
    f = std::floor(f * scale) / scale;
  }
  return {i0, std::min(i0 + 1, n - 1), f};
}
}  // namespace texel_taps

// Trilinear fetch of all channels of slab `slab` at (V, N·L, N·V) ∈ [0,1]³ (the hardware filter, in float).
template <class T>
std::array<T, 4> fetch_trilinear(const MicroShadowingLutView& lut, T visibility, T n_dot_l, T n_dot_v,
                                 int slab = 0) {
  using texel_taps::tap;
  const int b = lut.filter_weight_bits;
  const auto tx = tap(visibility, lut.n_vis, b), ty = tap(n_dot_l, lut.n_nl, b),
             tz = tap(n_dot_v, lut.n_nv, b);
  std::array<T, 4> out{};
  const int zbase = slab * lut.n_nv;
  for (int k = 0; k < 8; ++k) {
    const int x = (k & 1) ? tx.i1 : tx.i0, y = (k & 2) ? ty.i1 : ty.i0, z = zbase + ((k & 4) ? tz.i1 : tz.i0);
    const T w =
        T((k & 1) ? tx.f : 1.0f - tx.f) * T((k & 2) ? ty.f : 1.0f - ty.f) * T((k & 4) ? tz.f : 1.0f - tz.f);
    const float* p = lut.data + ((std::size_t(z) * lut.n_nl + y) * lut.n_vis + x) * lut.channels;
    for (int c = 0; c < lut.channels; ++c) out[c] += w * T(p[c]);
  }
  return out;
}

// Linear interpolation across the roughness channels: r is clamped to [roughness[0], roughness[channels−1]]
// (the table's range; the seed clamps roughness to [0.1, 1]). A shader does the same with one dot product.
template <class T>
T interpolate_roughness(const MicroShadowingLutView& lut, const std::array<T, 4>& ch, T roughness) {
  const int n = lut.channels;
  if (n <= 1) return ch[0];
  T r = roughness;
  if (!(r > T(lut.roughness[0]))) r = T(lut.roughness[0]);  // NaN → lowest roughness
  if (r > T(lut.roughness[n - 1])) r = T(lut.roughness[n - 1]);
  int j = 0;
  while (j + 2 < n && r > T(lut.roughness[j + 1])) ++j;
  const T r0 = T(lut.roughness[j]), r1 = T(lut.roughness[j + 1]);
  const T t = r1 > r0 ? clamp((r - r0) / (r1 - r0), T(0), T(1)) : T(0);
  return lerp(t, ch[j], ch[j + 1]);
}

// ---- Cone layout ---------------------------------------------------------------------------------------
// Axes: x = t, the position of the cone half-angle θ (sin²θ = V) relative to the light's polar angle θ_l,
// y = N·L coordinate, z = N·V coordinate + n_nv · roughness slab; channel h = a_h (h = 0: the azimuth mean).
// t ∈ [0, 1] spans the lit range θ ∈ [θ_l/2, π/2] (t = 0 is the early-out boundary 2V + N·L = 1, t = 1 is
// V = 1, or a little past it for grazing light: cone_d_top) through d = sin(θ − θ_l) =
// sqrt(V)·N·L − sqrt(1 − V)·sqrt(1 − N·L²) and
//   u(d) = d / (a + |d|),   t = (u(d) − u(d_lo)) / (u(d_top) − u(d_lo)),
// d_lo = −sqrt((1 − N·L)/2) = sin(−θ_l/2), d_top = N·L (V = 1), a = warp_scale · α. For small α the term is
// a near-step in d at the cone edge θ = θ_l, of width ~α with the heavy tails of the GGX slope distribution
// (~1/d² and, for grazing views, ~1/d); in u it is close to linear, so the step sits near t = ½ for every V
// and N·L and spreads over the whole axis instead of falling between two texels (docs/lut.md).
namespace cone_axis_warp {
template <class T>
T warp_u(T d, T a) {
  return d / (a + std::abs(d));
}
// Axis warps of a cosine c ∈ [0, 1]: 0: c; 1: 1 − sqrt(1 − c) (dense near c = 1); 2: sqrt(c) (dense near
// c = 0); 4: the mean of 1 and 2 (dense near both ends). axis_value is the inverse.
template <class T>
T axis_coord(T c, int warp) {
  if (warp == 1) return T(1) - std::sqrt(std::max(T(0), T(1) - c));
  if (warp == 2) return std::sqrt(std::max(T(0), c));
  if (warp == 4) return T(0.5) * (std::sqrt(std::max(T(0), c)) + T(1) - std::sqrt(std::max(T(0), T(1) - c)));
  return c;
}
template <class T>
T axis_value(T s, int warp) {
  if (warp == 1) return T(1) - (T(1) - s) * (T(1) - s);
  if (warp == 2) return s * s;
  if (warp == 4) {  // invert the monotone map by bisection (baker only)
    T lo = T(0), hi = T(1);
    for (int i = 0; i < 60; ++i) {
      const T mid = T(0.5) * (lo + hi);
      (axis_coord(mid, 4) < s ? lo : hi) = mid;
    }
    return T(0.5) * (lo + hi);
  }
  return s;
}
}  // namespace cone_axis_warp

// N·V coordinate of warp 3: u(N·V)/u(1) with u(c) = c/sqrt(b² + c²), b = nv_scale · max(α, 1e-4): dense
// where N·V ≲ α, where the VNDF of a grazing view changes shape. Other warps: cone_axis_warp::axis_coord.
template <class T>
T cone_nv_coord(const ConeLayoutParams& p, T n_dot_v, T roughness) {
  const T c = saturate(n_dot_v);
  if (p.nv_warp != 3) return cone_axis_warp::axis_coord(c, p.nv_warp);
  const T b = T(p.nv_scale) * std::max(roughness * roughness, T(1e-4));
  return saturate(c / std::sqrt(b * b + c * c) * std::sqrt(b * b + T(1)));
}
inline double cone_nv_of_coord(const ConeLayoutParams& p, double w, double roughness) {
  if (p.nv_warp != 3) return cone_axis_warp::axis_value(w, p.nv_warp);
  const double b = p.nv_scale * std::max(roughness * roughness, 1e-4);
  const double u = std::min(w / std::sqrt(b * b + 1.0), 1.0);  // c/sqrt(b² + c²) = u ⇒ c = b u/sqrt(1 − u²)
  return u >= 1.0 ? 1.0 : std::min(1.0, b * u / std::sqrt(1.0 - u * u));
}

// Warp width a(r) = warp_scale · max(r², 1e-4).
template <class T>
T cone_warp_width(const ConeLayoutParams& p, T roughness) {
  return T(p.warp_scale) * std::max(roughness * roughness, T(1e-4));
}

// Roughness clamped to the slabs' range (NaN → lowest) and its slab coordinate q ∈ [0, 1].
template <class T>
T cone_clamp_roughness(const ConeLayoutParams& p, T roughness) {
  T r = roughness;
  if (!(r > T(p.roughness_min))) r = T(p.roughness_min);
  if (r > T(p.roughness_max)) r = T(p.roughness_max);
  return r;
}
template <class T>
T cone_roughness_coord(const ConeLayoutParams& p, T r) {
  const T lo = T(p.roughness_min), hi = T(p.roughness_max);
  if (!(hi > lo)) return T(0);
  if (p.roughness_power == 0.0f) return saturate(std::log(r / lo) / std::log(hi / lo));
  if (p.roughness_power == 0.5f)  // the default: sqrt, as the shaders do
    return saturate((std::sqrt(r) - std::sqrt(lo)) / (std::sqrt(hi) - std::sqrt(lo)));
  const T e = T(p.roughness_power);
  return saturate((std::pow(r, e) - std::pow(lo, e)) / (std::pow(hi, e) - std::pow(lo, e)));
}
// Roughness of slab coordinate q (inverse of cone_roughness_coord).
inline double cone_roughness_of_coord(const ConeLayoutParams& p, double q) {
  const double lo = p.roughness_min, hi = p.roughness_max;
  if (p.roughness_power == 0.0f) return lo * std::pow(hi / lo, q);
  const double e = p.roughness_power;
  return std::pow(std::pow(lo, e) + q * (std::pow(hi, e) - std::pow(lo, e)), 1.0 / e);
}

// The end of the t axis: d_top = sqrt(N·L² + e²(1 − N·L²)), e = k a/(1 + k a), k = top_scale: just past
// V = 1 (d = N·L) by a margin that matters only for grazing light (N·L ≲ e). The table holds the term's
// smooth continuation past V = 1, P[min(n·m, m·l) > cos θ] / P[m·l > 0] for θ > π/2 (never sampled), so the
// lit side of the step keeps a fixed share of the axis however small N·L is; d_top is smooth in N·L and ≤ 1.
template <class T>
T cone_d_top(T n_dot_l, T a, T top_scale) {
  const T e = top_scale * a / (T(1) + top_scale * a);
  return std::sqrt(n_dot_l * n_dot_l + e * e * (T(1) - n_dot_l * n_dot_l));
}

// The x coordinate t ∈ [0, 1] (see above). V, N·L ∈ [0, 1]; a > 0.
template <class T>
T cone_t(T visibility, T n_dot_l, T a, T top_scale) {
  const T V = saturate(visibility), zl = saturate(n_dot_l);
  const T sl = std::sqrt(std::max(T(0), T(1) - zl * zl));
  const T d = std::sqrt(V) * zl - std::sqrt(T(1) - V) * sl;
  const T ulo = cone_axis_warp::warp_u(-std::sqrt(T(0.5) * (T(1) - zl)), a);
  const T utop = cone_axis_warp::warp_u(cone_d_top(zl, a, top_scale), a);
  return saturate((cone_axis_warp::warp_u(d, a) - ulo) / (utop - ulo));
}
// Inverse of cone_t for the baker: the cone half-angle θ ∈ [θ_l/2, θ_l + π/2] at t (θ > π/2: past V = 1).
inline double cone_theta_of_t(double t, double n_dot_l, double a, double top_scale) {
  const double zl = clamp(n_dot_l, 0.0, 1.0);
  const double ulo = cone_axis_warp::warp_u(-std::sqrt(0.5 * (1.0 - zl)), a);
  const double utop = cone_axis_warp::warp_u(cone_d_top(zl, a, top_scale), a);
  const double u = clamp(ulo + t * (utop - ulo), -1.0, 1.0);
  const double d = std::abs(u) < 1.0 ? a * u / (1.0 - std::abs(u)) : u;
  return std::acos(zl) + std::asin(clamp(d, -1.0, 1.0));
}
// The visibility sin²θ of cone_theta_of_t (θ ≤ π/2; 1 past V = 1).
inline double cone_visibility_of_t(double t, double n_dot_l, double a, double top_scale) {
  const double theta = cone_theta_of_t(t, n_dot_l, a, top_scale);
  return theta >= kPi<double> / 2 ? 1.0 : clamp(sqr(std::sin(theta)), 0.0, 1.0);
}

// Trilinear fetch (all channels) of roughness slab `slab` of a cone-layout table at texture coordinates
// (t, s, w) ∈ [0, 1]³ (the hardware filter; the z coordinate stays inside the slab).
template <class T>
std::array<T, 4> fetch_cone_slab(const MicroShadowingLutView& lut, T t, T s, T w, int slab) {
  return fetch_trilinear(lut, t, s, w, slab);  // the same filter: the slab is the z block of n_nv texels
}

// The cone-layout lookup: coordinates from the inputs, two slab fetches blended in roughness (the second
// fetch is skipped when the weight is 0). Returns the channels a_0 … a_H. No early-out here.
template <class T>
std::array<T, 4> fetch_cone(const MicroShadowingLutView& lut, T visibility, T n_dot_l, T n_dot_v,
                            T roughness) {
  const ConeLayoutParams& p = lut.cone;
  const T r = cone_clamp_roughness(p, roughness);
  const T t = cone_t(visibility, n_dot_l, cone_warp_width(p, r), T(p.top_scale));
  const T s = cone_axis_warp::axis_coord(saturate(n_dot_l), p.nl_warp);
  const T w = cone_nv_coord(p, n_dot_v, r);
  const T q = cone_roughness_coord(p, r) * T(lut.n_rough - 1);
  const int j = std::min(int(q), std::max(lut.n_rough - 2, 0));
  const T f = lut.n_rough > 1 ? clamp(q - T(j), T(0), T(1)) : T(0);
  std::array<T, 4> a = fetch_cone_slab(lut, t, s, w, j);
  if (f > T(0)) {
    const std::array<T, 4> b = fetch_cone_slab(lut, t, s, w, j + 1);
    for (int c = 0; c < lut.channels; ++c) a[c] += f * (b[c] - a[c]);
  }
  return a;
}

// The LUT approximation of the generic VNDF micro-shadowing term (Zurita 2026 Part 2), azimuth ignored (mean
// over φ). Domain: V, N·L, N·V clamped to [0, 1] (NaN → 0), roughness clamped to the channel range. Result in
// [0, 1].
template <class T>
T sample_micro_shadowing(const MicroShadowingLutView& lut, T visibility, T n_dot_l, T n_dot_v, T roughness) {
  if (micro_shadowing::exact_zero(visibility, n_dot_l)) return T(0);  // 2V + N·L < 1: exactly 0, no fetch
  if (lut.layout == LutLayout::Cone)
    return saturate(fetch_cone(lut, visibility, n_dot_l, n_dot_v, roughness)[0]);
  return saturate(
      interpolate_roughness(lut, fetch_trilinear(lut, visibility, n_dot_l, n_dot_v, 0), roughness));
}

// Azimuth-aware variant: a_0 + Σ_{h ≤ H} a_h cos(hφ), cos(hφ) by the Chebyshev recurrence from cos φ.
// cos_phi: cosine of the relative azimuth of l and v (relative_azimuth_cos). A plain table (H = 0) ignores
// it.
template <class T>
T sample_micro_shadowing_azimuth(const MicroShadowingLutView& lut, T visibility, T n_dot_l, T n_dot_v,
                                 T roughness, T cos_phi) {
  if (micro_shadowing::exact_zero(visibility, n_dot_l)) return T(0);  // 2V + N·L < 1: exactly 0, no fetch
  const T c1 = clamp(cos_phi, T(-1), T(1));
  if (lut.layout == LutLayout::Cone) {
    const std::array<T, 4> a = fetch_cone(lut, visibility, n_dot_l, n_dot_v, roughness);
    T sum = a[0], t_prev = T(1), t = c1;
    for (int h = 1; h <= lut.harmonics && h < lut.channels; ++h) {
      sum += t * a[h];
      const T next = T(2) * c1 * t - t_prev;
      t_prev = t, t = next;
    }
    return saturate(sum);
  }
  T sum = interpolate_roughness(lut, fetch_trilinear(lut, visibility, n_dot_l, n_dot_v, 0), roughness);
  T t_prev = T(1), t = c1;  // T_{h−1}(cos φ), T_h(cos φ) = cos((h−1)φ), cos(hφ)
  for (int h = 1; h <= lut.harmonics; ++h) {
    sum += t * interpolate_roughness(lut, fetch_trilinear(lut, visibility, n_dot_l, n_dot_v, h), roughness);
    const T next = T(2) * c1 * t - t_prev;
    t_prev = t, t = next;
  }
  return saturate(sum);
}

// cos of the relative azimuth φ between the tangent-plane projections of v and l (shading frame, n = +z).
// 1 when either projection vanishes (at the pole the term does not depend on φ).
template <class T>
T relative_azimuth_cos(const Vec3<T>& v, const Vec3<T>& l) {
  const T pv = v.x * v.x + v.y * v.y, pl = l.x * l.x + l.y * l.y;
  const T d = std::sqrt(pv * pl);
  if (!(d > T(0)) || !std::isfinite(d)) return T(1);
  return clamp((v.x * l.x + v.y * l.y) / d, T(-1), T(1));
}

}  // namespace msh::lut
