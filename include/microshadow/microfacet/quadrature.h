// Deterministic 1D quadrature shared by the microfacet references (GTR Λ table, GGX albedo). Double
// precision.
#pragma once

#include <array>
#include <cmath>
#include <vector>

namespace msh {

namespace detail {

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

// n-point Gauss-Legendre nodes and weights on [−1, 1] (Newton on P_n from the Chebyshev guesses, to 1e-15).
struct GaussLegendre {
  std::vector<double> x, w;
  explicit GaussLegendre(int n) : x(size_t(n)), w(size_t(n)) {
    for (int i = 0; i < n; ++i) {
      double z = std::cos(3.14159265358979323846 * (i + 0.75) / (n + 0.5)), dp = 1.0;
      for (int it = 0; it < 100; ++it) {
        double p0 = 1.0, p1 = z;  // P_0, P_1 → P_n by the three-term recurrence
        for (int k = 2; k <= n; ++k) {
          const double p2 = ((2 * k - 1) * z * p1 - (k - 1) * p0) / k;
          p0 = p1, p1 = p2;
        }
        dp = n * (z * p1 - p0) / (z * z - 1.0);
        const double dz = p1 / dp;
        z -= dz;
        if (std::abs(dz) < 1e-16) break;
      }
      x[size_t(i)] = z;
      w[size_t(i)] = 2.0 / ((1.0 - z * z) * dp * dp);
    }
  }
};

}  // namespace detail

}  // namespace msh
