// Exact reference (not for an engine) of the generic VNDF-based micro-shadowing term (Zurita 2026, "Improving
// Direct Lighting Material Occlusion - Part 2", GenericM_g) for the Beckmann–Spizzichino + V-cavity
// microsurface (microfacet/vcavity.h), in double precision.
//
// For the V-cavity the weight G2(v,l,m)/G1(v,m) depends on m, so it does not cancel in the ratio:
//   GenericM_g = ∫_{n·m > c, m·l > c} D_v(m) G2/G1(v,m) dm / ∫_{m·l > 0} D_v(m) G2/G1(v,m) dm
//              = ∫_{n·m > c, m·l > c} (v·m)⁺ D(m) G2(v,l,m) dm / ∫_{m·l > 0} (v·m)⁺ D(m) G2(v,l,m) dm,
// since D_v(m) = G1(v,m)(v·m)⁺D(m)/(n·v). In spherical coordinates (θ, φ) of m, with t = tanθ and
// a_w = w_t·(cos φ, sin φ):
//   (v·m) D(m) sinθ dθ = (a_v t² + z_v t) e^{−k t²} dt / (π αx αy),   G1(w, m) = min(1, 2 z_w / (a_w t +
//   z_w))
// (k = cos²φ/αx² + sin²φ/αy²), so at a fixed φ the θ range is the same as for the Smith term (the region and
// the (v·m)⁺ clip of reference/micro_shadowing_exact.h) and the integrand is smooth between the points
// t = z_w / a_w where a G1 leaves 1. That inner integral is an adaptive Gauss–Kronrod in s = √k t (s ≤ 9:
// e^{−81} is below double's resolution of the sum); the outer φ integral reuses the exact term's panels
// (closed-form kinks and square-root points) plus the two azimuths where min(G1(v), G1(l)) switches branch
// (z_v a_l = z_l a_v).
#pragma once

#include <microshadow/microfacet/vcavity.h>
#include <microshadow/reference/micro_shadowing_exact.h>

#include <algorithm>
#include <array>
#include <cmath>

namespace msh::micro_shadowing {

namespace vcavity_quadrature {
using namespace exact_quadrature;  // the exact term's azimuth slices and panel integrators

// Integrand over the azimuth φ of m for the V-cavity: ∫ (v·m)⁺ D(m) G2(v,l,m) sinθ dθ over
// {θ < theta_max ∧ m·l > c}, without the constant 1/(π αx αy). v.z > 0, l.z > 0 (the V-cavity G1 is 0
// for directions below the horizon), unit vectors.
struct VCavityIntegrand {
  Vec3d v, l;
  double inv_ax2, inv_ay2, c, theta_max, abs_tol;
  bool uncorrelated = false;  // weight G1(v,m)G1(l,m) instead of min(G1(v,m), G1(l,m))

  double operator()(double phi) const {
    const AzimuthSlice z = azimuth_slice(v, l, inv_ax2, inv_ay2, c, theta_max, phi);
    if (z.empty) return 0.0;
    const double a = z.a, b = z.b, p = z.p, q = z.q, lo = z.lo, hi = z.hi, sk = std::sqrt(z.k);
    constexpr double kSMax = 9.0;
    const auto s_of = [&](double th) {
      const double ct = std::cos(th);
      return ct > 1e-300 ? std::min(kSMax, sk * std::sin(th) / ct) : kSMax;
    };
    const double s_lo = s_of(lo), s_hi = s_of(hi);
    if (!(s_hi > s_lo)) return 0.0;
    // Panel ends: where G1(v, m) or G1(l, m) leaves 1 (t = z_w / a_w for a_w > 0).
    double pts[4] = {s_lo, s_hi, s_hi, s_hi};
    int np = 2;
    for (const double sw : {a > 0 ? sk * b / a : -1.0, p > 0 ? sk * q / p : -1.0})
      if (sw > s_lo && sw < s_hi) pts[np++] = sw;
    for (int i = 1; i < np; ++i)  // insertion sort of ≤ 4 values
      for (int j = i; j > 0 && pts[j] < pts[j - 1]; --j) std::swap(pts[j], pts[j - 1]);
    const double inv_sk = 1 / sk;
    const auto g = [&](double s) {
      const double t = s * inv_sk;
      const double vm = a * t + b, lm = p * t + q;  // (v·m)/cosθ, (l·m)/cosθ
      if (!(vm > 0) || !(lm > 0)) return std::array<double, 1>{0.0};
      const double g1v = std::min(1.0, 2 * b / vm), g1l = std::min(1.0, 2 * q / lm);
      const double g2 = uncorrelated ? g1v * g1l : std::min(g1v, g1l);
      return std::array<double, 1>{vm * t * std::exp(-s * s) * g2 * inv_sk};
    };
    double sum = 0;
    for (int i = 0; i + 1 < np; ++i)
      if (pts[i + 1] > pts[i]) sum += gauss_kronrod_adaptive<1>(g, pts[i], pts[i + 1], abs_tol)[0];
    return sum;
  }

  // Azimuths where min(G1(v, m), G1(l, m)) changes branch for every θ beyond both thresholds:
  // (z_v l_t − z_l v_t)·(cos φ, sin φ) = 0.
  int extra_breakpoints(double* out) const {
    const double ux = v.z * l.x - l.z * v.x, uy = v.z * l.y - l.z * v.y;
    if (!(std::hypot(ux, uy) > 1e-12)) return 0;
    const double ph = std::atan2(uy, ux);
    out[0] = ph - 0.5 * kPi<double>, out[1] = ph + 0.5 * kPi<double>;
    return 2;
  }
};

// ∫ over {n·m > c ∧ m·l > c} of (v·m)⁺ D(m) G2(v,l,m) dm (c = 0: the hemisphere), up to 1/(π αx αy).
inline double vcavity_region_mass(const BeckmannVCavity<double>& vc, const Vec3d& v, const Vec3d& l, double c,
                                  bool uncorrelated, double abs_tol) {
  // The inner tolerance is a small share of the outer one (the φ range is 2π).
  const VCavityIntegrand f{
      v, l, 1 / sqr(vc.alpha_x()), 1 / sqr(vc.alpha_y()), c, std::acos(c), abs_tol * 0.02, uncorrelated};
  return integrate_region(f, abs_tol);
}

}  // namespace vcavity_quadrature

// Exact GenericM_g for the Beckmann–Spizzichino + V-cavity microsurface (αx along x, αy along y) at full
// vectors, with the weight G2/G1 of `form`: G2Form::HeightCorrelated uses the V-cavity's own (correlated)
// G2 = min(G1(v,m), G1(l,m)) (Cook–Torrance), G2Form::Uncorrelated G1(v,m)G1(l,m). rel_tol bounds the
// quadrature's error estimate relative to the denominator. v.z < 0 is mirrored (as the sampler does), n·v <
// 1e-7 is raised to 1e-7 (the grazing limit);
// l.z ≤ 0 gives 0 (the V-cavity shadows every facet from a light below the horizon); non-unit vectors are
// normalized; NaN or Inf inputs give 0.
inline double generic_vcavity_exact(double V, const BeckmannVCavity<double>& vc, const Vec3d& v,
                                    const Vec3d& l, G2Form form = G2Form::HeightCorrelated,
                                    double rel_tol = 1e-7) {
  if (!is_finite(v) || !is_finite(l) || std::isnan(vc.alpha_x()) || std::isnan(vc.alpha_y())) return 0.0;
  const double vis = saturate(V);
  Vec3d vn = normalize(v), ln = normalize(l);
  if (vn.z < 0) vn = -vn;
  if (exact_zero(vis, ln.z) || vis == 0.0 || !(ln.z > 0)) return 0.0;
  // Grazing v: both masses vanish like n·v and the ratio has a limit; n·v is raised to 1e-7 to reach it.
  if (!(vn.z >= 1e-7)) vn = normalize(Vec3d(vn.x, vn.y, 1e-7), Vec3d(0, 0, 1));
  const BeckmannVCavity<double> d(Beckmann<double>(std::min(vc.alpha_x(), 1e4), std::min(vc.alpha_y(), 1e4)));
  // The unnormalized mass is at most π αx αy z_v (the VNDF's normalization): tolerances relative to it.
  const bool unc = form == G2Form::Uncorrelated;
  const double scale = kPi<double> * d.alpha_x() * d.alpha_y() * vn.z;
  const double den = vcavity_quadrature::vcavity_region_mass(d, vn, ln, 0.0, unc, 1e-3 * rel_tol * scale);
  if (!(den > 0)) return 0.0;
  if (vis == 1.0) return 1.0;
  const double c = cone_cos_from_visibility(vis);
  const double num = vcavity_quadrature::vcavity_region_mass(d, vn, ln, c, unc, rel_tol * den);
  return saturate(num / den);
}

// Mean over the relative azimuth φ (uniform) of generic_vcavity_exact with v = (sin θv cos φv, sin θv sin φv,
// N·V) and l at azimuth φv + φ, as generic_vndf_exact_azimuth_mean does for the Smith NDFs (the same panels
// and symmetry). N·L ∈ [−1, 1], N·V ∈ [0, 1] (|N·V| is used).
inline double generic_vcavity_exact_azimuth_mean(double V, const BeckmannVCavity<double>& vc, double n_dot_l,
                                                 double n_dot_v, double phi_v = 0.0,
                                                 G2Form form = G2Form::HeightCorrelated,
                                                 double abs_tol = 1e-5, double rel_tol = 1e-6) {
  if (std::isnan(vc.alpha_x()) || std::isnan(vc.alpha_y()) || !std::isfinite(phi_v)) return 0.0;
  const double vis = saturate(V);
  const double nl = input_domain::clamp_nan(n_dot_l, -1.0, 1.0);
  const double nv = input_domain::clamp_nan(std::abs(n_dot_v), 0.0, 1.0);
  if (exact_zero(vis, nl) || vis == 0.0 || !(nl > 0)) return 0.0;
  const double sv = std::sqrt(std::max(0.0, 1 - nv * nv)), sl = std::sqrt(std::max(0.0, 1 - nl * nl));
  if (sv == 0.0) phi_v = 0.0;
  const Vec3d v(sv * std::cos(phi_v), sv * std::sin(phi_v), nv);
  const auto at = [&](double phi) {
    return generic_vcavity_exact(
        vis, vc, v, Vec3d(sl * std::cos(phi_v + phi), sl * std::sin(phi_v + phi), nl), form, rel_tol);
  };
  if (sl == 0.0 || vis == 1.0) return at(0.0);
  const double q = phi_v / (0.5 * kPi<double>);
  const bool symmetric = vc.ndf().is_isotropic() || std::abs(q - std::round(q)) < 1e-12;
  return exact_quadrature::azimuth_mean(at, symmetric, abs_tol);
}

}  // namespace msh::micro_shadowing
