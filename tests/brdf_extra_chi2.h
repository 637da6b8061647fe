// Chi-square goodness-of-fit for direction samplers (the pbrt-v4 / Mitsuba 3 habit, REFERENCE.md §7), for the
// BRDF-extra tests: histogram of samples on a (cos θ, φ) grid of the upper hemisphere vs the pdf integrated
// over each cell (sub-cell midpoint rule), cells with expected count < 5 pooled, p-value from the regularized
// upper incomplete gamma function. Samples reported as "none" (nullopt) count as mass outside the hemisphere.
#pragma once

#include <microshadow/math/sampling.h>
#include <microshadow/math/vec.h>

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <functional>
#include <optional>
#include <vector>

namespace msh::test_extra {

// Q(a, x) = Γ(a, x)/Γ(a) (Numerical Recipes §6.2: series for x < a + 1, continued fraction otherwise).
inline double gamma_q(double a, double x) {
  if (x <= 0) return 1.0;
  const double gln = std::lgamma(a);
  if (x < a + 1) {
    double ap = a, sum = 1.0 / a, del = sum;
    for (int n = 0; n < 10000; ++n) {
      ap += 1;
      del *= x / ap;
      sum += del;
      if (std::abs(del) < std::abs(sum) * 1e-15) break;
    }
    return 1.0 - sum * std::exp(-x + a * std::log(x) - gln);
  }
  double b = x + 1 - a, c = 1.0 / 1e-300, d = 1.0 / b, h = d;
  for (int i = 1; i < 10000; ++i) {
    const double an = -i * (i - a);
    b += 2;
    d = an * d + b;
    if (std::abs(d) < 1e-300) d = 1e-300;
    c = b + an / c;
    if (std::abs(c) < 1e-300) c = 1e-300;
    d = 1.0 / d;
    const double del = d * c;
    h *= del;
    if (std::abs(del - 1) < 1e-15) break;
  }
  return std::exp(-x + a * std::log(x) - gln) * h;
}

struct Chi2Result {
  double p_value = 0;
  double statistic = 0;
  int dof = 0;
  bool sample_in_empty_cell = false;
  double expected_total = 0;  // ∫ pdf over the hemisphere (should be ≤ 1)
};

// sampler(u) → direction (or nullopt); pdf(w) solid-angle density. n_z × n_phi cells, `sub` × `sub` midpoints
// per cell for the expected counts.
inline Chi2Result chi2_directions(const std::function<std::optional<Vec3d>(Vec2d)>& sampler,
                                  const std::function<double(const Vec3d&)>& pdf, int n_samples,
                                  uint32_t seed, int n_z = 16, int n_phi = 32, int sub = 10) {
  const int cells = n_z * n_phi;
  std::vector<double> obs(size_t(cells), 0.0), exp(size_t(cells), 0.0);
  Pcg32 rng(seed);  // independent uniforms: a low-discrepancy sequence would make the statistic too small
  for (int i = 0; i < n_samples; ++i) {
    const double u0 = rng.next_double(), u1 = rng.next_double();
    const auto w = sampler(Vec2d(u0, u1));
    if (!w || !(w->z > 0)) continue;
    const int iz = std::min(n_z - 1, int(w->z * n_z));
    double phi = std::atan2(w->y, w->x);
    if (phi < 0) phi += 2 * kPi<double>;
    const int ip = std::min(n_phi - 1, int(phi / (2 * kPi<double>)*n_phi));
    obs[size_t(iz * n_phi + ip)] += 1;
  }
  Chi2Result r;
  const double dz = 1.0 / n_z, dp = 2 * kPi<double> / n_phi;
  for (int iz = 0; iz < n_z; ++iz)
    for (int ip = 0; ip < n_phi; ++ip) {
      double s = 0;
      for (int a = 0; a < sub; ++a)
        for (int b = 0; b < sub; ++b) {
          const double z = (iz + (a + 0.5) / sub) * dz, phi = (ip + (b + 0.5) / sub) * dp;
          s += pdf(spherical_direction(z, phi));
        }
      exp[size_t(iz * n_phi + ip)] = s * dz * dp / (sub * sub) * n_samples;
      r.expected_total += s * dz * dp / (sub * sub);
    }
  // Pool cells with expected < 5 (in order of increasing expectation) until the pool reaches 5.
  std::vector<int> idx(static_cast<size_t>(cells));
  for (int i = 0; i < cells; ++i) idx[size_t(i)] = i;
  std::sort(idx.begin(), idx.end(), [&](int a, int b) { return exp[size_t(a)] < exp[size_t(b)]; });
  double pool_o = 0, pool_e = 0, chi = 0;
  int used = 0;
  for (int i : idx) {
    const double e = exp[size_t(i)], o = obs[size_t(i)];
    if (e <= 0 && o > 0) r.sample_in_empty_cell = true;
    if (e < 5 || pool_e > 0) {
      pool_o += o, pool_e += e;
      if (pool_e >= 5) {
        chi += sqr(pool_o - pool_e) / pool_e, ++used;
        pool_o = pool_e = 0;
      }
      continue;
    }
    chi += sqr(o - e) / e, ++used;
  }
  if (pool_e > 0) chi += sqr(pool_o - pool_e) / pool_e, ++used;
  r.statistic = chi;
  r.dof = std::max(1, used - 1);
  r.p_value = gamma_q(0.5 * r.dof, 0.5 * chi);
  return r;
}

}  // namespace msh::test_extra
