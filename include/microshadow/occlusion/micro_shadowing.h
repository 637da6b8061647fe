// Micro-shadowing terms: how much of a light survives the micro-occlusion cone of a texel.
// Conventions (REFERENCE.md §1–§2): local shading frame n = (0,0,1), tangent = x; v, l unit vectors pointing
// away from the surface; visibility V ∈ [0,1] is visibility in projected solid angle, so the visibility cone
// has cos_t = sqrt(1 − V) (Nusselt analog).
//
// Input handling, shared by every function here: V and N·L are clamped to [0,1] and NaN maps to 0
// (saturate semantics), so every term returns a finite value in [0,1] for any input, including ±Inf and NaN.
//
// The exact generic VNDF-based term (seed 002, GenericM_g) is evaluated by deterministic quadrature:
//   For the Smith profile the per-sample weight G2/G1 depends on (v, l) only, so it cancels in the ratio and
//     GenericM_g = P[n·m > c ∧ m·l > c] / P[m·l > 0],   m ~ D_v (the VNDF of v),  c = cos_t.
//   In spherical coordinates (θ, φ) of m about n, D_v(m) dm ∝ (v·m)⁺ D(m) sinθ dθ dφ. For a fixed φ:
//     * n·m > c is θ < acos c;  m·l = R cos(θ − δ) > c is |θ − δ| < acos(c/R) (R, δ from l and φ);
//     * (v·m)⁺ clips θ to θ < atan2(v_z, −a) when a = v_t·(cosφ, sinφ) < 0;
//     * with t = tanθ the integrand is (a t² + b t)/(k t² + 1)² dt, k = cos²φ/αx² + sin²φ/αy², which has
//       the closed-form antiderivative a·Fa + b·Fb below.
//   What remains is a 1D integral over φ of a continuous, piecewise-smooth function (kinks and square-root
//   points where the θ interval changes shape), done by adaptive Gauss–Kronrod (7/15) with a tolerance
//   relative to the denominator. The azimuth mean is a second adaptive Gauss–Kronrod over the relative
//   azimuth. Accuracy and speed: docs/micro-shadowing.md.
#pragma once

#include <microshadow/math/sampling.h>
#include <microshadow/math/vec.h>
#include <microshadow/microfacet/ggx.h>

#include <array>
#include <cmath>
#include <cstdint>
#include <utility>

namespace msh::ms {

// Form of the Smith masking-shadowing function used for the per-sample weight G2/G1 (seed 002).
enum class G2Form { HeightCorrelated, Uncorrelated };

namespace detail {
// x clamped to [lo, hi]; NaN maps to `nan_value`.
template <class T>
T clamp_nan(T x, T lo, T hi, T nan_value = T(0)) {
  if (std::isnan(x)) return nan_value;
  return x < lo ? lo : (x > hi ? hi : x);
}
}  // namespace detail

// Cosine of the visibility cone's half-angle, sqrt(1 − V) (REFERENCE §1, Nusselt analog). V ∈ [0,1].
template <class T>
T cone_cos_from_visibility(T V) {
  return std::sqrt(T(1) - saturate(V));
}

// Reference term (seed 002): step(cos_t, N·L), lit iff N·L > cos_t (strict, the seed's χ⁺).
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

// Part 1 "analytical alternative" (Zurita 2026, as reported by third-party copies, REFERENCE §2):
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

// Exact early-out (REFERENCE §2): a cone normal is within θ of n and of l, so angle(n,l) < 2θ, i.e.
// N·L > cos 2θ = 1 − 2V. Hence 2V + N·L < 1 ⇒ the generic term is exactly 0 (for every roughness and v).
template <class T>
bool exact_zero(T V, T n_dot_l) {
  return T(2) * saturate(V) + saturate(n_dot_l) < T(1);
}

template <class T>
struct GenericSample {
  T cone, hemisphere, weight;
};

// G2(v,l,m)/G1(v,m) for the Smith profile given m·l > 0 and m·v > 0 (seed 002 table): uncorrelated G1(l),
// height-correlated G1(l)/(G1(l) + G1(v) − G1(l)G1(v)). Anisotropy via the projected roughness, which is what
// GGX::G1 does. Depends on (v, l) only.
template <class T>
T smith_g2_over_g1(const GGX<T>& ggx, const Vec3<T>& v, const Vec3<T>& l, G2Form form) {
  const T gl = ggx.G1(l), gv = ggx.G1(v);
  if (form == G2Form::Uncorrelated) return gl;
  const T den = gl + gv - gl * gv;
  return den > T(0) ? gl / den : T(0);
}

// The seed's per-microfacet function GenericM_m (seed 002, MicroShadowingTermPZGenericVNDFBased): m from the
// Dupuy–Benyoub 2023 VNDF sampler of v, weight G2/G1 in the chosen form. cos_t ∈ [0,1].
template <class T>
GenericSample<T> generic_vndf_sample(T cos_t, const GGX<T>& ggx, const Vec3<T>& v, const Vec3<T>& l,
                                     Vec2<T> u, G2Form form) {
  const Vec3<T> m = ggx.Sample_wm(v, u);
  const T n_dot_m = saturate(m.z);
  const T m_dot_l = saturate(dot(m, l));
  const T c = detail::clamp_nan(cos_t, T(0), T(1), T(1));
  GenericSample<T> s;
  s.weight = m_dot_l > T(0) ? smith_g2_over_g1(ggx, v, l, form) : T(0);
  s.hemisphere = (n_dot_m > T(0) && m_dot_l > T(0)) ? s.weight : T(0);
  s.cone = (n_dot_m - c > T(0) && m_dot_l - c > T(0)) ? s.weight : T(0);
  return s;
}

// GenericM_g (seed 002) estimated with n Owen-scrambled Sobol samples (seed 0: plain Sobol), Σcone /
// Σhemisphere; 0 when no sample reaches the hemisphere or when exact_zero holds (exact, no samples taken).
template <class T>
T generic_vndf_estimate(T V, const GGX<T>& ggx, const Vec3<T>& v, const Vec3<T>& l, int n, G2Form form,
                        uint32_t seed = 1) {
  const T vis = saturate(V);
  if (exact_zero(vis, l.z)) return T(0);
  const T c = cone_cos_from_visibility(vis);
  T cone = 0, hemi = 0;
  for (int i = 0; i < n; ++i) {
    const GenericSample<T> s = generic_vndf_sample(c, ggx, v, l, sobol_2d<T>(uint32_t(i), seed), form);
    cone += s.cone;
    hemi += s.hemisphere;
  }
  return hemi > T(0) ? std::min(T(1), cone / hemi) : T(0);
}

// ---- Exact evaluation (double) -------------------------------------------------------------------------

namespace detail {

// 7-point Gauss / 15-point Kronrod nodes and weights on [-1, 1] (QUADPACK qk15).
inline constexpr std::array<double, 8> kXgk = {
    0.991455371120812639206854697526329, 0.949107912342758524526189684047851,
    0.864864423359769072789712788640926, 0.741531185599394439863864773280788,
    0.586087235467691130294144845693013, 0.405845151377397166906606412076961,
    0.207784955007898467600689403773245, 0.000000000000000000000000000000000};
inline constexpr std::array<double, 8> kWgk = {
    0.022935322010529224963732008058970, 0.063092092629978553290700663189204,
    0.104790010322250183839876322541518, 0.140653259715525918745189590510238,
    0.169004726639267902826583426598550, 0.190350578064785409913256402421014,
    0.204432940075298892414161999234649, 0.209482141084727828012999174891714};
inline constexpr std::array<double, 4> kWg = {
    0.129484966168869693270611432679082, 0.279705391489276667901467239865264,
    0.381830050505118944950369775488975, 0.417959183673469387755102040816327};

// Adaptive Gauss–Kronrod 7/15 of a function returning N values (std::array<double, N>). An interval is
// accepted when every component's |K15 − G7| ≤ tol · (its length / total length), or at max_depth.
template <size_t N, class F>
std::array<double, N> gk15_adaptive(const F& f, double a, double b, double tol, int max_depth = 30) {
  using Arr = std::array<double, N>;
  struct Item {
    double a, b;
    int depth;
  };
  const double total = b - a;
  Arr sum{};
  if (!(total > 0)) return sum;
  Item stack[64];
  int top = 0;
  stack[top++] = {a, b, 0};
  while (top > 0) {
    const Item it = stack[--top];
    const double c = 0.5 * (it.a + it.b), h = 0.5 * (it.b - it.a);
    Arr k{}, g{};
    const Arr fc = f(c);
    for (size_t j = 0; j < N; ++j) k[j] = kWgk[7] * fc[j], g[j] = kWg[3] * fc[j];
    for (int i = 0; i < 7; ++i) {
      const Arr f1 = f(c - h * kXgk[i]), f2 = f(c + h * kXgk[i]);
      for (size_t j = 0; j < N; ++j) {
        k[j] += kWgk[i] * (f1[j] + f2[j]);
        if (i % 2 == 1) g[j] += kWg[i / 2] * (f1[j] + f2[j]);
      }
    }
    const bool forced = it.depth >= max_depth || top >= 62;
    const double local_tol = tol * (2 * h / total);
    bool ok = true;
    for (size_t j = 0; j < N; ++j) ok = ok && std::abs(h * (k[j] - g[j])) <= local_tol;
    if (ok || forced) {
      for (size_t j = 0; j < N; ++j) sum[j] += h * k[j];
    } else {
      stack[top++] = {c, it.b, it.depth + 1};
      stack[top++] = {it.a, c, it.depth + 1};
    }
  }
  return sum;
}

// ∫ t²/(k t² + 1)² dt from 0 to tanθ, = (atan s − s/(1 + s²)) / (2 k^{3/2}), s = √k tanθ, in θ form (finite
// at π/2).
inline double gv_Fa(double theta, double k, double sk) {
  const double s = std::sin(theta), c = std::cos(theta);
  const double q = k * s * s + c * c;
  return (std::atan2(sk * s, c) - sk * s * c / q) / (2.0 * k * sk);
}
// ∫ t/(k t² + 1)² dt from 0 to tanθ = tan²θ / (2(k tan²θ + 1)), in θ form.
inline double gv_Fb(double theta, double k) {
  const double s = std::sin(theta), c = std::cos(theta);
  return s * s / (2.0 * (k * s * s + c * c));
}

// Integrand over the azimuth φ of m: ∫ (v·m)⁺ D(m) sinθ dθ (up to the constant 1/(π αx αy) and the VNDF's
// G1(v)/v_z, which cancel in the ratio) over {θ < acos c ∧ m·l > c}, for c = cos_t (component 0) and c = 0
// (component 1, the hemisphere). v.z ≥ 0.
struct GenericIntegrand {
  Vec3d v, l;
  double ax, ay, cos_t, theta_c;

  double piece(double phi_c, double phi_s, double k, double sk, double c, double th_max) const {
    const double a = v.x * phi_c + v.y * phi_s, b = v.z;
    const double p = l.x * phi_c + l.y * phi_s, q = l.z;
    const double R = std::sqrt(p * p + q * q);
    if (!(R > c)) return 0.0;
    const double delta = std::atan2(p, q);
    const double beta = std::acos(std::min(1.0, c / R));
    double lo = std::max(0.0, delta - beta);
    double hi = std::min(th_max, delta + beta);
    if (a < 0) hi = std::min(hi, std::atan2(b, -a));  // (v·m)⁺ clip
    if (!(hi > lo)) return 0.0;
    const double r = a * (gv_Fa(hi, k, sk) - gv_Fa(lo, k, sk)) + b * (gv_Fb(hi, k) - gv_Fb(lo, k));
    return std::max(0.0, r);
  }
  std::array<double, 2> operator()(double phi) const {
    const double pc = std::cos(phi), ps = std::sin(phi);
    const double k = (pc * pc) / (ax * ax) + (ps * ps) / (ay * ay);
    const double sk = std::sqrt(k);
    return {piece(pc, ps, k, sk, cos_t, theta_c), piece(pc, ps, k, sk, 0.0, 0.5 * kPi<double>)};
  }
};

// Number of equal initial panels over [0, 2π): the integrand has a handful of kinks, panels let the adaptive
// rule find them without relying on the first 15-point estimate.
inline constexpr int kGenericPanels = 8;

}  // namespace detail

// Exact GenericM_g (seed 002) at full vectors, anisotropic GGX (αx along t = x, αy along b = y). Any G2 form
// gives the same value (the Smith weight cancels); the argument exists for API symmetry with the estimators.
// rel_tol bounds the quadrature error relative to the hemisphere integral (default 1e-9 → |error| ≲ 1e-8).
// v.z < 0 is mirrored (as the VNDF sampler does); non-unit vectors are normalized; NaN inputs give 0.
inline double generic_vndf_exact(double V, double alpha_x, double alpha_y, const Vec3d& v, const Vec3d& l,
                                 G2Form form = G2Form::HeightCorrelated, double rel_tol = 1e-9) {
  (void)form;
  const double vis = saturate(V);
  Vec3d vn = normalize(v), ln = normalize(l);
  if (!is_finite(v) || !is_finite(l) || std::isnan(alpha_x) || std::isnan(alpha_y)) return 0.0;
  if (vn.z < 0) vn = -vn;
  if (exact_zero(vis, ln.z) || vis == 0.0) return 0.0;
  if (vis == 1.0) return ln.z > -1.0 ? 1.0 : 0.0;
  const GGX<double> ggx(alpha_x, alpha_y);  // clamps α to [kMinAlpha, ∞)
  detail::GenericIntegrand f;
  f.v = vn, f.l = ln;
  f.ax = std::min(ggx.alpha_x(), 1e4), f.ay = std::min(ggx.alpha_y(), 1e4);
  f.cos_t = cone_cos_from_visibility(vis);
  f.theta_c = std::acos(f.cos_t);
  // Scale for the tolerance: a coarse (non-adaptive) estimate of the hemisphere integral.
  double scale = 0;
  const int P = detail::kGenericPanels;
  const double w = 2 * kPi<double> / P;
  for (int i = 0; i < 4 * P; ++i) scale += f((i + 0.5) * w / 4)[1] * (w / 4);
  if (!(scale > 0)) return 0.0;
  std::array<double, 2> sum{};
  for (int i = 0; i < P; ++i) {
    const auto s = detail::gk15_adaptive<2>(f, i * w, (i + 1) * w, rel_tol * scale / P * 1.0);
    sum[0] += s[0], sum[1] += s[1];
  }
  if (!(sum[1] > 0)) return 0.0;
  return saturate(sum[0] / sum[1]);
}

// Isotropic GGX (α), mean over the relative azimuth φ ∈ [0, π] (uniform) of the exact term with
// v = (sin θv, 0, N·V), l = (sin θl cos φ, sin θl sin φ, N·L): what a LUT texel stores (REFERENCE §1).
// N·V = 1 (or N·L = 1) is azimuth independent and takes one evaluation. rel_tol as above; the outer adaptive
// rule uses abs_tol on the mean.
inline double generic_vndf_exact_azimuth_mean(double V, double alpha, double n_dot_l, double n_dot_v,
                                              G2Form form = G2Form::HeightCorrelated, double abs_tol = 2e-7,
                                              double rel_tol = 1e-9) {
  const double vis = saturate(V);
  const double nl = detail::clamp_nan(n_dot_l, -1.0, 1.0),
               nv = detail::clamp_nan(std::abs(n_dot_v), 0.0, 1.0);
  if (std::isnan(alpha)) return 0.0;
  if (exact_zero(vis, nl) || vis == 0.0) return 0.0;
  const Vec3d v(std::sqrt(std::max(0.0, 1 - nv * nv)), 0, nv);
  const double sl = std::sqrt(std::max(0.0, 1 - nl * nl));
  auto at = [&](double phi) {
    return generic_vndf_exact(vis, alpha, alpha, v, Vec3d(sl * std::cos(phi), sl * std::sin(phi), nl), form,
                              rel_tol);
  };
  if (nv == 1.0 || sl == 0.0 || vis == 1.0) return at(0.0);
  const auto f = [&](double phi) { return std::array<double, 1>{at(phi)}; };
  // Two panels: the integrand is smoothest near φ = 0 and φ = π (mirror symmetric there).
  const double h = 0.5 * kPi<double>;
  const double s = detail::gk15_adaptive<1>(f, 0, h, abs_tol * kPi<double> * 0.5)[0] +
                   detail::gk15_adaptive<1>(f, h, 2 * h, abs_tol * kPi<double> * 0.5)[0];
  return saturate(s / kPi<double>);
}

}  // namespace msh::ms
