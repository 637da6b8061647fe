// Exact references of the micro-BRDF-aware micro-shadowing terms (docs/micro-shadowing-aware.md), double
// precision, Smith-GGX (anisotropic at full vectors). Not engine code: what the estimator, the closed form in
// float, the shaders and the study's terms are measured against. Engine-facing forms:
// occlusion/micro_shadowing_aware.h.
//
// Diffuse-aware term: a ratio of two integrals over the VNDF of v (the Smith G2/G1 cancels, as for the
// generic term of Zurita 2026, "Improving Direct Lighting Material Occlusion – Part 2"):
//   ∫ D_v(m) w_cone(m) dm / ∫ D_v(m) w_hemi(m) dm,
// with the weights of DiffuseAwareForm. In spherical coordinates (θ, φ) of m about n, for a fixed φ every
// indicator is an interval of θ (n·m > c: θ < acos c; x·m > c: |θ − δx| < acos(c/Rx) for x = l, v), and
// with tan θ = α_φ tan u (α_φ = (cos²φ/αx² + sin²φ/αy²)^−1/2) the measure (v·m)⁺ D(m) sin θ dθ becomes
// (α_φ sin u (v_t·e_φ) + cos u v_z) sin u du / (π αx αy k): smooth in u up to θ = π/2, so each θ interval is
// an adaptive Gauss–Kronrod in u (the Lambertian cap fraction's kink at θ = π/2 − acos c is a split point).
// The φ integral uses the generic term's closed-form breakpoints for the l-cone and (swapping roles) the
// v-cone, and the same smoothstep panels (reference/micro_shadowing_exact.h).
// Specular-aware azimuth mean: a 1D adaptive Gauss–Kronrod of S(φ) D(h(φ)) over φ ∈ [0, π] split at the two
// closed-form jumps of S, independent of the closed form it checks.
#pragma once

#include <microshadow/bsdf/diffuse.h>
#include <microshadow/math/quadrature.h>
#include <microshadow/occlusion/micro_shadowing_aware.h>
#include <microshadow/reference/micro_shadowing_exact.h>

#include <algorithm>
#include <cmath>

namespace msh::micro_shadowing {

// The second facet micro-BRDF of the reciprocal form (docs/micro-shadowing-aware.md §3.1): instead of
// Lambert, the Oren–Nayar qualitative model (Oren & Nayar 1994, "Generalization of Lambert's Reflectance
// Model"; bsdf::diffuse_oren_nayar_qualitative) on each facet, in the facet's own frame (normal m), with
// sub-facet slope deviation sigma (radians). Returns π f_ON(ρ = 1; l, v about m) = A + B max(0, cos Δφ) sin α
// tan β: 1 at sigma = 0 (Lambert), 0 when l or v is below the facet. m, l, v unit.
template <class T>
T oren_nayar_facet_weight(T sigma, const Vec3<T>& m, const Vec3<T>& l, const Vec3<T>& v) {
  const T ml = dot(m, l), mv = dot(m, v);
  if (!(ml > T(0)) || !(mv > T(0))) return T(0);
  if (!(sigma > T(0))) return T(1);
  // l and v in a frame of m: x along l's tangent component (any tangent when l = m: cos Δφ is then unused).
  const Vec3<T> lt = l - ml * m, vt = v - mv * m;
  const T sl = std::sqrt(std::max(T(0), dot(lt, lt))), sv2 = std::max(T(0), dot(vt, vt));
  const T vx = sl > T(1e-12) ? dot(lt, vt) / sl : std::sqrt(sv2);
  const Vec3<T> l_loc(sl, T(0), std::min(ml, T(1)));
  const Vec3<T> v_loc(vx, std::sqrt(std::max(T(0), sv2 - vx * vx)), std::min(mv, T(1)));
  return kPi<T> * bsdf::diffuse_oren_nayar_qualitative<T, T>(T(1), std::min(sigma, T(10)), l_loc, v_loc);
}
// The same as a facet weight for diffuse_aware_sample / diffuse_aware_estimate (occlusion/
// micro_shadowing_aware.h).
struct OrenNayarFacet {
  double sigma = 0;
  template <class T>
  T operator()(const Vec3<T>& m, const Vec3<T>& l, const Vec3<T>& v) const {
    return oren_nayar_facet_weight(T(sigma), m, l, v);
  }
};

namespace aware_quadrature {
using namespace exact_quadrature;  // the exact term's azimuth slices and panel integrators

#ifndef MSH_AWARE_INNER_TOL
#define MSH_AWARE_INNER_TOL 1e-10
#endif
inline constexpr double kAwareInnerRelTol = MSH_AWARE_INNER_TOL;

// ∫ w(m) (v·m)⁺ D(m) sin θ dθ over the θ interval of the region at azimuth φ (up to the VNDF's constant
// G1(v)/v_z, which cancels). cone = false: the hemisphere region m·l > 0 with the hemisphere weight.
struct AwareIntegrand {
  Vec3d v, l;
  double inv_ax2, inv_ay2, axay, c;  // c: the cone's cosine (for the cone region); 0 for the hemisphere
  bool cone;
  DiffuseAwareForm form;
  double rel_tol;
  double sigma = 0;  // Oren–Nayar facets (oren_nayar_facet_weight) in the Reciprocal form; 0: Lambert

  // [lo, hi] ∩= {θ : x·m > cx} with x·m = p sin θ + q cos θ; false if empty.
  static bool clip(double p, double q, double cx, double& lo, double& hi) {
    const double R = std::hypot(p, q);
    if (!(R > cx)) return false;
    const double d = std::atan2(p, q), b = std::acos(std::min(1.0, cx / R));
    lo = std::max(lo, d - b), hi = std::min(hi, d + b);
    return hi > lo;
  }

  double operator()(double phi) const {
    const double pc = std::cos(phi), ps = std::sin(phi);
    const double pl = l.x * pc + l.y * ps, ql = l.z, pv = v.x * pc + v.y * ps, qv = v.z;
    double lo = 0, hi = cone ? std::acos(c) : 0.5 * kPi<double>;
    const double cl = cone ? c : 0.0;
    const double cv = (cone && form == DiffuseAwareForm::Reciprocal) ? c : 0.0;
    if (!clip(pl, ql, cl, lo, hi) || !clip(pv, qv, cv, lo, hi)) return 0.0;
    const double k = pc * pc * inv_ax2 + ps * ps * inv_ay2, al = 1 / std::sqrt(k);
    const auto to_u = [&](double th) { return std::atan2(std::sin(th), al * std::cos(th)); };
    const auto g = [&](double u) {
      const double su = std::sin(u), cu = std::cos(u);
      const double th = std::atan2(al * su, cu), st = std::sin(th), ct = std::cos(th);
      const double ml = pl * st + ql * ct;
      if (!(ml > 0)) return 0.0;
      double w = ml;
      if (form == DiffuseAwareForm::Flux) w *= cone ? lambert_cap_fraction(ct, c) : 0.5 * (1 + ct);
      if (form == DiffuseAwareForm::Reciprocal && sigma > 0)
        w *= oren_nayar_facet_weight(sigma, Vec3d(st * pc, st * ps, ct), l, v);
      return w * std::max(0.0, al * su * pv + cu * qv) * su;
    };
    double s = 0;
    // The Lambertian cap fraction has a kink where the cap touches the facet's horizon (θ = π/2 − acos c).
    const double kink = 0.5 * kPi<double> - std::acos(c);
    if (form == DiffuseAwareForm::Flux && cone && kink > lo && kink < hi) {
      s = gauss_kronrod(g, to_u(lo), to_u(kink), 0.0, rel_tol) +
          gauss_kronrod(g, to_u(kink), to_u(hi), 0.0, rel_tol);
    } else {
      s = gauss_kronrod(g, to_u(lo), to_u(hi), 0.0, rel_tol);
    }
    return s / (kPi<double> * axay * k);
  }
};

inline double aware_region(const GGX<double>& ggx, const Vec3d& v, const Vec3d& l, double c, bool cone,
                           DiffuseAwareForm form, double abs_tol, double sigma = 0) {
  const AwareIntegrand f{v,
                         l,
                         1 / sqr(ggx.alpha_x()),
                         1 / sqr(ggx.alpha_y()),
                         ggx.alpha_x() * ggx.alpha_y(),
                         cone ? c : 0.0,
                         cone,
                         form,
                         1e-10,
                         sigma};
  double bp[64];
  int nb = region_breakpoints(v, l, cone ? c : 0.0, bp);
  if (cone && form == DiffuseAwareForm::Reciprocal) {
    double b2[24];
    const int n2 = region_breakpoints(l, v, c, b2);  // the v-cone's breakpoints (roles swapped)
    for (int i = 0; i < n2 && nb < 60; ++i) bp[nb++] = b2[i];
  }
  return integrate_panels(f, bp, nb, abs_tol);
}

}  // namespace aware_quadrature

// Exact diffuse-aware term at full vectors (anisotropic GGX, αx along x): cone / hemisphere integrals of the
// DiffuseAwareForm weights over the VNDF of v. V = 0 or the early-out 2V + N·L < 1 → 0; V = 1 → 1; v.z < 0
// mirrored; NaN/Inf → 0. rel_tol bounds the quadrature error relative to the denominator (measured in
// docs/micro-shadowing-aware.md). facet_sigma > 0: Oren–Nayar facets in the Reciprocal form (§3.1; the Flux
// form keeps Lambert facets); NaN → 0.
inline double diffuse_aware_exact(double V, double alpha_x, double alpha_y, const Vec3d& v, const Vec3d& l,
                                  DiffuseAwareForm form, double rel_tol = 1e-7, double facet_sigma = 0) {
  if (!is_finite(v) || !is_finite(l) || std::isnan(alpha_x) || std::isnan(alpha_y)) return 0.0;
  const double sg = std::isnan(facet_sigma) ? 0.0 : std::clamp(facet_sigma, 0.0, 10.0);
  const double vis = saturate(V);
  Vec3d vn = normalize(v), ln = normalize(l);
  if (vn.z < 0) vn = -vn;
  if (exact_zero(vis, ln.z) || vis == 0.0 || !(ln.z > -1)) return 0.0;
  if (vis == 1.0) return 1.0;
  const GGX<double> ggx(std::min(alpha_x, 1e4), std::min(alpha_y, 1e4));
  const double c = cone_cos_from_visibility(vis);
  const double den = aware_quadrature::aware_region(ggx, vn, ln, c, false, form, 1e-9, sg);
  if (!(den > 1e-300)) return 0.0;
  const double num = aware_quadrature::aware_region(ggx, vn, ln, c, true, form, rel_tol * den, sg);
  return saturate(num / den);
}

// Isotropic GGX: the diffuse-aware term averaged over φ ∈ [0, π] with the diffuse lobe's own weight (the
// Lambertian-microfacet radiance, i.e. the hemisphere integral), ∫ num dφ / ∫ den dφ; v = (sin θv, 0, N·V),
// l = (sin θl cos φ, sin θl sin φ, N·L). Two-panel adaptive Gauss–Kronrod as generic_vndf_exact_azimuth_mean.
inline double diffuse_aware_exact_azimuth_mean(double V, double alpha, double n_dot_l, double n_dot_v,
                                               DiffuseAwareForm form, double rel_tol = 1e-6) {
  if (std::isnan(alpha)) return 0.0;
  const double vis = saturate(V);
  const double nl = input_domain::clamp_nan(n_dot_l, 0.0, 1.0),
               nv = input_domain::clamp_nan(n_dot_v, 0.0, 1.0);
  if (exact_zero(vis, nl) || vis == 0.0 || !(nl > 0)) return 0.0;
  if (vis == 1.0) return 1.0;
  const Vec3d v(safe_sqrt(1 - nv * nv), 0, std::max(nv, 1e-6));
  const double sl = safe_sqrt(1 - nl * nl), c = cone_cos_from_visibility(vis);
  const GGX<double> ggx(std::min(alpha, 1e4));
  const auto nd = [&](double phi) {
    const Vec3d l(sl * std::cos(phi), sl * std::sin(phi), nl);
    const double den = aware_quadrature::aware_region(ggx, v, l, c, false, form, 1e-9);
    return std::array<double, 2>{aware_quadrature::aware_region(ggx, v, l, c, true, form, rel_tol * den),
                                 den};
  };
  if (nv == 1.0 || sl == 0.0) {
    const auto r = nd(0.0);
    return r[1] > 0 ? saturate(r[0] / r[1]) : 0.0;
  }
  const double h = 0.5 * kPi<double>;
  const double d0 = nd(0.0)[1];
  const auto a = gauss_kronrod_adaptive<2>(nd, 0.0, h, rel_tol * d0 * h);
  const auto b = gauss_kronrod_adaptive<2>(nd, h, 2 * h, rel_tol * d0 * h);
  const double den = a[1] + b[1];
  return den > 0 ? saturate((a[0] + b[0]) / den) : 0.0;
}

// Reference for specular_aware_azimuth_mean: ∫ S(φ) D(h(φ)) dφ / ∫ D(h(φ)) dφ over [0, π] by adaptive
// Gauss–Kronrod of D(h) (GGX NDF, microfacet/ggx.h) split at the jumps of S, found on a 4096-point grid and
// refined by bisection on the indicator itself (not by the closed form's cos φ thresholds).
inline double specular_aware_azimuth_mean_quadrature(double V, double alpha, double n_dot_l, double n_dot_v,
                                                     double tol = 1e-12) {
  const double cl = input_domain::clamp_nan(n_dot_l, 0.0, 1.0),
               cv = input_domain::clamp_nan(n_dot_v, 0.0, 1.0);
  if (!(cl > 0) || !(cv > 0)) return 0.0;
  const GGX<double> ggx(std::clamp(alpha, 1e-4, 1.0));
  const Vec3d v(safe_sqrt(1 - cv * cv), 0, cv);
  const double sl = safe_sqrt(1 - cl * cl);
  const auto L = [&](double p) { return Vec3d(sl * std::cos(p), sl * std::sin(p), cl); };
  const auto S = [&](double p) { return specular_aware(V, v, L(p)); };
  const auto D = [&](double p) { return ggx.D(normalize(v + L(p))); };
  // Jumps of S on a fine grid, refined by bisection.
  double cuts[8];
  int nc = 0;
  const int n = 4096;
  double prev = S(0.0);
  for (int i = 1; i <= n && nc < 6; ++i) {
    const double b = kPi<double> * i / n, sb = S(b);
    if (sb != prev) {
      double a = kPi<double> * (i - 1) / n, hi = b;
      for (int it = 0; it < 60; ++it) {
        const double m = 0.5 * (a + hi);
        (S(m) == prev ? a : hi) = m;
      }
      cuts[nc++] = 0.5 * (a + hi);
    }
    prev = sb;
  }
  double pts[10];
  int np = 0;
  pts[np++] = 0;
  for (int i = 0; i < nc; ++i) pts[np++] = cuts[i];
  pts[np++] = kPi<double>;
  double num = 0, den = 0;
  for (int i = 0; i + 1 < np; ++i) {
    const double part = gauss_kronrod(D, pts[i], pts[i + 1], tol);
    den += part;
    if (S(0.5 * (pts[i] + pts[i + 1])) > 0) num += part;
  }
  return den > 0 ? saturate(num / den) : 0.0;
}

}  // namespace msh::micro_shadowing
