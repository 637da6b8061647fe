// Chi-square goodness-of-fit test for direction samplers; see chi2.h.
#include "support/chi2.h"

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <numeric>
#include <vector>

namespace msh::test {
namespace {

constexpr double kTwoPi = 2.0 * kPi<double>;

// 5-point Gauss-Legendre on [-1, 1].
constexpr double kGlX[5] = {-0.9061798459386640, -0.5384693101056831, 0.0, 0.5384693101056831,
                            0.9061798459386640};
constexpr double kGlW[5] = {0.2369268850561891, 0.4786286704993665, 0.5688888888888889, 0.4786286704993665,
                            0.2369268850561891};
constexpr int kMaxDepth = 28;  // binary splits: 14 levels in each of z and φ

struct Integrator {
  const std::function<double(const Vec3d&)>& pdf;
  long evals = 0;

  double f(double z, double phi) {
    ++evals;
    const double v = pdf(spherical_direction(z, phi));
    return std::isfinite(v) ? v : 0.0;  // an infinite pdf at a single node (e.g. a pole) carries no mass
  }
  double gl(double z0, double z1, double p0, double p1) {
    const double zc = 0.5 * (z0 + z1), zh = 0.5 * (z1 - z0), pc = 0.5 * (p0 + p1), ph = 0.5 * (p1 - p0);
    double s = 0;
    for (int i = 0; i < 5; ++i) {
      double row = 0;
      for (int j = 0; j < 5; ++j) row += kGlW[j] * f(zc + zh * kGlX[i], pc + ph * kGlX[j]);
      s += kGlW[i] * row;
    }
    return s * zh * ph;
  }
  // Split the rectangle in z or in φ (whichever halving changes the estimate more) until the parent estimate
  // and its two halves agree to tol; depth-capped. Peaks near the poles need refinement in z only.
  double adapt(double z0, double z1, double p0, double p1, double whole, double tol, int depth) {
    const double zm = 0.5 * (z0 + z1), pm = 0.5 * (p0 + p1);
    const double za = gl(z0, zm, p0, p1), zb = gl(zm, z1, p0, p1);
    const double pa = gl(z0, z1, p0, pm), pb = gl(z0, z1, pm, p1);
    const double ez = std::abs(za + zb - whole), ep = std::abs(pa + pb - whole);
    const bool split_z = ez >= ep;
    const double a = split_z ? za : pa, b = split_z ? zb : pb;
    if (depth >= kMaxDepth || (depth >= 2 && std::max(ez, ep) <= tol)) return a + b;
    const double t =
        0.7071 * tol;  // not 0.5: along a jump the error halves with the area, the tolerance must not
    if (split_z) return adapt(z0, zm, p0, p1, a, t, depth + 1) + adapt(zm, z1, p0, p1, b, t, depth + 1);
    return adapt(z0, z1, p0, pm, a, t, depth + 1) + adapt(z0, z1, pm, p1, b, t, depth + 1);
  }
  double integrate(double z0, double z1, double p0, double p1, double tol) {
    return adapt(z0, z1, p0, p1, gl(z0, z1, p0, p1), tol, 0);
  }
};

}  // namespace

double regularized_gamma_q(double a, double x) {
  if (!(a > 0) || !(x > 0)) return 1.0;
  const double log_prefactor = -x + a * std::log(x) - std::lgamma(a);
  if (x < a + 1) {  // series for P(a, x)
    double ap = a, del = 1.0 / a, sum = del;
    for (int n = 0; n < 100000; ++n) {
      ap += 1;
      del *= x / ap;
      sum += del;
      if (std::abs(del) < std::abs(sum) * 1e-16) break;
    }
    return std::max(0.0, 1.0 - sum * std::exp(log_prefactor));
  }
  constexpr double kTiny = 1e-300;  // continued fraction for Q(a, x) (modified Lentz)
  double b = x + 1 - a, c = 1 / kTiny, d = 1 / b, h = d;
  for (int i = 1; i < 100000; ++i) {
    const double an = -i * (i - a);
    b += 2;
    d = an * d + b;
    if (std::abs(d) < kTiny) d = kTiny;
    c = b + an / c;
    if (std::abs(c) < kTiny) c = kTiny;
    d = 1 / d;
    const double del = d * c;
    h *= del;
    if (std::abs(del - 1) < 1e-16) break;
  }
  return std::min(1.0, std::exp(log_prefactor) * h);
}

double integrate_sphere_rect(const std::function<double(const Vec3d&)>& pdf, double z0, double z1,
                             double phi0, double phi1, double abs_tol) {
  Integrator in{pdf};
  return in.integrate(z0, z1, phi0, phi1, abs_tol);
}

Chi2Result chi2_test_directions(const std::function<std::optional<Vec3d>(uint32_t)>& sample,
                                const std::function<double(const Vec3d&)>& pdf, int n_samples, int theta_bins,
                                int phi_bins, double significance, int n_tests) {
  Chi2Result r;
  const int nt = std::max(1, theta_bins), np = std::max(1, phi_bins), cells = nt * np;
  std::vector<double> obs(size_t(cells), 0.0), expc(size_t(cells), 0.0);
  auto cell_of = [&](const Vec3d& w) {
    const int it = std::clamp(int((w.z + 1.0) * 0.5 * nt), 0, nt - 1);
    double phi = std::atan2(w.y, w.x);
    if (phi < 0) phi += kTwoPi;
    const int ip = std::clamp(int(phi / kTwoPi * np), 0, np - 1);
    return it * np + ip;
  };

  // Histogram. A malformed sample fails the test at once (and is reported).
  long n_rejected = 0, n_bad = 0, n_zero_pdf = 0;
  std::string bad;
  for (int i = 0; i < n_samples; ++i) {
    const std::optional<Vec3d> w = sample(uint32_t(i));
    if (!w) {
      ++n_rejected;
      continue;
    }
    if (!is_finite(*w) || std::abs(length(*w) - 1.0) > 1e-4) {
      if (n_bad++ < 5) {
        char buf[160];
        std::snprintf(buf, sizeof buf, "  sample %d = (%.9g, %.9g, %.9g) is not a finite unit vector\n", i,
                      w->x, w->y, w->z);
        bad += buf;
      }
      continue;
    }
    if (!(pdf(*w) > 0)) {  // a sample where the pdf says it cannot be
      if (n_zero_pdf++ < 5) {
        char buf[160];
        std::snprintf(buf, sizeof buf, "  sample %d = (%.9g, %.9g, %.9g) has pdf 0\n", i, w->x, w->y, w->z);
        bad += buf;
      }
    }
    obs[size_t(cell_of(*w))] += 1;
  }

  // Expected counts: n × ∫cell pdf, to 1e-3·max(1, √E) counts per cell, so the bias (δE)²/E of each cell's χ²
  // term stays below 1e-6.
  Integrator in{pdf};
  const double dz = 2.0 / nt, dp = kTwoPi / np, n = std::max(1, n_samples);
  double mass = 0;
  for (int it = 0; it < nt; ++it)
    for (int ip = 0; ip < np; ++ip) {
      const double z0 = -1.0 + it * dz, z1 = (it + 1 == nt) ? 1.0 : z0 + dz;
      const double p0 = ip * dp, p1 = (ip + 1 == np) ? kTwoPi : p0 + dp;
      const double guess = std::abs(in.gl(z0, z1, p0, p1)) * n;
      const double m = in.integrate(z0, z1, p0, p1, 1e-3 * std::max(1.0, std::sqrt(guess)) / n);
      mass += m;
      expc[size_t(it * np + ip)] = m * n_samples;
    }

  // Pool low-expectation cells (ascending expectation) until the pool reaches 5; zero-mass cells must be
  // empty.
  std::vector<int> order(static_cast<size_t>(cells));
  std::iota(order.begin(), order.end(), 0);
  std::stable_sort(order.begin(), order.end(),
                   [&](int a, int b) { return expc[size_t(a)] < expc[size_t(b)]; });
  long in_empty_sliver = 0;
  double pool_o = 0, pool_e = 0, chi = 0;
  int used = 0;
  for (int c : order) {
    const double e = expc[size_t(c)], o = obs[size_t(c)];
    if (e <= 0) {
      // Samples here all have pdf > 0 (else n_zero_pdf fails the test): the cell's support is a sliver the
      // quadrature nodes missed. Such cells join the low-expectation pool; samples of zero pdf fail above.
      if (o > 0) ++in_empty_sliver, pool_o += o;
      continue;
    }
    if (e < 5 || pool_e > 0) {
      pool_o += o, pool_e += e;
      if (pool_e >= 5) chi += sqr(pool_o - pool_e) / pool_e, ++used, pool_o = pool_e = 0;
      continue;
    }
    chi += sqr(o - e) / e, ++used;
  }
  if (pool_e > 0) {
    // A last pool below 5 is merged into the statistic as one more cell (it only lowers the power slightly).
    chi += sqr(pool_o - pool_e) / pool_e, ++used;
  }
  r.statistic = chi;
  r.dof = std::max(1, used - 1);
  r.p_value = regularized_gamma_q(0.5 * r.dof, 0.5 * chi);
  const double alpha = 1.0 - std::pow(1.0 - significance, 1.0 / std::max(1, n_tests));
  r.pass = n_bad == 0 && n_zero_pdf == 0 && used > 0 && r.p_value >= alpha;
  if (r.pass) return r;

  // Failure report: summary, marginals, and the cells that contribute most to χ².
  std::string t;
  char buf[512];
  std::snprintf(buf, sizeof buf,
                "chi2 = %.3f, dof = %d, p = %.3g (threshold %.3g); samples %d, rejected %ld, malformed %ld, "
                "of zero pdf %ld, cells of zero computed mass holding samples %ld; integral of pdf over the "
                "sphere = %.6f\n",
                chi, r.dof, r.p_value, alpha, n_samples, n_rejected, n_bad, n_zero_pdf, in_empty_sliver,
                mass);
  t += buf + bad;
  t += "cos(theta) rows [z0, z1): observed vs expected\n";
  for (int it = nt - 1; it >= 0; --it) {
    double o = 0, e = 0;
    for (int ip = 0; ip < np; ++ip) o += obs[size_t(it * np + ip)], e += expc[size_t(it * np + ip)];
    if (o == 0 && e == 0) continue;
    std::snprintf(buf, sizeof buf, "  [%+.3f, %+.3f)  obs %10.0f  exp %12.2f\n", -1.0 + it * dz,
                  -1.0 + (it + 1) * dz, o, e);
    t += buf;
  }
  t += "phi columns: observed vs expected\n";
  for (int ip = 0; ip < np; ++ip) {
    double o = 0, e = 0;
    for (int it = 0; it < nt; ++it) o += obs[size_t(it * np + ip)], e += expc[size_t(it * np + ip)];
    std::snprintf(buf, sizeof buf, "  [%.4f, %.4f)  obs %10.0f  exp %12.2f\n", ip * dp, (ip + 1) * dp, o, e);
    t += buf;
  }
  std::vector<int> worst(static_cast<size_t>(cells));
  std::iota(worst.begin(), worst.end(), 0);
  auto contrib = [&](int c) {
    const double e = expc[size_t(c)], o = obs[size_t(c)];
    return e > 0 ? sqr(o - e) / e : (o > 0 ? 1e300 : 0.0);
  };
  std::stable_sort(worst.begin(), worst.end(), [&](int a, int b) { return contrib(a) > contrib(b); });
  t += "largest cell contributions (z range, phi range, obs, exp):\n";
  for (int k = 0; k < std::min(cells, 20); ++k) {
    const int c = worst[size_t(k)], it = c / np, ip = c % np;
    if (contrib(c) == 0) break;
    std::snprintf(buf, sizeof buf, "  z [%+.3f, %+.3f) phi [%.3f, %.3f)  obs %8.0f  exp %10.3f\n",
                  -1.0 + it * dz, -1.0 + (it + 1) * dz, ip * dp, (ip + 1) * dp, obs[size_t(c)],
                  expc[size_t(c)]);
    t += buf;
  }
  r.table = std::move(t);
  return r;
}

Chi2Result chi2_test_directions_stretched(const std::function<std::optional<Vec3d>(uint32_t)>& sample,
                                          const std::function<double(const Vec3d&)>& pdf, double ax,
                                          double ay, int n_samples, int theta_bins, int phi_bins,
                                          double significance, int n_tests) {
  auto fwd = [&](uint32_t i) -> std::optional<Vec3d> {
    const std::optional<Vec3d> w = sample(i);
    if (!w || !is_finite(*w)) return w;  // malformed samples are still reported by the plain test
    const double l = length(*w);
    if (std::abs(l - 1.0) > 1e-4) return *w;
    return normalize(Vec3d(w->x / ax, w->y / ay, w->z));
  };
  auto pdf_stretched = [&](const Vec3d& wp) {
    const Vec3d sw(ax * wp.x, ay * wp.y, wp.z);
    const double l = length(sw);
    return pdf(sw / l) * ax * ay / (l * l * l);
  };
  return chi2_test_directions(fwd, pdf_stretched, n_samples, theta_bins, phi_bins, significance, n_tests);
}

}  // namespace msh::test
