// Runtime sampler for the micro-shadowing LUT (seed 002 "LUT-Based Approximation"; layout REFERENCE.md §1).
// Header-only, no allocation, no I/O: an engine points a MicroShadowingLutView at its own copy of the table.
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

#include <array>
#include <cmath>

namespace msh::lut {

// Roughness of the channels r, g, b, a of the default table (REFERENCE.md §1).
inline constexpr std::array<float, 4> kDefaultRoughness = {0.1f, 0.4f, 0.7f, 1.0f};

// Non-owning view of a baked table (see the layout above). 1 ≤ channels ≤ 4, strictly increasing roughness.
struct MicroShadowingLutView {
  const float* data = nullptr;
  int n_vis = 0, n_nl = 0, n_nv = 1;  // n_nv = 1: the 2D LUT (N·V = 1)
  int channels = 4;
  std::array<float, 4> roughness = kDefaultRoughness;
  int harmonics = 0;  // extra cos(hφ) slabs along z (0: plain LUT)
  int depth() const { return n_nv * (harmonics + 1); }
};

// Continuous texel coordinate of parameter u ∈ [0, 1] on an axis of n texels, computed the way a GPU does it:
// the shader remaps u' = (u·(n − 1) + 0.5)/n (REFERENCE.md §1), the sampler takes x = u'·n − 0.5.
template <class T>
T gpu_texel_coord(T u, int n) {
  const T un = (saturate(u) * T(n - 1) + T(0.5)) / T(n);
  return un * T(n) - T(0.5);
}

namespace lut_detail {
// Linear-filter footprint on one axis with clamp-to-edge addressing.
struct Tap {
  int i0, i1;
  float f;
};
template <class T>
Tap tap(T u, int n) {
  const T x = clamp(gpu_texel_coord(u, n), T(0), T(n - 1));
  const int i0 = std::min(int(x), n - 1);
  return {i0, std::min(i0 + 1, n - 1), float(x - T(i0))};
}
}  // namespace lut_detail

// Trilinear fetch of all channels of slab `slab` at (V, N·L, N·V) ∈ [0,1]³ (the hardware filter, in float).
template <class T>
std::array<T, 4> fetch_trilinear(const MicroShadowingLutView& lut, T visibility, T n_dot_l, T n_dot_v,
                                 int slab = 0) {
  using lut_detail::tap;
  const auto tx = tap(visibility, lut.n_vis), ty = tap(n_dot_l, lut.n_nl), tz = tap(n_dot_v, lut.n_nv);
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

// Exact early-out (REFERENCE.md §2): 2V + N·L < 1 ⇒ the term is 0, no fetch needed.
template <class T>
bool micro_shadowing_early_out(T visibility, T n_dot_l) {
  return T(2) * saturate(visibility) + saturate(n_dot_l) < T(1);
}

// The LUT approximation of the generic VNDF micro-shadowing term (seed 002), azimuth ignored (mean over φ).
// Domain: V, N·L, N·V clamped to [0, 1] (NaN → 0), roughness clamped to the channel range. Result in [0, 1].
template <class T>
T sample_micro_shadowing(const MicroShadowingLutView& lut, T visibility, T n_dot_l, T n_dot_v, T roughness) {
  if (micro_shadowing_early_out(visibility, n_dot_l)) return T(0);
  return saturate(
      interpolate_roughness(lut, fetch_trilinear(lut, visibility, n_dot_l, n_dot_v, 0), roughness));
}

// Azimuth-aware variant: a_0 + Σ_{h ≤ H} a_h cos(hφ), cos(hφ) by the Chebyshev recurrence from cos φ.
// cos_phi: cosine of the relative azimuth of l and v (relative_azimuth_cos). A plain table (H = 0) ignores
// it.
template <class T>
T sample_micro_shadowing_azimuth(const MicroShadowingLutView& lut, T visibility, T n_dot_l, T n_dot_v,
                                 T roughness, T cos_phi) {
  if (micro_shadowing_early_out(visibility, n_dot_l)) return T(0);
  const T c1 = clamp(cos_phi, T(-1), T(1));
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
