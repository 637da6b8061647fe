// Exact (deterministic quadrature, double precision) area-light micro-shadowing: a point-wise term M(l)
// averaged over the solid angle Ω of a light, weighted by what the receiver does with each direction,
//
//   M_area = ∫_Ω M(l) f(v, l) (n·l)⁺ dl / ∫_Ω f(v, l) (n·l)⁺ dl,
//
// f = 1 for a Lambertian receiver, f = the GGX specular BRDF D G2 / (4 (n·v)(n·l)) (Fresnel = 1; it is
// near-constant over a light and would only reweight) for a specular one. Not for an engine: it is the
// reference the fast forms (occlusion/micro_shadowing_area.h), the shaders and the renderer are measured
// against. Definitions, fast forms and measured errors: docs/area-lights.md.
//
// Conventions: local shading frame n = +z (docs/theory.md §1); every light is given as SEEN FROM THE
// SHADING POINT by unit directions in that frame (only the solid angle matters, so distances are in units
// of the distance to the light's centre):
//   Cap  {center, radius}: spherical cap, unit centre direction, angular radius ∈ [0, π/2] (a sphere light;
//        also a disk light that faces the point: its edge seen at angle ρ is the cap of radius ρ, exactly).
//   Disk {center, normal, radius}: a planar disk whose centre is at distance 1 along the unit `center`,
//        with unit `normal` (either sign) and radius `radius` (disk radius / distance). Its outline as seen
//        is a conic, not a circle, unless normal = ±center (then use disk_facing()).
//   Quad {corners}: four unit corner directions in order around the edge (either winding) of a planar
//        convex quadrilateral, e.g. a rectangle light (rect_light()); its edges are great-circle arcs.
// Lights that cross the horizon are clipped by the (n·l)⁺ weight; a light entirely below the horizon has
// no weight and M_area is defined as 0. A light of zero size (radius 0, or a quad with coincident corners)
// returns the point value M(center) exactly, so the area form reduces to today's point terms.
//
// Quadrature (derivation: docs/area-lights.md §2). Every term of occlusion/micro_shadowing.h jumps or
// kinks only on circles of constant n·l (the visibility cone n·l = cos_t, the early-out n·l = 1 − 2V, the
// kinks of the older terms), as does the horizon. So the integral runs in the polar coordinates of n,
// dl = dz dφ with z = n·l:
//   * outer: z ∈ [0, 1], split at the term's circles, at the z where the light's outline is tangent to a
//     circle of constant z (cap: cos(θc ± ρ); quad: corners and the extreme z of each edge; disk: the
//     stationary points of z along the rim, roots of a trigonometric quartic) and, for a GGX receiver, at the
//     mirror direction's z; each panel by adaptive Gauss–Kronrod (math/quadrature.h) after the substitution
//     z = z0 + (z1 − z0)(3s² − 2s³), which turns the square-root endpoints of the φ-width into smooth ones;
//   * inner: on the circle of constant z the light is a set of φ-intervals in closed form (cap and quad:
//     arcs cos(φ − φ0) > t; disk: the roots of a trigonometric quartic); a term that depends on z only
//     with a Lambertian receiver needs no φ quadrature (the interval lengths), anything else is adaptive
//     Gauss–Kronrod over each interval, split at the GGX mirror azimuth.
// Both integrals are positive; the Gauss–Kronrod error criterion is panel-relative (rel_tol), so the ratio's
// relative error is bounded by about 2·rel_tol for integrands whose discontinuities are all declared.
#pragma once

#include <microshadow/math/quadrature.h>
#include <microshadow/math/vec.h>
#include <microshadow/microfacet/ggx.h>
#include <microshadow/occlusion/micro_shadowing.h>
#include <microshadow/occlusion/micro_shadowing_area.h>
#include <microshadow/occlusion/micro_shadowing_aware.h>
#include <microshadow/reference/micro_shadowing_aware_exact.h>
#include <microshadow/reference/micro_shadowing_exact.h>

#include <algorithm>
#include <array>
#include <cmath>
#include <complex>
#include <type_traits>
#include <utility>
#include <vector>

namespace msh::area {

// ---- light shapes (as seen from the shading point, local frame n = +z) -----------------------------------

struct Cap {
  Vec3d center{0, 0, 1};  // unit centre direction
  double radius = 0;      // angular radius ρ ∈ [0, π/2]
};

struct Disk {
  Vec3d center{0, 0, 1};   // unit direction to the disk's centre (at distance 1)
  Vec3d normal{0, 0, -1};  // unit normal of the disk (either sign)
  double radius = 0;       // disk radius / distance to its centre, ≥ 0
};

struct Quad {
  std::array<Vec3d, 4> corners{};  // unit corner directions, in order around the edge (either winding)
};

// One of the three (a tagged union without <variant>, which the header-only core does not use): built
// implicitly from a Cap, Disk or Quad.
struct Shape {
  enum class Kind { Cap, Disk, Quad };
  Kind kind = Kind::Cap;
  Cap cap;
  Disk disk;
  Quad quad;
  Shape() = default;
  Shape(const Cap& c) : kind(Kind::Cap), cap(c) {}     // NOLINT(google-explicit-constructor)
  Shape(const Disk& d) : kind(Kind::Disk), disk(d) {}  // NOLINT(google-explicit-constructor)
  Shape(const Quad& q) : kind(Kind::Quad), quad(q) {}  // NOLINT(google-explicit-constructor)
};

// A disk facing the shading point (normal = −center) whose edge is seen at angular radius ρ: exactly the
// spherical cap of radius ρ.
inline Cap disk_facing(const Vec3d& center, double edge_angle) { return Cap{normalize(center), edge_angle}; }

// A rectangle light centred at distance 1 along `center`, spanned by the orthonormal axes u, w (units of
// the distance), half-extents half_u, half_w: its four corner directions.
inline Quad rect_light(const Vec3d& center, const Vec3d& u, const Vec3d& w, double half_u, double half_w);
// The rectangle c ± half_u·u ± half_w·w with its centre c at any distance (not 0; the plane not through the
// shading point), e.g. a rectangle light given in world units relative to the point.
inline Quad rect_quad(const Vec3d& c, const Vec3d& u, const Vec3d& w, double half_u, double half_w) {
  return Quad{{normalize(c + half_u * u + half_w * w), normalize(c - half_u * u + half_w * w),
               normalize(c - half_u * u - half_w * w), normalize(c + half_u * u - half_w * w)}};
}
inline Quad rect_light(const Vec3d& center, const Vec3d& u, const Vec3d& w, double half_u, double half_w) {
  return rect_quad(normalize(center), u, w, half_u, half_w);
}

// The frame of a light facing the shading point: u0 ⟂ center in the plane of (n, center), pointing away
// from n (x at the pole), w0 = center × u0, turned by `roll` about the centre direction.
inline std::pair<Vec3d, Vec3d> facing_axes(const Vec3d& center, double roll) {
  const Vec3d c = normalize(center);
  const Vec3d p = c.z * c - Vec3d(0, 0, 1);
  const Vec3d u0 = length(p) > 1e-12 ? normalize(p) : Vec3d(1, 0, 0);
  const Vec3d w0 = cross(c, u0);
  const Vec3d u = std::cos(roll) * u0 + std::sin(roll) * w0;
  return {u, cross(c, u)};
}

// A rectangle centred at distance 1 along `center` with half-extents tan(ang_u), tan(ang_w) (so seen at
// angular half-extents ang_u, ang_w < π/2 from its centre when it faces the point), its u axis turned by
// `roll` about the centre direction (facing_axes), then the plane tilted by `tilt` ∈ (−π/2, π/2) about its
// w axis (tilt 0: facing the point; positive tilt turns the normal toward n for roll 0).
inline Quad rect_tilted(const Vec3d& center, double ang_u, double ang_w, double tilt = 0, double roll = 0) {
  const Vec3d c = normalize(center);
  const auto [u, w] = facing_axes(c, roll);
  const Vec3d ut = std::cos(tilt) * u + std::sin(tilt) * c;
  return rect_light(c, ut, w, std::tan(ang_u), std::tan(ang_w));
}
inline Quad rect_facing(const Vec3d& center, double ang_u, double ang_w, double roll = 0) {
  return rect_tilted(center, ang_u, ang_w, 0, roll);
}

// A disk centred at distance 1 along `center`, radius tan(edge_angle) (seen at angular radius edge_angle
// when facing), its normal tilted by `tilt` ∈ (−π/2, π/2) from −center about the w axis of
// facing_axes(center, roll).
inline Disk disk_tilted(const Vec3d& center, double edge_angle, double tilt = 0, double roll = 0) {
  const Vec3d c = normalize(center);
  const Vec3d u = facing_axes(c, roll).first;
  const Vec3d ut = std::cos(tilt) * u + std::sin(tilt) * c;
  return Disk{c, normalize(cross(ut, facing_axes(c, roll).second)), std::tan(edge_angle)};
}

// ---- receivers -----------------------------------------------------------------------------------------

struct Receiver {
  enum class Kind { Lambert, GGX };
  Kind kind = Kind::Lambert;
  double alpha_x = 0.25, alpha_y = 0.25;  // GGX α (clamped to GGX::kMinAlpha)
  Vec3d v{0, 0, 1};                       // unit view direction, v.z > 0 (GGX only)

  static Receiver lambert() { return {}; }
  static Receiver ggx(double alpha, const Vec3d& v) { return ggx(alpha, alpha, v); }
  static Receiver ggx(double ax, double ay, const Vec3d& v) {
    Receiver r;
    r.kind = Kind::GGX, r.alpha_x = ax, r.alpha_y = ay, r.v = normalize(v);
    return r;
  }
  // f(v, l)(n·l)⁺ up to a constant factor: 1·z for Lambert, D(h) G2(v, l) / (4 n·v) for GGX; 0 for l.z ≤ 0.
  double weight(const Vec3d& l) const {
    if (!(l.z > 0)) return 0.0;
    if (kind == Kind::Lambert) return l.z;
    const GGX<double> g(alpha_x, alpha_y);
    const Vec3d h = normalize(v + l);
    return g.D(h) * g.G2(v, l) / (4 * std::max(v.z, 1e-12));
  }
};

// ---- point-wise terms -----------------------------------------------------------------------------------

// A curve on the sphere where a term jumps or kinks that is not a circle of constant n·l:
// {l : l·axis = k0 + k1 z + k2 z²}, z = n·l (e.g. the specular-aware term's l·v = 2c² − 1 and n·h = c, i.e.
// l·v = (z + n·v)²/(2c²) − 1). On each circle of constant z it meets at most two azimuths, in closed form;
// they become panel edges of the inner (φ) quadrature, and the z where it is tangent to a circle (found by
// a scan and bisection, or listed among the term's z_breaks) edges of the outer one.
struct AzimuthBreak {
  Vec3d axis{0, 0, 1};
  double k0 = 0, k1 = 0, k2 = 0;
  double k(double z) const { return k0 + z * (k1 + z * k2); }
};

// A point term: a callable M(l) → [0, 1] (double(const Vec3d&)), the values of z = n·l where it jumps or
// kinks (each becomes a panel edge), whether it depends on z only (then no φ quadrature is needed for a
// Lambertian receiver) and, for a term that depends on the azimuth, the curves where it jumps.
// Class template argument deduction: PointTerm{lambda, {breaks...}, z_only} or
// PointTerm{lambda, {breaks...}, false, {curves...}}.
template <class F>
struct PointTerm {
  F M;
  std::vector<double> z_breaks;
  bool z_only = false;
  std::vector<AzimuthBreak> phi_breaks = {};
};
template <class F>
PointTerm(F, std::vector<double>, bool) -> PointTerm<F>;
template <class F>
PointTerm(F, std::vector<double>, bool, std::vector<AzimuthBreak>) -> PointTerm<F>;

// The circles of constant n·l where a term of occlusion/micro_shadowing.h is not smooth: the cone
// cos_t = sqrt(1 − V) (reference step, Chan 2018), the early-out 1 − 2V (generic term), 1 − 2V² (Brinck–
// Maximov 2016) and sqrt(1 − V⁵) (Part 1). Used for callables whose own breaks are unknown (CLI registry).
inline std::vector<double> standard_z_breaks(double V) {
  const double v = saturate(V);
  return {micro_shadowing::cone_cos_from_visibility(v), 1 - 2 * v, 1 - 2 * v * v,
          std::sqrt(std::max(0.0, 1 - std::pow(v, 5)))};
}

// The closed-form terms of occlusion/micro_shadowing.h as point terms: M(V, n·l) with the z where each kinks.
// (A captureless term is a function pointer, so the four share one PointTerm type.)
inline auto closed_form_term(double V, double (*term)(double, double), std::vector<double> z_breaks) {
  return PointTerm{[V, term](const Vec3d& l) { return term(V, l.z); }, std::move(z_breaks), true};
}
inline auto reference_step_term(double V) {
  return closed_form_term(V, micro_shadowing::reference_step<double>,
                          {micro_shadowing::cone_cos_from_visibility(saturate(V))});
}
inline auto brinck_maximov_2016_term(double V) {
  const double v = saturate(V);
  return closed_form_term(V, micro_shadowing::brinck_maximov_2016<double>, {1 - 2 * v * v, 2 - 2 * v * v});
}
inline auto chan_2018_term(double V) {
  return closed_form_term(V, micro_shadowing::chan_2018<double>,
                          {micro_shadowing::cone_cos_from_visibility(saturate(V))});
}
inline auto part1_analytic_term(double V) {
  return closed_form_term(V, micro_shadowing::part1_analytic<double>,
                          {std::sqrt(std::max(0.0, 1 - std::pow(saturate(V), 5)))});
}
// The generic VNDF term (Zurita 2026b) at the full direction l, exact (micro_shadowing::generic_vndf_exact),
// view v.
inline auto generic_vndf_term(double V, double alpha_x, double alpha_y, const Vec3d& v,
                              double rel_tol = 1e-8) {
  return PointTerm{
      [=](const Vec3d& l) { return micro_shadowing::generic_vndf_exact(V, alpha_x, alpha_y, v, l, rel_tol); },
      {1 - 2 * saturate(V)},
      false};
}

// ---- the micro-BRDF-aware terms (occlusion/micro_shadowing_aware.h, docs/micro-shadowing-aware.md) -----

// Where the specular-aware indicator χ(n·h > c) χ(h·l > c) (c = sqrt(1 − V)) jumps, for the view v:
// h·l > c ⇔ l·v > 2c² − 1 (a circle about v), n·h > c ⇔ (z + n·v)² > 2c² (1 + l·v) (a curve
// l·v = (z + n·v)²/(2c²) − 1). Both are tangent to a circle of constant z where the azimuth-mean closed
// form's interval ends reach φ = 0 or π: θl = |2t − θv| and θl = θv + 2t (t = acos c, θv = acos n·v) — the
// kinks of the azimuth mean.
inline std::vector<double> specular_aware_z_breaks(double V, double n_dot_v) {
  std::vector<double> z;
  for (double k : micro_shadowing::specular_aware_kinks(V, n_dot_v))
    if (k > -1) z.push_back(k);
  return z;
}
inline std::vector<AzimuthBreak> specular_aware_curves(double V, const Vec3d& v) {
  const double c = micro_shadowing::cone_cos_from_visibility(saturate(V)), c2 = std::max(c * c, 1e-300);
  const Vec3d vn = normalize(v);
  return {AzimuthBreak{vn, 2 * c * c - 1, 0, 0},
          AzimuthBreak{vn, vn.z * vn.z / (2 * c2) - 1, vn.z / c2, 1 / (2 * c2)}};
}

// The specular-aware term at the full direction l (view v): an indicator whose jumps are all panel edges.
inline auto specular_aware_term(double V, const Vec3d& v) {
  const Vec3d vn = normalize(v);
  return PointTerm{[V, vn](const Vec3d& l) { return micro_shadowing::specular_aware(V, vn, l); },
                   specular_aware_z_breaks(V, vn.z), false, specular_aware_curves(V, vn)};
}
// Its GGX-lobe-weighted azimuth mean (closed form; in float: the shaders' form), a function of z only.
template <class T = double>
auto specular_aware_azimuth_mean_term(double V, double alpha, double n_dot_v) {
  return PointTerm{
      [=](const Vec3d& l) {
        return double(micro_shadowing::specular_aware_azimuth_mean<T>(T(V), T(alpha), T(l.z), T(n_dot_v)));
      },
      specular_aware_z_breaks(V, n_dot_v), true};
}
// The diffuse-aware term (exact quadrature over the VNDF) at the full direction, anisotropic GGX, view v:
// continuous in l except at the generic term's early-out 2V + N·L < 1 (its region is a subset of the
// generic one), so its breaks are those of the generic term and the cone.
inline auto diffuse_aware_term(double V, double alpha_x, double alpha_y, const Vec3d& v,
                               micro_shadowing::DiffuseAwareForm form, double rel_tol = 1e-8) {
  return PointTerm{[=](const Vec3d& l) {
                     return micro_shadowing::diffuse_aware_exact(V, alpha_x, alpha_y, v, l, form, rel_tol);
                   },
                   {1 - 2 * saturate(V), micro_shadowing::cone_cos_from_visibility(saturate(V))},
                   false};
}
// Its azimuth mean (isotropic), a function of z only.
inline auto diffuse_aware_azimuth_mean_term(double V, double alpha, double n_dot_v,
                                            micro_shadowing::DiffuseAwareForm form) {
  return PointTerm{[=](const Vec3d& l) {
                     return micro_shadowing::diffuse_aware_exact_azimuth_mean(V, alpha, l.z, n_dot_v, form);
                   },
                   {1 - 2 * saturate(V), micro_shadowing::cone_cos_from_visibility(saturate(V))},
                   true};
}

struct AreaOptions {
  double rel_tol = 1e-8;  // panel-relative Gauss–Kronrod tolerance (outer; inner uses rel_tol / 4)
};

namespace area_quadrature {

constexpr double kTwoPi = 2 * kPi<double>;

// Up to 8 disjoint φ-intervals in [0, 2π).
struct Arcs {
  int n = 0;
  std::array<std::pair<double, double>, 8> iv{};
  void add(double a, double b) {
    if (b > a && n < 8) iv[size_t(n++)] = {a, b};
  }
  static Arcs full() {
    Arcs r;
    r.add(0, kTwoPi);
    return r;
  }
  // The arc |φ − c| < w (mod 2π), w ∈ [0, π].
  static Arcs arc(double c, double w) {
    Arcs r;
    if (!(w > 0)) return r;
    if (w >= kPi<double>) return full();
    double lo = std::fmod(c - w, kTwoPi);
    if (lo < 0) lo += kTwoPi;
    const double hi = lo + 2 * w;
    if (hi <= kTwoPi) {
      r.add(lo, hi);
    } else {
      r.add(0, hi - kTwoPi);
      r.add(lo, kTwoPi);
    }
    return r;
  }
  Arcs intersect(const Arcs& o) const {
    Arcs r;
    for (int i = 0; i < n; ++i)
      for (int j = 0; j < o.n; ++j)
        r.add(std::max(iv[size_t(i)].first, o.iv[size_t(j)].first),
              std::min(iv[size_t(i)].second, o.iv[size_t(j)].second));
    std::sort(r.iv.begin(), r.iv.begin() + r.n);
    return r;
  }
  double length() const {
    double s = 0;
    for (int i = 0; i < n; ++i) s += iv[size_t(i)].second - iv[size_t(i)].first;
    return s;
  }
};

// {φ : z·hz + s·(hx cos φ + hy sin φ) > 0} on the circle of constant z (s = sqrt(1 − z²)).
inline Arcs halfspace_arcs(const Vec3d& h, double z, double s) {
  const double hr = std::hypot(h.x, h.y), a = z * h.z;
  if (!(s * hr > std::abs(a))) return a > 0 ? Arcs::full() : Arcs{};
  return Arcs::arc(std::atan2(h.y, h.x), std::acos(std::clamp(-a / (s * hr), -1.0, 1.0)));
}

// Real roots in [0, 2π) of the trigonometric polynomial g(φ) = A0 + A1 cos φ + B1 sin φ + A2 cos 2φ +
// B2 sin 2φ. With ψ = φ − φ0 and t = tan(ψ/2), (1 + t²)² g is a quartic in t; φ0 + π is the sample where
// |g| is largest, so the leading coefficient g(φ0 + π) is far from 0. Roots by Durand–Kerner (Weierstrass)
// iteration, near-real ones polished by Newton on g in φ. The caller tests the intervals between roots, so
// a spurious root is harmless; only a missed one would matter.
struct TrigPoly2 {
  double A0 = 0, A1 = 0, B1 = 0, A2 = 0, B2 = 0;
  double operator()(double p) const {
    return A0 + A1 * std::cos(p) + B1 * std::sin(p) + A2 * std::cos(2 * p) + B2 * std::sin(2 * p);
  }
  double deriv(double p) const {
    return -A1 * std::sin(p) + B1 * std::cos(p) - 2 * A2 * std::sin(2 * p) + 2 * B2 * std::cos(2 * p);
  }
  // (c0 + c1 cos + s1 sin)(d0 + d1 cos + t1 sin)
  static TrigPoly2 product(double c0, double c1, double s1, double d0, double d1, double t1) {
    TrigPoly2 r;
    r.A0 = c0 * d0 + 0.5 * (c1 * d1 + s1 * t1);
    r.A1 = c0 * d1 + c1 * d0, r.B1 = c0 * t1 + s1 * d0;
    r.A2 = 0.5 * (c1 * d1 - s1 * t1), r.B2 = 0.5 * (c1 * t1 + s1 * d1);
    return r;
  }
};

inline int trig_roots(const TrigPoly2& g, double* out) {
  const double scale = std::abs(g.A0) + std::abs(g.A1) + std::abs(g.B1) + std::abs(g.A2) + std::abs(g.B2);
  if (!(scale > 0) || !std::isfinite(scale)) return 0;
  double phi0 = 0, best = -1;
  for (int k = 0; k < 16; ++k) {
    const double p = kTwoPi * k / 16;
    if (std::abs(g(p)) > best) best = std::abs(g(p)), phi0 = p - kPi<double>;
  }
  const double c1 = std::cos(phi0), s1 = std::sin(phi0), c2 = std::cos(2 * phi0), s2 = std::sin(2 * phi0);
  const double a1 = g.A1 * c1 + g.B1 * s1, b1 = -g.A1 * s1 + g.B1 * c1;
  const double a2 = g.A2 * c2 + g.B2 * s2, b2 = -g.A2 * s2 + g.B2 * c2;
  const double p4 = g.A0 - a1 + a2, p3 = 2 * b1 - 4 * b2, p2 = 2 * g.A0 - 6 * a2, p1 = 2 * b1 + 4 * b2,
               p0 = g.A0 + a1 + a2;
  using C = std::complex<double>;
  const C q[4] = {C(p3 / p4), C(p2 / p4), C(p1 / p4), C(p0 / p4)};
  auto P = [&](C t) { return (((t + q[0]) * t + q[1]) * t + q[2]) * t + q[3]; };
  const double R = 1 + std::max({std::abs(q[0]), std::abs(q[1]), std::abs(q[2]), std::abs(q[3])});
  C z[4];
  for (int i = 0; i < 4; ++i) z[i] = std::polar(R, 0.4 + kTwoPi * i / 4);
  for (int it = 0; it < 500; ++it) {
    double change = 0;
    for (int i = 0; i < 4; ++i) {
      C den(1, 0);
      for (int j = 0; j < 4; ++j)
        if (j != i) den *= z[i] - z[j];
      if (std::abs(den) == 0) den = C(1e-300, 0);
      const C dz = P(z[i]) / den;
      z[i] -= dz;
      change = std::max(change, std::abs(dz) / (1 + std::abs(z[i])));
    }
    if (change < 1e-15) break;
  }
  int n = 0;
  for (int i = 0; i < 4; ++i) {
    if (!(std::abs(z[i].imag()) <= 1e-3 * (1 + std::abs(z[i].real())))) continue;
    double p = phi0 + 2 * std::atan(z[i].real());
    for (int it = 0; it < 8; ++it) {  // Newton on g in φ
      const double d = g.deriv(p);
      if (!(std::abs(d) > 1e-300)) break;
      const double step = g(p) / d;
      if (!(std::abs(step) < 0.1)) break;
      p -= step;
    }
    p = std::fmod(p, kTwoPi);
    if (p < 0) p += kTwoPi;
    out[n++] = p;
  }
  return n;
}

// The φ-intervals of {l : inside(l)} on the circle of constant z whose boundary points are roots[0..n):
// tests the midpoint of each gap.
template <class Inside>
Arcs arcs_from_roots(double* roots, int n, double z, double s, const Inside& inside) {
  std::sort(roots, roots + n);
  Arcs r;
  if (n == 0) {
    if (inside(Vec3d(s, 0, z))) r = Arcs::full();
    return r;
  }
  double prev = roots[n - 1] - kTwoPi;
  for (int i = 0; i <= n; ++i) {
    const double next = i < n ? roots[i] : roots[0] + kTwoPi;
    if (next - prev > 1e-15) {
      const double mid = 0.5 * (prev + next);
      if (inside(Vec3d(s * std::cos(mid), s * std::sin(mid), z))) {
        // [prev, next] may straddle 0: split into [0, 2π).
        double a = prev, b = next;
        if (a < 0) {
          r.add(a + kTwoPi, kTwoPi);
          a = 0;
        }
        if (b > kTwoPi) {
          r.add(0, b - kTwoPi);
          b = kTwoPi;
        }
        r.add(a, b);
      }
    }
    prev = next;
  }
  // Merge touching intervals (after the wrap split) and sort.
  std::sort(r.iv.begin(), r.iv.begin() + r.n);
  Arcs m;
  for (int i = 0; i < r.n; ++i) {
    if (m.n > 0 && r.iv[size_t(i)].first <= m.iv[size_t(m.n - 1)].second + 1e-15)
      m.iv[size_t(m.n - 1)].second = std::max(m.iv[size_t(m.n - 1)].second, r.iv[size_t(i)].second);
    else
      m.add(r.iv[size_t(i)].first, r.iv[size_t(i)].second);
  }
  return m;
}

// Per-shape geometry: contains(l), arcs(z), z_breaks, center, zero size.
struct CapGeom {
  Vec3d c;
  double cos_r, rho;
  explicit CapGeom(const Cap& cap)
      : c(normalize(cap.center)),
        cos_r(std::cos(std::clamp(cap.radius, 0.0, kPi<double>))),
        rho(std::clamp(cap.radius, 0.0, kPi<double>)) {}
  bool zero() const { return !(rho > 0); }
  Vec3d center() const { return c; }
  bool contains(const Vec3d& l) const { return dot(l, c) > cos_r; }
  Arcs arcs(double z, double s) const {
    const double sc = std::hypot(c.x, c.y);
    if (!(s * sc > 1e-300)) return z * c.z > cos_r ? Arcs::full() : Arcs{};
    const double t = (cos_r - z * c.z) / (s * sc);
    if (t <= -1) return Arcs::full();
    if (t >= 1) return {};
    return Arcs::arc(std::atan2(c.y, c.x), std::acos(t));
  }
  void breaks(std::vector<double>& z) const {
    const double tc = std::acos(std::clamp(c.z, -1.0, 1.0));
    z.push_back(std::cos(std::min(kPi<double>, tc + rho)));
    z.push_back(std::cos(std::abs(tc - rho)));
  }
};

struct QuadGeom {
  std::array<Vec3d, 4> v;
  std::array<Vec3d, 4> h;  // inward edge normals
  bool degenerate = false;
  explicit QuadGeom(const Quad& q) {
    Vec3d sum(0, 0, 0);
    for (int i = 0; i < 4; ++i) v[size_t(i)] = normalize(q.corners[size_t(i)]), sum += v[size_t(i)];
    const Vec3d cen = normalize(sum);
    double sgn = 0;
    for (int i = 0; i < 4; ++i) {
      const Vec3d e = cross(v[size_t(i)], v[size_t((i + 1) % 4)]);
      h[size_t(i)] = normalize(e, Vec3d(0, 0, 0));
      sgn += dot(h[size_t(i)], cen);
    }
    if (sgn < 0)
      for (auto& x : h) x = -x;
    int null_edges = 0;
    for (const auto& x : h) null_edges += !(dot(x, x) > 0);
    degenerate = null_edges >= 3 || !(quad_solid_angle() > 1e-15);
  }
  // Girard: Σ interior angles − 2π for the convex spherical polygon, via two triangles (Van Oosterom &
  // Strackee 1983, "The Solid Angle of a Plane Triangle").
  double quad_solid_angle() const {
    auto tri = [](const Vec3d& a, const Vec3d& b, const Vec3d& c) {
      const double num = std::abs(dot(a, cross(b, c)));
      const double den = 1 + dot(a, b) + dot(b, c) + dot(c, a);
      return 2 * std::atan2(num, den);
    };
    return tri(v[0], v[1], v[2]) + tri(v[0], v[2], v[3]);
  }
  bool zero() const { return degenerate; }
  Vec3d center() const { return normalize(v[0] + v[1] + v[2] + v[3]); }
  bool contains(const Vec3d& l) const {
    for (const auto& x : h)
      if (dot(x, x) > 0 && !(dot(l, x) > 0)) return false;
    return true;
  }
  Arcs arcs(double z, double s) const {
    Arcs r = Arcs::full();
    for (const auto& x : h)
      if (dot(x, x) > 0) r = r.intersect(halfspace_arcs(x, z, s));
    return r;
  }
  void breaks(std::vector<double>& z) const {
    for (int i = 0; i < 4; ++i) {
      z.push_back(v[size_t(i)].z);
      // Extreme z of edge i's great circle, if inside the edge's arc.
      const Vec3d& hn = h[size_t(i)];
      const Vec3d p = Vec3d(0, 0, 1) - hn.z * hn;
      if (!(length(p) > 1e-12)) continue;
      for (const Vec3d& e : {normalize(p), -1.0 * normalize(p)}) {
        const Vec3d &a = v[size_t(i)], &b = v[size_t((i + 1) % 4)];
        if (dot(cross(a, e), cross(a, b)) >= 0 && dot(cross(e, b), cross(a, b)) >= 0) z.push_back(e.z);
      }
    }
  }
};

struct DiskGeom {
  Vec3d c, nd, e1, e2;
  double R, cn;
  explicit DiskGeom(const Disk& d)
      : c(normalize(d.center)), nd(normalize(d.normal)), R(std::max(0.0, d.radius)) {
    const Frame<double> f = Frame<double>::from_z(nd);
    e1 = f.s, e2 = f.t;
    cn = dot(c, nd);
  }
  bool zero() const { return !(R > 0) || !(std::abs(cn) > 1e-12); }
  Vec3d center() const { return c; }
  bool contains(const Vec3d& l) const {
    const double dn = dot(l, nd);
    if (!(dn * cn > 0)) return false;
    const Vec3d p = (cn / dn) * l - c;
    return dot(p, p) < R * R;
  }
  // Boundary on the circle z: roots of l^T Q l (Q: the elliptic cone |(c·nd) l − (l·nd) c|² = R² (l·nd)²)
  // and of l·nd (the cone's two nappes), the intervals sorted by contains().
  Arcs arcs(double z, double s) const {
    // Q = cn² I − cn (c ndᵀ + nd cᵀ) + (1 − R²) nd ndᵀ.
    double Q[3][3];
    const double cc[3] = {c.x, c.y, c.z}, nn[3] = {nd.x, nd.y, nd.z};
    for (int i = 0; i < 3; ++i)
      for (int j = 0; j < 3; ++j)
        Q[i][j] = (i == j ? cn * cn : 0) - cn * (cc[i] * nn[j] + nn[i] * cc[j]) + (1 - R * R) * nn[i] * nn[j];
    TrigPoly2 g;
    g.A0 = 0.5 * s * s * (Q[0][0] + Q[1][1]) + z * z * Q[2][2];
    g.A1 = 2 * s * z * Q[0][2], g.B1 = 2 * s * z * Q[1][2];
    g.A2 = 0.5 * s * s * (Q[0][0] - Q[1][1]), g.B2 = s * s * Q[0][1];
    double roots[8];
    int n = trig_roots(g, roots);
    // l·nd = z nz + s (nx cos φ + ny sin φ) = 0.
    const double hr = std::hypot(nd.x, nd.y);
    if (s * hr > std::abs(z * nd.z)) {
      const double c0 = std::atan2(nd.y, nd.x), w = std::acos(std::clamp(-z * nd.z / (s * hr), -1.0, 1.0));
      for (double p : {c0 - w, c0 + w}) {
        p = std::fmod(p, kTwoPi);
        roots[n++] = p < 0 ? p + kTwoPi : p;
      }
    }
    return arcs_from_roots(roots, n, z, s, [this](const Vec3d& l) { return contains(l); });
  }
  // Stationary points of z(a) = p_z/|p| along the rim p(a) = c + R(cos a e1 + sin a e2):
  // p_z'(p·p) − p_z(p·p') = 0, a trigonometric quartic in a.
  void breaks(std::vector<double>& z) const {
    const double al = dot(c, e1), be = dot(c, e2);
    // p·p = 1 + R² + 2R(al cos a + be sin a); p·p' = R(be cos a − al sin a);
    // p_z = c.z + R(e1.z cos a + e2.z sin a); p_z' = R(e2.z cos a − e1.z sin a).
    const TrigPoly2 t1 = TrigPoly2::product(0, R * e2.z, -R * e1.z, 1 + R * R, 2 * R * al, 2 * R * be);
    const TrigPoly2 t2 = TrigPoly2::product(c.z, R * e1.z, R * e2.z, 0, R * be, -R * al);
    TrigPoly2 h;
    h.A0 = t1.A0 - t2.A0, h.A1 = t1.A1 - t2.A1, h.B1 = t1.B1 - t2.B1, h.A2 = t1.A2 - t2.A2,
    h.B2 = t1.B2 - t2.B2;
    double roots[8];
    const int n = trig_roots(h, roots);
    for (int i = 0; i < n; ++i) {
      const Vec3d p = c + R * (std::cos(roots[i]) * e1 + std::sin(roots[i]) * e2);
      z.push_back(normalize(p).z);
    }
  }
};

// The polar-about-n quadrature of §2 for any integrand: ∫ over the light ∩ {z > z_lo} of
// z_factor(z) · ∫_arcs(z) phi_integrand(l) dφ dz. phi_constant: phi_integrand does not depend on φ (it is
// evaluated once per circle, times the arcs' length). zb: the z where the integrand jumps or kinks; peak
// (may be null): a direction where it peaks, whose z and azimuth become panel edges.
// The azimuths in [0, 2π) where `curve` meets the circle of constant z (at most 2).
inline int curve_azimuths(const AzimuthBreak& curve, double z, double s, double* out) {
  const double r = std::hypot(curve.axis.x, curve.axis.y);
  if (!(s * r > 1e-300)) return 0;
  const double x = (curve.k(z) - z * curve.axis.z) / (s * r);
  if (!(std::abs(x) < 1)) return 0;
  const double p0 = std::atan2(curve.axis.y, curve.axis.x), w = std::acos(x);
  int n = 0;
  for (double p : {p0 - w, p0 + w}) {
    p = std::fmod(p, kTwoPi);
    out[n++] = p < 0 ? p + kTwoPi : p;
  }
  return n;
}

// The z in (z_lo, 1) where `curve` is tangent to a circle of constant z ((k − z a_z)² = (1 − z²) |a_xy|²):
// sign changes on a 512-point grid, refined by bisection.
inline void curve_tangent_z(const AzimuthBreak& curve, double z_lo, std::vector<double>& out) {
  const double r2 = curve.axis.x * curve.axis.x + curve.axis.y * curve.axis.y;
  auto g = [&](double z) { return sqr(curve.k(z) - z * curve.axis.z) - (1 - z * z) * r2; };
  constexpr int kN = 512;
  double za = z_lo, ga = g(za);
  for (int i = 1; i <= kN; ++i) {
    const double zb = z_lo + (1 - z_lo) * i / kN, gb = g(zb);
    if ((ga < 0) != (gb < 0)) {
      double a = za, b = zb;
      for (int it = 0; it < 60; ++it) {
        const double m = 0.5 * (a + b);
        ((g(m) < 0) == (ga < 0) ? a : b) = m;
      }
      out.push_back(0.5 * (a + b));
    }
    za = zb, ga = gb;
  }
}

// peak (may be null): a direction where the integrand peaks, whose z and azimuth become panel edges;
// curves: where it jumps off the circles of constant z (their azimuths are inner panel edges).
template <class G, class Zf, class Pf>
double integrate_polar(const G& geom, const Zf& z_factor, const Pf& phi_integrand, bool phi_constant,
                       const std::vector<double>& zb, const Vec3d* peak, double z_lo, double rel_tol,
                       const std::vector<AzimuthBreak>& curves = {}) {
  double phi_peak = -1;
  if (peak != nullptr && std::hypot(peak->x, peak->y) > 1e-12) {
    phi_peak = std::atan2(peak->y, peak->x);
    if (phi_peak < 0) phi_peak += kTwoPi;
  }
  auto inner = [&](double z) -> double {
    if (!(z > z_lo)) return 0.0;
    const double s = std::sqrt(std::max(0.0, 1 - z * z));
    const Arcs arcs = geom.arcs(z, s);
    if (arcs.n == 0) return 0.0;
    const double zf = z_factor(z, s);
    if (phi_constant) return zf * phi_integrand(Vec3d(s, 0, z)) * arcs.length();
    double sum = 0;
    auto f = [&](double p) { return phi_integrand(Vec3d(s * std::cos(p), s * std::sin(p), z)); };
    auto panel = [&](double a, double b) {
      const double h = b - a;
      if (!(h > 0)) return 0.0;
      return gauss_kronrod([&](double u) { return f(a + h * u * u * (3 - 2 * u)) * 6 * h * u * (1 - u); },
                           0.0, 1.0, 0.0, 0.25 * rel_tol);
    };
    double cuts[34];
    int nc = 0;
    if (phi_peak >= 0) cuts[nc++] = phi_peak;
    for (const AzimuthBreak& cv : curves)
      if (nc + 2 <= 34) nc += curve_azimuths(cv, z, s, cuts + nc);
    std::sort(cuts, cuts + nc);
    for (int i = 0; i < arcs.n; ++i) {
      double a = arcs.iv[size_t(i)].first;
      const double b = arcs.iv[size_t(i)].second;
      for (int j = 0; j < nc; ++j)
        if (cuts[j] > a && cuts[j] < b) sum += panel(a, cuts[j]), a = cuts[j];
      sum += panel(a, b);
    }
    return zf * sum;
  };
  std::vector<double> pts = {z_lo, 1.0};
  for (double z : zb)
    if (z > z_lo && z < 1) pts.push_back(z);
  if (peak != nullptr && peak->z > z_lo && peak->z < 1) pts.push_back(peak->z);
  std::vector<double> tangents;
  for (const AzimuthBreak& cv : curves) curve_tangent_z(cv, z_lo, tangents);
  for (double z : tangents)
    if (z > z_lo && z < 1) pts.push_back(z);
  std::sort(pts.begin(), pts.end());
  double total = 0;
  for (size_t i = 0; i + 1 < pts.size(); ++i) {
    const double a = pts[i], h = pts[i + 1] - pts[i];
    if (!(h > 1e-15)) continue;
    total += gauss_kronrod([&](double u) { return inner(a + h * u * u * (3 - 2 * u)) * 6 * h * u * (1 - u); },
                           0.0, 1.0, 0.0, rel_tol);
  }
  return total;
}

// The GGX mirror direction of the view (the receiver weight's peak).
inline Vec3d mirror_direction(const Receiver& rec) { return Vec3d(-rec.v.x, -rec.v.y, rec.v.z); }

template <class G, class F>
double integrate_shape(const G& geom, const Receiver& rec, const PointTerm<F>* term,
                       const std::vector<double>& zb, double rel_tol) {
  const bool lambert = rec.kind == Receiver::Kind::Lambert;
  const bool z_only = term == nullptr || term->z_only;
  const Vec3d mirror = mirror_direction(rec);
  return integrate_polar(
      geom, [&](double z, double s) { return (term && z_only) ? term->M(Vec3d(s, 0, z)) : 1.0; },
      [&](const Vec3d& l) {
        const double w = rec.weight(l);
        return (term && !z_only) ? w * term->M(l) : w;
      },
      lambert && z_only, zb, lambert ? nullptr : &mirror, 0.0, rel_tol,
      (term && !z_only) ? term->phi_breaks : std::vector<AzimuthBreak>{});
}

template <class G, class F>
std::vector<double> all_breaks(const G& geom, const Receiver& rec, const PointTerm<F>* term) {
  std::vector<double> zb;
  geom.breaks(zb);
  if (rec.kind == Receiver::Kind::GGX) zb.push_back(rec.v.z);
  if (term) zb.insert(zb.end(), term->z_breaks.begin(), term->z_breaks.end());
  return zb;
}

}  // namespace area_quadrature

// ∫_Ω M(l) f(v,l)(n·l)⁺ dl and ∫_Ω f(v,l)(n·l)⁺ dl (the receiver's weight, without the BRDF's constant
// factors: 1/π for Lambert; D G2/(4 n·v) for GGX).
struct AreaIntegrals {
  double weighted = 0, total = 0;
};

namespace area_quadrature {
// Calls f(geometry) with the geometry of the shape's kind.
template <class R, class Fn>
R with_geom(const Shape& shape, Fn&& f) {
  switch (shape.kind) {
    case Shape::Kind::Disk:
      return f(DiskGeom(shape.disk));
    case Shape::Kind::Quad:
      return f(QuadGeom(shape.quad));
    default:
      return f(CapGeom(shape.cap));
  }
}
inline double one(const Vec3d&) { return 1.0; }
}  // namespace area_quadrature

template <class F>
AreaIntegrals area_integrals(const Shape& shape, const Receiver& rec, const PointTerm<F>& term,
                             const AreaOptions& opt = {}) {
  return area_quadrature::with_geom<AreaIntegrals>(shape, [&](const auto& geom) {
    const PointTerm<double (*)(const Vec3d&)>* none = nullptr;
    AreaIntegrals r;
    r.total = area_quadrature::integrate_shape(geom, rec, none, area_quadrature::all_breaks(geom, rec, none),
                                               opt.rel_tol);
    if (r.total > 0)
      r.weighted = area_quadrature::integrate_shape(
          geom, rec, &term, area_quadrature::all_breaks(geom, rec, &term), opt.rel_tol);
    return r;
  });
}

// The light's centre direction (cap, disk: their centre; quad: the normalized sum of the corners).
inline Vec3d shape_center(const Shape& shape) {
  return area_quadrature::with_geom<Vec3d>(shape, [](const auto& g) { return g.center(); });
}

// Whether the shape has zero solid angle (radius 0, coincident corners, a disk seen edge-on).
inline bool shape_is_point(const Shape& shape) {
  return area_quadrature::with_geom<bool>(shape, [](const auto& g) { return g.zero(); });
}

// Whether the direction l is inside the light.
inline bool shape_contains(const Shape& shape, const Vec3d& l) {
  return area_quadrature::with_geom<bool>(shape, [&](const auto& g) { return g.contains(l); });
}

// M_area (definition at the top). Zero-size light: M(center). No weight above the horizon: 0. The value is
// clamped to [0, 1].
template <class F>
double area_micro_shadowing_exact(const Shape& shape, const Receiver& rec, const PointTerm<F>& term,
                                  const AreaOptions& opt = {}) {
  if (shape_is_point(shape)) return term.M(shape_center(shape));
  const AreaIntegrals r = area_integrals(shape, rec, term, opt);
  return r.total > 0 ? saturate(r.weighted / r.total) : 0.0;
}

// ∫_Ω (n·l)⁺ dl (Lambert) or ∫_Ω f (n·l)⁺ dl (GGX): the light's weight, e.g. irradiance / radiance.
inline double light_weight(const Shape& shape, const Receiver& rec, const AreaOptions& opt = {}) {
  return area_integrals(shape, rec, PointTerm<double (*)(const Vec3d&)>{&area_quadrature::one, {}, true}, opt)
      .total;
}

// ---- any integrand over a light ---------------------------------------------------------------------------

// Where a general integrand g(l) over a light is not smooth, for integrate_light.
struct IntegrandBreaks {
  std::vector<double> z;  // values of z = n·l where g jumps or kinks (e.g. the horizon of a clamped cosine)
  bool has_peak = false;  // g peaks sharply at `peak` (e.g. a GGX lobe's mirror direction): its z and
  Vec3d peak{0, 0, 1};    //   azimuth about n become panel edges
  bool below_horizon = false;  // integrate all of the light (z ∈ [−1, 1]); default: only its part with z > 0
};

// ∫_Ω g(l) dl over the light's solid angle (or its part above the horizon) by the quadrature of §2 above,
// the one place that integrates over a light: the area terms and the LTC verification (bsdf/runtime/
// ltc_baker.h) use it. g: a callable double(const Vec3d&) of a unit direction in the frame n = +z.
// rel_tol: panel-relative Gauss–Kronrod tolerance.
template <class G>
double integrate_light(const Shape& shape, const G& g, const IntegrandBreaks& b = {},
                       const AreaOptions& opt = {}) {
  return area_quadrature::with_geom<double>(shape, [&](const auto& geom) {
    if (geom.zero()) return 0.0;
    std::vector<double> zb = b.z;
    geom.breaks(zb);
    const double z_lo = b.below_horizon ? -1.0 : 0.0;
    if (b.below_horizon) zb.push_back(0.0);
    return area_quadrature::integrate_polar(
        geom, [](double, double) { return 1.0; }, g, false, zb, b.has_peak ? &b.peak : nullptr, z_lo,
        opt.rel_tol);
  });
}

// ---- closed forms the quadrature is checked against
// ----------------------------------------------------------

// Form factor (Lambertian receiver, n = +z) of a sphere of angular radius σ whose centre is at elevation
// cos ω = n·c, clipped by the horizon (Snyder 1996, "Area light sources for real-time graphics"; the form of
// Lagarde & de Rousiers 2014, "Moving Frostbite to PBR", eq. 19, divided by π).
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

}  // namespace msh::area
