// Gauss-Legendre quadrature on [0,1], used for the 1D averages of the BRDF work (F̄, Ē, R̄_spec).
// Nodes by Newton iteration on the Legendre recurrence (Numerical Recipes §4.6, "gauleg"); exact for
// polynomials of degree ≤ 2n − 1.
#pragma once

#include <microshadow/math/vec.h>

#include <vector>

namespace msh::bsdf {

template <class T>
struct GaussLegendre01 {
  std::vector<T> x, w;  // nodes in (0,1) ascending, weights summing to 1

  explicit GaussLegendre01(int n) : x(size_t(std::max(n, 1))), w(size_t(std::max(n, 1))) {
    n = std::max(n, 1);
    const int m = (n + 1) / 2;
    for (int i = 0; i < m; ++i) {
      // Initial guess (Tricomi), then Newton on P_n(z) computed in double for every T.
      double z = std::cos(kPi<double> * (i + 0.75) / (n + 0.5)), pp = 1.0;
      for (int it = 0; it < 100; ++it) {
        double p1 = 1.0, p2 = 0.0;
        for (int j = 1; j <= n; ++j) {
          const double p3 = p2;
          p2 = p1;
          p1 = ((2.0 * j - 1.0) * z * p2 - (j - 1.0) * p3) / j;
        }
        pp = n * (z * p1 - p2) / (z * z - 1.0);
        const double z1 = z;
        z = z1 - p1 / pp;
        if (std::abs(z - z1) < 1e-15) break;
      }
      const double wi = 2.0 / ((1.0 - z * z) * pp * pp);
      // Map [-1,1] → [0,1]: x = (1 ± z)/2, weight halves.
      x[size_t(i)] = T(0.5 * (1.0 - z));
      x[size_t(n - 1 - i)] = T(0.5 * (1.0 + z));
      w[size_t(i)] = w[size_t(n - 1 - i)] = T(0.5 * wi);
    }
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

}  // namespace msh::bsdf
