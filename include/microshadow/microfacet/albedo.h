// Directional albedo of the single-scattering GGX microfacet BRDF with F = 1 and the height-correlated Smith
// G2:
//   E(μ, α) = ∫_{H²} D(h) G2(v, l) / (4μ) dl,   v = (sqrt(1 − μ²), 0, μ)   (RTR4 9.8 with 9.34, 9.31, 9.41)
// by deterministic quadrature, in double whatever T is.
//
// How: l is parameterized by (z = cos θl, φl) ∈ [0,1] × [0,π] (dl = dz dφ; the integrand is even in φl, hence
// the factor 2). It is smooth on the closed hemisphere (v·h > 0 and l·h > 0 for all l there) except for two
// features of width ~α: the peak at the mirror direction (z = μ, φl = π) and the rise of G1(l) near z = 0.
// Both axes get breakpoints graded geometrically (ratio 4) toward these points, from α²/16 out to the domain
// ends, so every panel is at most ~4× wider than its distance to a feature and the integrand is smooth on it
// at that scale; each panel gets a fixed 16-point Gauss-Legendre rule in both variables (tensor product). The
// result is a deterministic function of (μ, α). tests/test_microfacet_albedo.cpp checks ≤ 1e-6 against the
// closed form E(1, 1) = 1 − ln 2, Cycles' published table values, an independent quasi-Monte Carlo estimate,
// and a 2×-refined rule. Cost: ~0.5–5 ms per call (docs/microfacet.md).
//
// Domain: μ ∈ [0, 1] (clamped; μ = 0 returns 0, the limit), α ∈ [0, ∞) clamped below to GGX<T>::kMinAlpha.
#pragma once

#include <microshadow/math/quadrature.h>
#include <microshadow/math/vec.h>
#include <microshadow/microfacet/ggx.h>

#include <algorithm>
#include <vector>

namespace msh {

namespace albedo_quadrature {

// Breakpoints of [lo, hi] graded geometrically toward c (c itself included when inside): c ± w·4^j.
inline std::vector<double> graded_breaks(double lo, double hi, double c, double w, double ratio) {
  std::vector<double> b{lo, hi};
  if (c > lo && c < hi) b.push_back(c);
  for (double d = w; d < hi - lo; d *= ratio) {
    if (c - d > lo) b.push_back(c - d);
    if (c + d < hi) b.push_back(c + d);
  }
  std::sort(b.begin(), b.end());
  return b;
}

// The rule with its knobs: n_gl Gauss-Legendre nodes per panel, breakpoint grading `ratio` (> 1). Exposed so
// the tests can compare against a refined rule.
inline double ggx_directional_albedo_rule(double mu, double alpha, int n_gl, double ratio) {
  const double m = clamp(mu, 0.0, 1.0);
  if (!(m > 0.0)) return 0.0;
  const GGX<double> g(alpha == alpha ? alpha : 0.0);
  const double a = g.alpha_x();
  const Vec3d v(std::sqrt(std::max(0.0, 1.0 - m * m)), 0.0, m);
  auto f = [&](double z, double phi) {
    const Vec3d l = spherical_direction(z, phi);
    const Vec3d h = normalize(v + l);
    return g.D(h) * g.G2(v, l);
  };
  const double w = std::max(a * a / 16.0, 1e-12);
  std::vector<double> zb = albedo_quadrature::graded_breaks(0.0, 1.0, m, w, ratio);
  for (double d = w; d < 1.0; d *= ratio) zb.push_back(d);  // toward z = 0 (grazing l)
  std::sort(zb.begin(), zb.end());
  zb.erase(std::unique(zb.begin(), zb.end()), zb.end());
  const std::vector<double> pb = albedo_quadrature::graded_breaks(0.0, kPi<double>, kPi<double>, w, ratio);
  static const GaussLegendre rule16(16);
  const GaussLegendre gl_other(n_gl == 16 ? 1 : n_gl);
  const GaussLegendre& gl = n_gl == 16 ? rule16 : gl_other;
  // Node lists of the two composite rules.
  std::vector<double> zn, zw, pn, pw;
  auto nodes = [&](const std::vector<double>& b, std::vector<double>& xs, std::vector<double>& ws) {
    for (size_t i = 0; i + 1 < b.size(); ++i) {
      const double c = 0.5 * (b[i] + b[i + 1]), h = 0.5 * (b[i + 1] - b[i]);
      for (size_t k = 0; k < gl.x.size(); ++k) xs.push_back(c + h * gl.x[k]), ws.push_back(h * gl.w[k]);
    }
  };
  nodes(zb, zn, zw);
  nodes(pb, pn, pw);
  double sum = 0.0;
  for (size_t i = 0; i < pn.size(); ++i) {
    double s = 0.0;
    for (size_t j = 0; j < zn.size(); ++j) s += zw[j] * f(zn[j], pn[i]);
    sum += pw[i] * s;
  }
  return 2.0 * sum / (4.0 * m);
}

}  // namespace albedo_quadrature

template <class T>
T ggx_directional_albedo(T mu, T alpha) {
  return T(albedo_quadrature::ggx_directional_albedo_rule(double(mu), double(alpha), 16, 4.0));
}

}  // namespace msh
