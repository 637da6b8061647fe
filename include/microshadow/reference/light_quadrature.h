// Deterministic quadrature of a directional integrand over the solid angle of a light: a spherical cap
// (sphere light) or a planar rectangle, by nested adaptive Gauss–Kronrod (math/quadrature.h). The reference
// of the LTC verification (docs/ltc.md): ∫_light f(v, l) (n·l)⁺ dl with the GGX BRDF, and ∫_light D_ltc. The
// integrand is any callable g(l) of a unit direction; where it has a kink (the horizon crossing the light)
// the adaptive rule refines around it. Passes the analytic cases of tests/test_ltc.cpp (form factors of a
// sphere, clipped or not, Snyder 1996, and of a rectangle, Howell's catalogue C-11).
#pragma once

#include <microshadow/math/quadrature.h>
#include <microshadow/math/vec.h>

namespace msh::reference {

// ∫ over the cap of axis `axis` (unit) and angular radius sigma ∈ (0, π/2] of g(l) dl, in polar coordinates
// about the axis (θ ∈ [0, σ], φ ∈ [0, 2π] split into four panels). rel_tol: relative accuracy of each 1D
// rule.
template <class G>
double integrate_cap(const G& g, const Vec3d& axis, double sigma, double rel_tol = 1e-7,
                     double abs_tol = 1e-13) {
  const Framed f = Framed::from_z(axis);
  auto inner = [&](double th) {
    const double st = std::sin(th), ct = std::cos(th);
    auto gp = [&](double ph) { return g(f.to_world(Vec3d(st * std::cos(ph), st * std::sin(ph), ct))); };
    double s = 0;
    for (int q = 0; q < 4; ++q)
      s += gauss_kronrod(gp, q * 0.5 * kPi<double>, (q + 1) * 0.5 * kPi<double>, abs_tol, rel_tol);
    return s * st;
  };
  return gauss_kronrod(inner, 0.0, sigma, abs_tol, rel_tol);
}

// ∫ over the rectangle c + s·ex + t·ey, |s| ≤ hx, |t| ≤ hy (ex, ey orthonormal; c relative to the shading
// point, the plane not through it) of g(l) dl, with dl = |n_L·p| / |p|³ ds dt.
template <class G>
double integrate_rect(const G& g, const Vec3d& c, const Vec3d& ex, const Vec3d& ey, double hx, double hy,
                      double rel_tol = 1e-7, double abs_tol = 1e-13) {
  const Vec3d nl = cross(ex, ey);
  auto inner = [&](double s) {
    auto gt = [&](double t) {
      const Vec3d p = c + ex * s + ey * t;
      const double d2 = dot(p, p), d = std::sqrt(d2);
      return g(p / d) * std::abs(dot(nl, p)) / (d2 * d);
    };
    return gauss_kronrod(gt, -hy, 0.0, abs_tol, rel_tol) + gauss_kronrod(gt, 0.0, hy, abs_tol, rel_tol);
  };
  return gauss_kronrod(inner, -hx, 0.0, abs_tol, rel_tol) + gauss_kronrod(inner, 0.0, hx, abs_tol, rel_tol);
}

// Closed forms for the tests and the CLI's self-check (Lambertian receiver, n = +z):
// form factor of a sphere of angular radius σ whose centre is at elevation cos ω = n·c, clipped by the
// horizon (Snyder 1996, "Area light sources for real-time graphics"; the form of Lagarde & de Rousiers 2014,
// "Moving Frostbite to PBR", eq. 19, divided by π).
inline double sphere_form_factor(double cos_omega, double sin_sigma) {
  const double s2 = sin_sigma * sin_sigma;
  if (cos_omega * cos_omega > s2) return cos_omega > 0 ? s2 * cos_omega : 0.0;
  const double sin_omega = std::sqrt(std::max(0.0, 1.0 - cos_omega * cos_omega));
  const double x = std::sqrt(1.0 / s2 - 1.0);
  const double y = -x * cos_omega / sin_omega;
  const double sy = sin_omega * std::sqrt(std::max(0.0, 1.0 - y * y));
  return std::max(0.0, ((cos_omega * std::acos(std::clamp(y, -1.0, 1.0)) - x * sy) * s2 + std::atan(sy / x)) /
                           kPi<double>);
}

// Form factor from a differential area to a parallel rectangle a × b at height h with one corner above it
// (Howell, "A Catalog of Radiation Heat Transfer Configuration Factors", C-11).
inline double rect_corner_form_factor(double a, double b, double h) {
  const double x = a / h, y = b / h, sx = std::sqrt(1 + x * x), sy = std::sqrt(1 + y * y);
  return (x / sx * std::atan(y / sx) + y / sy * std::atan(x / sy)) / (2 * kPi<double>);
}

}  // namespace msh::reference
