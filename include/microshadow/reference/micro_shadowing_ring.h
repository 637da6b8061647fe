// Reference (not for an engine): semi-analytic evaluation of the generic VNDF-based micro-shadowing term
// (Zurita 2026b, docs/theory.md §3) for isotropic Smith-GGX, used to verify the LUT baker on every texel. A
// second method beside reference/micro_shadowing_exact.h (the two agree to 3e-10 when this one is refined).
// Independent of the samplers: no VNDF sampling, no Monte Carlo.
//
// For the Smith profile G2/G1 depends on (v, l) only, so the term is the VNDF-mass ratio
//   R = ∫_{n·m > c, m·l > c} (v·m)⁺ D(m) dm / ∫_{m·l > 0} (v·m)⁺ D(m) dm,   c = sqrt(1 − V).
// On a ring of constant θ_m both constraints and the back-facing clamp are arcs in the azimuth φ_m, so the
// φ_m integral is closed form (ring_integral). The remaining θ_m integral runs in the "stretched" angle ω
// (tan ω = tan θ_m / α), where the GGX measure D sinθ dθ = sinω sqrt(cos²ω + α² sin²ω)/π dω is bounded for
// any α; it is split at the θ_m where an arc appears or becomes a full circle (square-root kinks) and each
// piece is integrated with Gauss-Legendre after a cosine map that smooths the square-root end points.
#pragma once

#include <microshadow/math/quadrature.h>
#include <microshadow/math/vec.h>

#include <algorithm>
#include <array>
#include <cmath>

namespace msh::micro_shadowing {

namespace ring_quadrature {

// The 16-point Gauss-Legendre rule of math/quadrature.h, its positive half ascending: kGLx[i] = x, kGLw[i] =
// w of the i-th positive node (the rule is symmetric).
struct PositiveHalfGL16 {
  std::array<double, 8> x{}, w{};
  PositiveHalfGL16() {
    const GaussLegendre r(16);  // nodes descending from near +1
    for (int i = 0; i < 8; ++i) x[size_t(i)] = r.x[size_t(7 - i)], w[size_t(i)] = r.w[size_t(7 - i)];
  }
};
inline const PositiveHalfGL16 kGL16;
inline const std::array<double, 8>& kGLx = kGL16.x;
inline const std::array<double, 8>& kGLw = kGL16.w;

// ∫ over [lo, hi] of (A cos x + B) dx.
inline double cos_affine_integral(double lo, double hi, double A, double B) {
  return hi > lo ? A * (std::sin(hi) - std::sin(lo)) + B * (hi - lo) : 0.0;
}

// Half-width in [0, π] of the arc {x : cos x > t}.
inline double arc_half_width(double t) { return t <= -1.0 ? kPi<double> : (t >= 1.0 ? 0.0 : std::acos(t)); }

}  // namespace ring_quadrature

// Geometry of one (v, l) configuration: v = (sv, 0, zv), l = (sl cos φ, sl sin φ, zl).
struct MsGeometry {
  double zv, sv, zl, sl, phi;
  static MsGeometry make(double n_dot_v, double n_dot_l, double phi) {
    const double zv = clamp(n_dot_v, 0.0, 1.0), zl = clamp(n_dot_l, 0.0, 1.0);
    return {zv, safe_sqrt(1.0 - zv * zv), zl, safe_sqrt(1.0 - zl * zl), phi};
  }
};

// ∫_0^{2π} χ(n·m ring) χ⁺(m·l − c) (v·m)⁺ dφ_m on the ring (cos θ_m, sin θ_m) = (ct, st). Closed form: the
// two constraints are arcs |φ_m| < a (v·m > 0) and |φ_m − φ| < b (m·l > c). Domain: c ∈ [0, 1].
inline double ring_integral(const MsGeometry& g, double ct, double st, double c) {
  using namespace ring_quadrature;
  const double A = st * g.sv, B = ct * g.zv;  // v·m = A cos φ_m + B
  const double pa = st * g.sl;                // m·l = pa cos(φ_m − φ) + ct zl
  const double a = A > 0.0 ? arc_half_width(-B / A) : (B > 0.0 ? kPi<double> : 0.0);
  const double rhs = c - ct * g.zl;
  const double b = pa > 0.0 ? arc_half_width(rhs / pa) : (rhs < 0.0 ? kPi<double> : 0.0);
  if (a <= 0.0 || b <= 0.0) return 0.0;
  if (b >= kPi<double>) return cos_affine_integral(-a, a, A, B);
  if (a >= kPi<double>) return cos_affine_integral(g.phi - b, g.phi + b, A, B);
  double sum = 0.0;
  for (int k = -1; k <= 1; ++k) {
    const double lo = std::max(-a, g.phi - b + 2.0 * kPi<double> * k);
    const double hi = std::min(a, g.phi + b + 2.0 * kPi<double> * k);
    sum += cos_affine_integral(lo, hi, A, B);
  }
  return sum;
}

// ∫_{θ_m < acos(c_cap)} ring_integral(θ_m, c) D(θ_m) sin θ_m dθ_m for GGX α, i.e. the VNDF mass (up to the
// common factor G1(v)/(n·v)) of {n·m > c_cap, m·l > c}; 16 Gauss-Legendre nodes per piece, each piece
// split in `subdivide` equal parts (for convergence checks).
inline double cone_mass(const MsGeometry& g, double alpha, double c_cap, double c, int subdivide = 3) {
  using namespace ring_quadrature;
  alpha = std::max(alpha, 1e-4);
  if (c_cap >= 1.0) return 0.0;
  const double theta_max = std::acos(std::max(c_cap, 0.0));
  const double theta_c = std::acos(clamp(c, 0.0, 1.0));
  const double theta_l = std::acos(g.zl), theta_v = std::acos(g.zv);
  // θ_m where an arc appears, or closes into a full circle: square-root kinks of the integrand.
  double brk[6];
  int nb = 0;
  brk[nb++] = 0.0;
  for (double t : {theta_c - theta_l, theta_l - theta_c, kPi<double> / 2 - theta_v, theta_l + theta_c})
    if (t > 0.0 && t < theta_max) brk[nb++] = t;
  brk[nb++] = theta_max;
  for (int i = 1; i < nb; ++i)  // insertion sort of ≤ 6 values
    for (int j = i; j > 0 && brk[j - 1] > brk[j]; --j) std::swap(brk[j - 1], brk[j]);
  auto to_omega = [&](double th) {
    return th >= kPi<double> / 2 ? kPi<double> / 2 : std::atan(std::tan(th) / alpha);
  };
  double total = 0.0;
  for (int q = 0; q < (nb - 1) * subdivide; ++q) {
    const int p = q / subdivide, k = q % subdivide;
    const double p0 = to_omega(brk[p]), p1 = to_omega(brk[p + 1]);
    const double w0 = p0 + (p1 - p0) * k / subdivide, w1 = p0 + (p1 - p0) * (k + 1) / subdivide;
    if (!(w1 > w0)) continue;
    const double half = 0.5 * (w1 - w0);
    auto eval = [&](double x) {  // x ∈ [0, 1]; ω = w0 + (w1 − w0)(1 − cos πx)/2
      const double omega = w0 + half * (1.0 - std::cos(kPi<double> * x));
      const double domega = half * kPi<double> * std::sin(kPi<double> * x);
      const double so = std::sin(omega), co = std::cos(omega);
      const double r = std::sqrt(co * co + alpha * alpha * so * so);
      const double ct = co / r, st = alpha * so / r;
      return so * r * kInvPi<double> * ring_integral(g, ct, st, c) * domega;
    };
    double s = 0.0;
    for (int i = 0; i < 8; ++i) s += kGLw[i] * (eval(0.5 - 0.5 * kGLx[i]) + eval(0.5 + 0.5 * kGLx[i]));
    total += 0.5 * s;
  }
  return total;
}

// The generic term at one relative azimuth φ, (Zurita 2026b; Smith ratio form, docs/theory.md §3). Domain: V,
// N·L, N·V ∈ [0, 1], α ≥ 0 (clamped to 1e-4). V = 1 → 1, V = 0 → 0, early-out region 2V + N·L < 1 → 0; a
// configuration with no VNDF mass facing l (e.g. N·V = N·L = 0, φ = π) returns 0 for V < 1.
inline double micro_shadowing_semi_analytic(double alpha, double visibility, double n_dot_l, double n_dot_v,
                                            double phi) {
  if (!(visibility < 1.0)) return 1.0;
  if (!(visibility > 0.0) || 2.0 * visibility + n_dot_l < 1.0) return 0.0;
  const MsGeometry g = MsGeometry::make(n_dot_v, n_dot_l, phi);
  const double c = std::sqrt(1.0 - visibility);
  const double den = cone_mass(g, alpha, 0.0, 0.0);
  if (!(den > 1e-300)) return 0.0;
  return clamp(cone_mass(g, alpha, c, c) / den, 0.0, 1.0);
}

// Mean over φ ∈ [0, π] (uniform) of micro_shadowing_semi_analytic: the value a LUT texel stores. Composite
// Gauss-Legendre (16 nodes per panel, `panels` panels); the φ integrand is smooth except at isolated kinks.
inline double micro_shadowing_semi_analytic_azimuth_mean(double alpha, double visibility, double n_dot_l,
                                                         double n_dot_v, int panels = 8) {
  using namespace ring_quadrature;
  if (!(visibility < 1.0)) return 1.0;
  if (!(visibility > 0.0) || 2.0 * visibility + n_dot_l < 1.0) return 0.0;
  double sum = 0.0;
  const double h = kPi<double> / panels;
  for (int p = 0; p < panels; ++p) {
    const double mid = (p + 0.5) * h;
    for (int i = 0; i < 8; ++i) {
      const double dx = 0.5 * h * kGLx[i];
      sum += kGLw[i] * 0.5 * h *
             (micro_shadowing_semi_analytic(alpha, visibility, n_dot_l, n_dot_v, mid - dx) +
              micro_shadowing_semi_analytic(alpha, visibility, n_dot_l, n_dot_v, mid + dx));
    }
  }
  return sum / kPi<double>;
}

// One LUT row at once: out[i] = azimuth mean for visibility[i], i < n, sharing the hemisphere mass per φ node
// (the slow part of a full-table verification). Same rule as micro_shadowing_semi_analytic_azimuth_mean.
inline void micro_shadowing_semi_analytic_row(double alpha, double n_dot_l, double n_dot_v,
                                              const double* visibility, int n, double* out, int panels = 4,
                                              int subdivide = 3) {
  using namespace ring_quadrature;
  for (int i = 0; i < n; ++i) out[i] = 0.0;
  const double h = kPi<double> / panels;
  for (int p = 0; p < panels; ++p)
    for (int j = 0; j < 16; ++j) {
      const double x = j < 8 ? -kGLx[7 - j] : kGLx[j - 8], w = j < 8 ? kGLw[7 - j] : kGLw[j - 8];
      const MsGeometry g = MsGeometry::make(n_dot_v, n_dot_l, (p + 0.5) * h + 0.5 * h * x);
      const double den = cone_mass(g, alpha, 0.0, 0.0, subdivide);
      if (!(den > 1e-300)) continue;
      for (int i = 0; i < n; ++i) {
        const double V = visibility[i];
        if (!(V > 0.0) || !(V < 1.0) || 2.0 * V + n_dot_l < 1.0) continue;
        const double c = std::sqrt(1.0 - V);
        out[i] += w * 0.5 * h / kPi<double> * clamp(cone_mass(g, alpha, c, c, subdivide) / den, 0.0, 1.0);
      }
    }
  for (int i = 0; i < n; ++i)
    if (!(visibility[i] < 1.0)) out[i] = 1.0;
}

}  // namespace msh::micro_shadowing
