// Exact reference evaluation of the generic VNDF-based micro-shadowing term (Zurita 2026, "Improving Direct
// Lighting Material Occlusion - Part 2", GenericM_g) for anisotropic Smith-GGX, in double precision. Not for
// an engine: it is the reference the estimator, the LUT baker, the ALU fits and the shaders are measured
// against. Conventions and the engine-facing terms: occlusion/micro_shadowing.h.
//
// The term is evaluated deterministically:
//   For the Smith profile the per-sample weight G2/G1 depends on (v, l) only, so it cancels in the ratio and
//     GenericM_g = P[n·m > c ∧ m·l > c] / P[m·l > 0],   m ~ D_v (the VNDF of v),  c = cos_t.
//   Denominator: closed form. In the stretched (α = 1) configuration the VNDF is a clamped cosine lobe and
//     m·l > 0 is a hemisphere, so P is a cosine integral over a spherical triangle (Lambert's formula).
//   Numerator: in spherical coordinates (θ, φ) of m about n, D_v(m) dm ∝ (v·m)⁺ D(m) sinθ dθ dφ. For a fixed
//   φ:
//     * n·m > c is θ < acos c;  m·l = R cos(θ − δ) > c is |θ − δ| < acos(c/R) (R, δ from l and φ);
//     * (v·m)⁺ clips θ to θ < atan2(v_z, −a) when a = v_t·(cosφ, sinφ) < 0;
//     * with t = tanθ the integrand is (a t² + b t)/(k t² + 1)² dt, k = cos²φ/αx² + sin²φ/αy², which has a
//       closed-form antiderivative.
//   What remains is a 1D integral over φ of a continuous, piecewise-smooth function. Its kinks and
//   square-root points (where the θ interval changes form) are found in closed form; each panel between them
//   is integrated by adaptive Gauss–Kronrod (7/15) after a smoothstep substitution that removes the square
//   roots. The azimuth mean is a second adaptive Gauss–Kronrod over the relative azimuth. Accuracy and speed:
//   docs/micro-shadowing.md.
#pragma once

#include <microshadow/math/quadrature.h>
#include <microshadow/math/vec.h>
#include <microshadow/microfacet/beckmann.h>
#include <microshadow/microfacet/ggx.h>
#include <microshadow/occlusion/micro_shadowing.h>

#include <algorithm>
#include <array>
#include <cmath>

namespace msh::micro_shadowing {

namespace exact_quadrature {

// With t = tanθ, s = √k t: ∫_0^t (a u² + b u)/(k u² + 1)² du
//   = a (atan s − s/(1 + s²)) / (2 k^{3/2}) + b t² / (2(k t² + 1)),
// written in sinθ, cosθ so that θ = π/2 is finite.
inline double gv_F(double theta, double a, double b, double k, double sk) {
  const double s = std::sin(theta), c = std::cos(theta);
  const double q = k * s * s + c * c;
  return a * (std::atan2(sk * s, c) - sk * s * c / q) / (2.0 * k * sk) + b * s * s / (2.0 * q);
}

// Beckmann (RTR4 9.52): with t = tanθ, D(m) sinθ dθ (v·m) = (a t² + b t) e^{−k t²} dt / (π αx αy), so
// ∫_0^t (a u² + b u) e^{−k u²} du = b (1 − e^{−k t²})/(2k) + a (√π erf(√k t)/(4 k^{3/2}) − t e^{−k t²}/(2k)),
// finite at θ = π/2 (t = ∞).
inline double beckmann_theta_F(double theta, double a, double b, double k, double sk) {
  const double s = std::sin(theta), c = std::cos(theta);
  constexpr double kSqrtPi = 1.7724538509055160;
  if (!(c > 1e-300)) return b / (2 * k) + a * kSqrtPi / (4 * k * sk);
  const double t = s / c, kt2 = k * t * t;
  const double e = std::exp(-kt2);
  return -b * std::expm1(-kt2) / (2 * k) +
         a * (kSqrtPi * std::erf(sk * t) / (4 * k * sk) - (e > 0 ? t * e : 0.0) / (2 * k));
}

// The θ antiderivative of (v·m) D(m) sinθ at one azimuth, per shape-invariant Smith NDF: D(m) is
// f(k tan²θ)/(π αx αy cos⁴θ) with k = cos²φ/αx² + sin²φ/αy² for both.
template <class Dist>
struct ThetaMass;
template <>
struct ThetaMass<GGX<double>> {
  static double F(double theta, double a, double b, double k, double sk) { return gv_F(theta, a, b, k, sk); }
};
template <>
struct ThetaMass<Beckmann<double>> {
  static double F(double theta, double a, double b, double k, double sk) {
    return beckmann_theta_F(theta, a, b, k, sk);
  }
};

// The θ interval of the region {θ < theta_max ∧ m·l > c ∧ v·m > 0} at the azimuth φ of m, with the
// azimuth's projections a = v_t·(cos φ, sin φ) (v·m = a sinθ + b cosθ, b = v_z), p = l_t·(cos φ, sin φ)
// (m·l = p sinθ + q cosθ, q = l_z) and k = cos²φ/αx² + sin²φ/αy². empty when the interval is.
struct AzimuthSlice {
  double lo, hi, a, b, p, q, k;
  bool empty;
};
inline AzimuthSlice azimuth_slice(const Vec3d& v, const Vec3d& l, double inv_ax2, double inv_ay2, double c,
                                  double theta_max, double phi) {
  const double pc = std::cos(phi), ps = std::sin(phi);
  AzimuthSlice z{
      0, 0, v.x * pc + v.y * ps, v.z, l.x * pc + l.y * ps, l.z, pc * pc * inv_ax2 + ps * ps * inv_ay2, true};
  const double R = std::sqrt(z.p * z.p + z.q * z.q);  // m·l = R cos(θ − δ)
  if (!(R > c)) return z;
  const double delta = std::atan2(z.p, z.q);
  const double beta = std::acos(std::min(1.0, c / R));
  z.lo = std::max(0.0, delta - beta);
  z.hi = std::min(theta_max, delta + beta);
  if (z.a < 0) z.hi = std::min(z.hi, std::atan2(z.b, -z.a));  // (v·m)⁺ clip
  z.empty = !(z.hi > z.lo);
  return z;
}

// Integrand over the azimuth φ of m: ∫ (v·m)⁺ D(m) sinθ dθ over {θ < acos c ∧ m·l > c}, up to the constant
// 1/(π αx αy) and the VNDF's G1(v)/v_z, which cancel in the ratio. c = cos_t for the cone, 0 for the
// hemisphere. v.z ≥ 0, v and l unit. Dist: GGX<double> (the default) or Beckmann<double>.
template <class Dist>
struct RegionIntegrandT {
  Vec3d v, l;
  double inv_ax2, inv_ay2, c, theta_max;

  double operator()(double phi) const {
    const AzimuthSlice z = azimuth_slice(v, l, inv_ax2, inv_ay2, c, theta_max, phi);
    if (z.empty) return 0.0;
    const double sk = std::sqrt(z.k);
    const double r = ThetaMass<Dist>::F(z.hi, z.a, z.b, z.k, sk) -
                     (z.lo > 0 ? ThetaMass<Dist>::F(z.lo, z.a, z.b, z.k, sk) : 0.0);
    return std::max(0.0, r);
  }
};
using RegionIntegrand = RegionIntegrandT<GGX<double>>;

// Azimuths where the θ interval of RegionIntegrand changes form (kinks) or vanishes like a square root, all
// in closed form: the l-cone meets the n-cone; the l-cone is tangent to a meridian (R = c, support ends); the
// great circle v·m = 0 meets the n-cone or the l-cone; p = 0. Returned unsorted, count in n.
inline int region_breakpoints(const Vec3d& v, const Vec3d& l, double c, double* out) {
  int n = 0;
  const double sc = std::sqrt(std::max(0.0, 1 - c * c));
  const double lt = std::hypot(l.x, l.y), q = l.z;
  const double phl = lt > 0 ? std::atan2(l.y, l.x) : 0.0;
  auto pair = [&](double center, double cosw) {
    if (std::abs(cosw) <= 1) {
      const double w = std::acos(cosw);
      out[n++] = center - w, out[n++] = center + w;
    }
  };
  out[n++] = phl;  // the origin of the panels
  if (lt > 1e-12) {
    if (q <= c) pair(phl, 0.0);                      // p = 0: support end of the hemisphere when l.z ≤ 0
    if (sc > 0) pair(phl, c * (1 - q) / (sc * lt));  // l-cone ∩ n-cone
    if (c > std::abs(q)) pair(phl, std::sqrt(c * c - q * q) / lt);  // support ends (R = c)
  }
  const double vt = std::hypot(v.x, v.y);
  if (vt > 1e-12) {
    const double phv = std::atan2(v.y, v.x);
    if (sc > 0) pair(phv, -v.z * c / (sc * vt));  // v circle ∩ n-cone
    // v circle ∩ l-cone: m = cosψ e1 + sinψ e2 ⟂ v with m·l = c.
    const Frame<double> f = Frame<double>::from_z(v);
    const double A = dot(l, f.s), B = dot(l, f.t), rho = std::hypot(A, B);
    if (rho > c && rho > 0) {
      const double psi0 = std::atan2(B, A), dpsi = std::acos(c / rho);
      for (double psi : {psi0 - dpsi, psi0 + dpsi}) {
        const Vec3d m = std::cos(psi) * f.s + std::sin(psi) * f.t;
        if (m.z > 0) out[n++] = std::atan2(m.y, m.x);
      }
    }
  }
  return n;
}

// ∫_0^{2π} f dφ: panels between the nb breakpoints bp (bp[0] is the origin; none wider than π/2), each
// integrated by adaptive Gauss–Kronrod after the substitution φ = a + (b − a)(3s² − 2s³), which turns
// square-root endpoints into smooth ones. abs_tol is the total absolute tolerance. nb ≤ 70.
template <class F>
double integrate_panels(const F& f, const double* bp, int nb, double abs_tol) {
  const double two_pi = 2 * kPi<double>;
  const double origin = bp[0];  // φ_l: every other breakpoint is mapped into [origin, origin + 2π)
  double pts[72];
  int np = 0;
  pts[np++] = 0.0;
  for (int i = 1; i < nb; ++i) {
    double x = std::fmod(bp[i] - origin, two_pi);
    if (x < 0) x += two_pi;
    if (x > 1e-12 && x < two_pi - 1e-12) pts[np++] = x;
  }
  pts[np++] = two_pi;
  std::sort(pts, pts + np);
  double sum = 0;
  for (int i = 0; i + 1 < np; ++i) {
    const double a0 = pts[i], b0 = pts[i + 1];
    if (!(b0 - a0 > 1e-13)) continue;
    const int parts = int(std::ceil((b0 - a0) / (0.5 * kPi<double>)));
    for (int j = 0; j < parts; ++j) {
      const double a = origin + a0 + (b0 - a0) * j / parts, h = (b0 - a0) / parts;
      const auto g = [&](double s) {
        return std::array<double, 1>{f(a + h * s * s * (3 - 2 * s)) * 6 * h * s * (1 - s)};
      };
      sum += gauss_kronrod_adaptive<1>(g, 0.0, 1.0, abs_tol * h / two_pi)[0];
    }
  }
  return sum;
}

// ∫_0^{2π} f dφ, panels between the closed-form breakpoints of the region. F: any integrand over φ with
// members v, l, c (RegionIntegrandT; the V-cavity's in micro_shadowing_vcavity.h, which adds its own
// breakpoints through an optional member extra_breakpoints(double* out) → count).
template <class F>
double integrate_region(const F& f, double abs_tol) {
  double bp[32];
  int nb = region_breakpoints(f.v, f.l, f.c, bp);
  if constexpr (requires { f.extra_breakpoints(bp); }) nb += f.extra_breakpoints(bp + nb);
  return integrate_panels(f, bp, nb, abs_tol);
}

// ∫ (w·m) dm over {m·w > 0 ∧ m·n1 > 0 ∧ m·n2 > 0} (unit w, n1, n2): a spherical triangle (or lune, or
// hemisphere), integrated by Lambert's polygon formula, ½ Σ_edges θ_e (w·n_e), with n_e the inward normal of
// the edge's great circle (Arvo 1995, "Applications of Irradiance Tensors"). The arc of circle i inside the
// other two hemispheres is the overlap of two semicircles, π − angle between their centres.
inline double clamped_cosine_over_hemispheres(const Vec3d& w, const Vec3d& n1, const Vec3d& n2) {
  Vec3d ns[3] = {w, n1, n2};
  int n = 1;
  for (const Vec3d& c : {n1, n2}) {
    bool dup = false;
    for (int i = 0; i < n; ++i) {
      if (length(c - ns[i]) < 1e-12) dup = true;
      if (length(c + ns[i]) < 1e-12) return 0.0;  // opposite hemispheres: measure zero
    }
    if (!dup) ns[n++] = c;
  }
  double sum = 0;
  for (int i = 0; i < n; ++i) {
    double theta = 2 * kPi<double>;
    Vec3d u[2];
    int nu = 0;
    for (int j = 0; j < n; ++j)
      if (j != i) u[nu++] = normalize(ns[j] - dot(ns[j], ns[i]) * ns[i], Vec3d(0, 0, 0));
    if (nu == 1) theta = kPi<double>;
    if (nu == 2) theta = std::max(0.0, kPi<double> - std::atan2(length(cross(u[0], u[1])), dot(u[0], u[1])));
    sum += theta * dot(w, ns[i]);
  }
  return 0.5 * sum;
}

// P[m·l > 0] for m ~ VNDF of v (v.z ≥ 0), closed form. In the stretched (α = 1) configuration the VNDF is the
// clamped cosine 2(w·m)⁺/(π(1 + w_z)) on z > 0 with w = normalize(αx v_x, αy v_y, v_z) (Heitz 2018), and
// m·l > 0 becomes m·(αx l_x, αy l_y, l_z) > 0, a hemisphere: the three-hemisphere integral above.
inline double vndf_hemisphere_probability(const GGX<double>& ggx, const Vec3d& v, const Vec3d& l) {
  const Vec3d w = normalize(Vec3d(ggx.alpha_x() * v.x, ggx.alpha_y() * v.y, v.z));
  const Vec3d lp = normalize(Vec3d(ggx.alpha_x() * l.x, ggx.alpha_y() * l.y, l.z), Vec3d(0, 0, 0));
  if (!(dot(lp, lp) > 0)) return 0.0;
  return std::min(1.0,
                  clamped_cosine_over_hemispheres(w, Vec3d(0, 0, 1), lp) / (0.5 * kPi<double> * (1 + w.z)));
}

// P[n·m > c ∧ m·l > c] for m ~ VNDF of v (v.z ≥ 0) by the azimuthal quadrature (c = 0: the hemisphere, used
// to cross-check the closed form). abs_tol is on the probability.
template <class Dist>
double vndf_region_probability(const Dist& dist, const Vec3d& v, const Vec3d& l, double c, double abs_tol) {
  // D_v(m) dm = G1(v)/v_z · (v·m)⁺ · D(m) sinθ dθ dφ, D(m) sinθ dθ in t = tanθ as in ThetaMass; the
  // integrand drops the constant 1/(π αx αy).
  const double pre = dist.G1_over_cos(v) / (kPi<double> * dist.alpha_x() * dist.alpha_y());
  const RegionIntegrandT<Dist> f{v, l, 1 / sqr(dist.alpha_x()), 1 / sqr(dist.alpha_y()), c, std::acos(c)};
  return pre * integrate_region(f, abs_tol / pre);
}

// P[m·l > 0] for m ~ VNDF of v: closed form for GGX, the c = 0 quadrature for Beckmann (no closed form).
inline double vndf_hemisphere_mass(const GGX<double>& ggx, const Vec3d& v, const Vec3d& l, double) {
  return vndf_hemisphere_probability(ggx, v, l);
}
inline double vndf_hemisphere_mass(const Beckmann<double>& b, const Vec3d& v, const Vec3d& l,
                                   double abs_tol) {
  return std::min(1.0, vndf_region_probability(b, v, l, 0.0, abs_tol));
}

// Mean over the relative azimuth φ of at(φ): over [0, π] in two panels when the term is symmetric in
// φ → −φ, else over [0, 2π] in four; each panel an adaptive Gauss–Kronrod with error estimate ≤ abs_tol per
// unit of φ.
template <class F>
double azimuth_mean(const F& at, bool symmetric, double abs_tol) {
  const auto f = [&](double phi) { return std::array<double, 1>{at(phi)}; };
  const double h = 0.5 * kPi<double>;
  const int panels = symmetric ? 2 : 4;
  double s = 0;
  for (int i = 0; i < panels; ++i) s += gauss_kronrod_adaptive<1>(f, i * h, (i + 1) * h, abs_tol * h)[0];
  return saturate(s / (panels * h));
}

}  // namespace exact_quadrature

// Exact GenericM_g (Zurita 2026b) at full vectors for an anisotropic shape-invariant Smith NDF: GGX<double>
// or Beckmann<double> (αx along t = x, αy along b = y). It takes no G2 form: for the Smith profile the weight
// G2/G1 depends on (v, l) only and cancels in the ratio, so both forms give the same value. Numerator by
// azimuthal quadrature, denominator in closed form (GGX) or by the same quadrature at c = 0 (Beckmann, to
// 1e-3·rel_tol). rel_tol bounds the quadrature's error estimate relative to the denominator (default 1e-7;
// the measured error is far below, see docs/micro-shadowing.md). v.z < 0 is mirrored (as the VNDF samplers
// do); non-unit vectors are normalized; NaN or Inf inputs give 0.
template <class Dist>
requires SmithDistribution<Dist>
double generic_vndf_exact(double V, const Dist& dist, const Vec3d& v, const Vec3d& l, double rel_tol = 1e-7) {
  if (!is_finite(v) || !is_finite(l) || std::isnan(dist.alpha_x()) || std::isnan(dist.alpha_y())) return 0.0;
  const double vis = saturate(V);
  Vec3d vn = normalize(v), ln = normalize(l);
  if (vn.z < 0) vn = -vn;
  if (exact_zero(vis, ln.z) || vis == 0.0) return 0.0;
  const Dist d(std::min(dist.alpha_x(), 1e4), std::min(dist.alpha_y(), 1e4));  // α ∈ [kMinAlpha, 1e4]
  const double den = exact_quadrature::vndf_hemisphere_mass(d, vn, ln, 1e-3 * rel_tol);
  if (!(den > 0)) return 0.0;
  if (vis == 1.0) return 1.0;
  const double c = cone_cos_from_visibility(vis);
  const double num = exact_quadrature::vndf_region_probability(d, vn, ln, c, rel_tol * den);
  return saturate(num / den);
}

// The same for anisotropic GGX given by its two roughnesses (αx, αy).
inline double generic_vndf_exact(double V, double alpha_x, double alpha_y, const Vec3d& v, const Vec3d& l,
                                 double rel_tol = 1e-7) {
  if (std::isnan(alpha_x) || std::isnan(alpha_y)) return 0.0;
  return generic_vndf_exact(V, GGX<double>(alpha_x, alpha_y), v, l, rel_tol);
}

// Isotropic GGX (α), mean over the relative azimuth φ ∈ [0, π] (uniform) of the exact term with
// v = (sin θv, 0, N·V), l = (sin θl cos φ, sin θl sin φ, N·L): what a LUT texel stores (docs/theory.md §1).
// N·V = 1, N·L = ±1 and V = 1 are azimuth independent and take one evaluation. The mean is an adaptive
// Gauss–Kronrod over φ (two panels) whose error estimate is bounded by abs_tol; rel_tol is passed to
// generic_vndf_exact. The term is smooth in φ apart from a few kinks; the measured error with the defaults
// is < 1e-6 (docs/micro-shadowing.md).
inline double generic_vndf_exact_azimuth_mean(double V, double alpha, double n_dot_l, double n_dot_v,
                                              double abs_tol = 1e-5, double rel_tol = 1e-5) {
  if (std::isnan(alpha)) return 0.0;
  const double vis = saturate(V);
  const double nl = input_domain::clamp_nan(n_dot_l, -1.0, 1.0);
  const double nv = input_domain::clamp_nan(std::abs(n_dot_v), 0.0, 1.0);
  if (exact_zero(vis, nl) || vis == 0.0) return 0.0;
  const Vec3d v(std::sqrt(std::max(0.0, 1 - nv * nv)), 0, nv);
  const double sl = std::sqrt(std::max(0.0, 1 - nl * nl));
  auto at = [&](double phi) {
    return generic_vndf_exact(vis, alpha, alpha, v, Vec3d(sl * std::cos(phi), sl * std::sin(phi), nl),
                              rel_tol);
  };
  if (nv == 1.0 || sl == 0.0 || vis == 1.0) return at(0.0);
  const auto f = [&](double phi) { return std::array<double, 1>{at(phi)}; };
  // Two panels: one 15-point rule over [0, π] can misjudge a kink (measured 2.7e-6 error); two keep it <
  // 1e-6.
  const double h = 0.5 * kPi<double>;
  const double s = gauss_kronrod_adaptive<1>(f, 0.0, h, abs_tol * h)[0] +
                   gauss_kronrod_adaptive<1>(f, h, 2 * h, abs_tol * h)[0];
  return saturate(s / kPi<double>);
}

// Anisotropic Smith NDF (GGX<double> or Beckmann<double>, αx along x, αy along y): mean over the relative
// azimuth φ (uniform) of generic_vndf_exact with v = (sin θv cos φv, sin θv sin φv, N·V) at tangent azimuth
// φv and l = (sin θl cos(φv + φ), sin θl sin(φv + φ), N·L): the anisotropic counterpart of what a LUT texel
// stores. For φv a multiple of π/2 the term is symmetric in φ → −φ (mirror about the plane of v and the
// axis it lies on), so the mean over [0, π] is the whole circle's and takes two panels as the isotropic
// mean; otherwise the mean is over [0, 2π] in four panels. Each panel is an adaptive Gauss–Kronrod whose
// error estimate is bounded by abs_tol (per unit of φ); rel_tol goes to generic_vndf_exact. N·L ∈ [−1, 1],
// N·V ∈ [0, 1] (|N·V| is used); the early-out, V ∈ {0, 1} and N·L = ±1 take one evaluation or none.
template <class Dist>
requires SmithDistribution<Dist>
double generic_vndf_exact_azimuth_mean(double V, const Dist& dist, double n_dot_l, double n_dot_v,
                                       double phi_v = 0.0, double abs_tol = 1e-5, double rel_tol = 1e-5) {
  if (std::isnan(dist.alpha_x()) || std::isnan(dist.alpha_y()) || !std::isfinite(phi_v)) return 0.0;
  const double vis = saturate(V);
  const double nl = input_domain::clamp_nan(n_dot_l, -1.0, 1.0);
  const double nv = input_domain::clamp_nan(std::abs(n_dot_v), 0.0, 1.0);
  if (exact_zero(vis, nl) || vis == 0.0) return 0.0;
  const double sv = std::sqrt(std::max(0.0, 1 - nv * nv)), sl = std::sqrt(std::max(0.0, 1 - nl * nl));
  if (sv == 0.0) phi_v = 0.0;  // v = n: its azimuth is arbitrary
  const Vec3d v(sv * std::cos(phi_v), sv * std::sin(phi_v), nv);
  auto at = [&](double phi) {
    return generic_vndf_exact(vis, dist, v, Vec3d(sl * std::cos(phi_v + phi), sl * std::sin(phi_v + phi), nl),
                              rel_tol);
  };
  if (sl == 0.0 || vis == 1.0) return at(0.0);
  const double q = phi_v / (0.5 * kPi<double>);
  return exact_quadrature::azimuth_mean(at, dist.is_isotropic() || std::abs(q - std::round(q)) < 1e-12,
                                        abs_tol);
}

// Anisotropic GGX with v along the tangent (φv = 0): the mean over φ ∈ [0, π] (the form the CLI's
// generic-vndf method reports without --phi).
inline double generic_vndf_exact_azimuth_mean_anisotropic(double V, double alpha_x, double alpha_y,
                                                          double n_dot_l, double n_dot_v,
                                                          double abs_tol = 1e-5) {
  if (std::isnan(alpha_x) || std::isnan(alpha_y)) return 0.0;
  return generic_vndf_exact_azimuth_mean(V, GGX<double>(alpha_x, alpha_y), n_dot_l, n_dot_v, 0.0, abs_tol,
                                         1e-7);
}

}  // namespace msh::micro_shadowing
