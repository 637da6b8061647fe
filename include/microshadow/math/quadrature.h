// Deterministic 1D quadrature, the one module of the project: adaptive Gauss-Kronrod (7/15) and
// Gauss-Legendre rules on [−1, 1] and on [0, 1]. Nodes and sums in double precision; GaussLegendre01<T>
// stores them as T. Used by the GTR Λ table, the GGX albedo reference, the BRDF averages (F̄, Ē) and the
// table bakers.
#pragma once

#include <algorithm>
#include <array>
#include <cmath>
#include <vector>

namespace msh {

// Adaptive Gauss-Kronrod (7/15) on [a, b] to absolute tolerance tol: bisects while |K15 − G7| > tol (the
// tolerance halves with each split) or |K15 − G7| ≤ rel_tol·|K15| (panel-relative: also stops where round-off
// dominates), depth ≤ 30. Returns the K15 sums (error usually far below the estimate).
template <class F>
double gauss_kronrod(const F& f, double a, double b, double tol, double rel_tol = 1e-12, int depth = 0) {
  static constexpr std::array<double, 8> xk = {
      0.991455371120812639, 0.949107912342758525, 0.864864423359769073, 0.741531185599394440,
      0.586087235467691130, 0.405845151377397167, 0.207784955007898468, 0.0};
  static constexpr std::array<double, 8> wk = {
      0.022935322010529225, 0.063092092629978553, 0.104790010322250184, 0.140653259715525919,
      0.169004726639267903, 0.190350578064785410, 0.204432940075298892, 0.209482141084727828};
  static constexpr std::array<double, 4> wg = {0.129484966168869693, 0.279705391489276668,
                                               0.381830050505118945, 0.417959183673469388};
  const double c = 0.5 * (a + b), h = 0.5 * (b - a);
  double k = wk[7] * f(c), g = wg[3] * f(c);
  for (int i = 0; i < 7; ++i) {
    const double f1 = f(c - h * xk[size_t(i)]), f2 = f(c + h * xk[size_t(i)]);
    k += wk[size_t(i)] * (f1 + f2);
    if (i % 2 == 1) g += wg[size_t(i / 2)] * (f1 + f2);
  }
  k *= h, g *= h;
  // The relative floor stops the recursion where round-off, not truncation, dominates |K − G|.
  if (depth >= 30 || !std::isfinite(k) || std::abs(k - g) <= std::max(tol, rel_tol * std::abs(k))) return k;
  return gauss_kronrod(f, a, c, 0.5 * tol, rel_tol, depth + 1) +
         gauss_kronrod(f, c, b, 0.5 * tol, rel_tol, depth + 1);
}

// n-point Gauss-Legendre rule on [−1, 1] (n ≥ 1; smaller n is taken as 1), exact for polynomials of degree
// ≤ 2n − 1. Nodes x descending from near +1 to near −1; x[n−1−i] = −x[i] and w[n−1−i] = w[i] exactly. Each
// positive node by Newton iteration on P_n (three-term recurrence) from Tricomi's guess
// cos(π(i + 3/4)/(n + 1/2)), to |Δz| < 1e-15 (Numerical Recipes §4.6, "gauleg").
struct GaussLegendre {
  std::vector<double> x, w;

  explicit GaussLegendre(int n) : x(size_t(std::max(n, 1))), w(size_t(std::max(n, 1))) {
    n = std::max(n, 1);
    const int m = (n + 1) / 2;
    for (int i = 0; i < m; ++i) {
      double z = std::cos(3.14159265358979323846 * (i + 0.75) / (n + 0.5)), pp = 1.0;
      for (int it = 0; it < 100; ++it) {
        double p1 = 1.0, p2 = 0.0;  // P_j(z), P_{j−1}(z)
        for (int j = 1; j <= n; ++j) {
          const double p3 = p2;
          p2 = p1;
          p1 = ((2.0 * j - 1.0) * z * p2 - (j - 1.0) * p3) / j;
        }
        pp = n * (z * p1 - p2) / (z * z - 1.0);  // P_n'(z)
        const double z1 = z;
        z = z1 - p1 / pp;
        if (std::abs(z - z1) < 1e-15) break;
      }
      // For odd n the middle node is written twice; −z (the second write) is its value.
      x[size_t(i)] = z;
      x[size_t(n - 1 - i)] = -z;
      w[size_t(i)] = w[size_t(n - 1 - i)] = 2.0 / ((1.0 - z * z) * pp * pp);
    }
  }
};

// The n-point Gauss-Legendre rule mapped to [0, 1]: nodes ascending, weights summing to 1.
template <class T>
struct GaussLegendre01 {
  std::vector<T> x, w;

  explicit GaussLegendre01(int n) {
    const GaussLegendre r(n);
    x.resize(r.x.size()), w.resize(r.x.size());
    for (size_t i = 0; i < r.x.size(); ++i) x[i] = T(0.5 * (1.0 - r.x[i])), w[i] = T(0.5 * r.w[i]);
  }

  template <class F>
  auto integrate(F&& f) const {
    auto s = f(x[0]) * w[0];
    for (size_t i = 1; i < x.size(); ++i) s += f(x[i]) * w[i];
    return s;
  }
};

// ∫₀¹ f(x) dx with n Gauss-Legendre nodes.
template <class T, class F>
auto gauss_legendre_01(int n, F&& f) {
  return GaussLegendre01<T>(n).integrate(f);
}

}  // namespace msh
