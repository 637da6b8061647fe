// Generalized Trowbridge-Reitz (GTR) distribution, Burley 2012, RTR4 eqs. 9.46–9.47:
//   D(m) = k(α, γ) / (π (1 + (n·m)²(α² − 1))^γ), isotropic; γ = 2 is GGX, γ = 1 Burley's clear-coat lobe.
// GTR is not shape-invariant, so its Smith Λ has no closed form in general: Λ(μ) = (1/μ) ∫ D(m) (−v·m)⁺ dm
// (Heitz 2014, eq. 72 rearranged: the projected area of the back-facing microfacets), whose azimuthal
// integral is closed-form, leaving a 1D integral in θm done by adaptive Gauss-Kronrod at construction. r =
// Λ·sqrt(1 + x)/x, x = α²tan²θ, is tabulated against u = (2/π) atan(α tan θ) (r is smooth in u and finite and
// nonzero at both ends; for γ = 2 it is 1/(2(1 + cos(πu/2)))) and interpolated by a limited cubic, so Λ keeps
// its relative accuracy from the pole to grazing. Table build: deterministic, tens of ms
// (docs/microfacet.md); copies share the table.
//
// Domain: α ∈ [kMinAlpha, 1] is the intended range (α > 1 also works), γ ∈ [kMinGamma, kMaxGamma]; finite
// values outside are clamped to them, NaN is a precondition violation (it propagates as NaN, without building
// the table). Unit directions; finite results for grazing, backfacing and pole inputs. Same member names as
// GGX<T> except Sample_wm and PDF (no visible-normal sampler: only plain NDF sampling, exact inverse CDF);
// the Smith members (G1, G2, D(w, m), pdf_ndf) are smith.h's.
#pragma once

#include <microshadow/math/quadrature.h>
#include <microshadow/math/sampling.h>
#include <microshadow/math/vec.h>
#include <microshadow/microfacet/smith.h>

#include <array>
#include <cmath>
#include <limits>
#include <memory>
#include <utility>
#include <vector>

namespace msh {

// GTR normalization k(α, γ) (9.47), written with expm1/log so it is accurate near α = 1 and γ = 1 and does
// not overflow for large γ at small α: k = (γ−1)(α²−1)/(1 − α^{2(1−γ)}).
inline double gtr_normalization(double alpha, double gamma) {
  const double a2 = alpha * alpha, la2 = std::log(a2);
  if (a2 == 1.0) return 1.0;
  if (gamma == 1.0) return (a2 - 1.0) / la2;
  const double e = (1.0 - gamma) * la2;  // ln α^{2(1−γ)}
  if (e > 0)                             // γ > 1, α < 1 (or the reverse): divide through by α^{2(1−γ)}
    return (gamma - 1.0) * (a2 - 1.0) * std::exp(-e) / std::expm1(-e);
  return (gamma - 1.0) * (a2 - 1.0) / -std::expm1(e);
}

template <class T>
class GTR : public SmithMicrofacet<GTR<T>, T> {
  using Smith = SmithMicrofacet<GTR<T>, T>;

 public:
  using Smith::D;

  // Below α = 1e-2 the Λ-table quadrature can take seconds (the NDF peak is ~α wide); GTR is a rough-lobe
  // model.
  static constexpr T kMinAlpha = T(1e-2);
  static constexpr T kMinGamma = T(0.05), kMaxGamma = T(20);
  static constexpr int kTableSize = 257;

  GTR() : GTR(T(0.5), T(2)) {}
  GTR(T alpha, T gamma)
      : a_(alpha > kMinAlpha || std::isnan(alpha) ? alpha : kMinAlpha),
        g_(gamma > kMinGamma || std::isnan(gamma) ? std::min(gamma, kMaxGamma) : kMinGamma),
        log_k_(T(std::log(gtr_normalization(double(a_), double(g_))))),
        table_(build_table(double(a_), double(g_))) {}

  T alpha() const { return a_; }
  T gamma() const { return g_; }
  bool is_isotropic() const { return true; }

  // D(m) (9.46) evaluated as exp(ln k − γ ln(1 + z²(α² − 1)))/π: no overflow or underflow of the two factors.
  T D(const Vec3<T>& wm) const { return wm.z > T(0) ? T(D_of_cos(double(wm.z), log_k_, a_, g_)) : T(0); }

  // Smith Λ = r(u)·x/sqrt(1 + x) from the table, x = α²tan²θ, u = (2/π) atan(sqrt(x)); even in w.z. Grazing w
  // gives the largest finite T.
  T Lambda(const Vec3<T>& w) const {
    const double z = std::abs(double(w.z)), s2 = sqr(double(w.x)) + sqr(double(w.y));
    const double x = double(a_) * double(a_) * s2 / (z * z);
    if (!(x < 1e300)) return s2 > 0 ? std::numeric_limits<T>::max() : T(0);
    const double l = interp(2.0 * kInvPi<double> * std::atan(std::sqrt(x))) * x / std::sqrt(1.0 + x);
    return l < double(std::numeric_limits<T>::max()) ? T(l) : std::numeric_limits<T>::max();
  }
  // G1(w)/|cos θ|; at grazing its limit 1/(μΛ) → 1/∫D(m)(−v·m)⁺dm, taken from the table's last entry.
  T G1_over_cos(const Vec3<T>& w) const {
    const T z = std::abs(w.z);
    if (z > T(1e-4)) return this->G1(w) / z;
    return T(1) / (z + T(table_->grazing_back_area));
  }
  // Plain NDF sampling, pdf D(m)(n·m): t = cos²θ has density k(1 + t(α² − 1))^{−γ} on [0, 1], inverted in
  // closed form: t = (α²^… ) — t(α²−1) = expm1(log1p(u·expm1((1−γ) ln α²))/(1−γ)); γ = 1: t = expm1(u ln
  // α²)/(α² − 1).
  Vec3<T> sample_ndf(Vec2<T> u) const {
    const double ux = clamp(double(u.x), 0.0, 1.0), a2 = double(a_) * double(a_), la2 = std::log(a2);
    double t;
    if (std::abs(a2 - 1.0) < 1e-12) {
      t = ux;
    } else if (double(g_) == 1.0) {
      t = std::expm1(ux * la2) / (a2 - 1.0);
    } else {
      const double e = 1.0 - double(g_);
      t = std::expm1(std::log1p(ux * std::expm1(e * la2)) / e) / (a2 - 1.0);
    }
    const T cos_t = T(std::sqrt(clamp(t, 0.0, 1.0)));
    return spherical_direction(cos_t, T(2) * kPi<T> * u.y);
  }
  // Λ(θ) by direct quadrature (no table), in double: the reference the table is built from.
  static double lambda_reference(double cos_t, double alpha, double gamma) {
    const double mu = clamp(std::abs(cos_t), 0.0, 1.0);
    return mu > 0 ? back_area(mu, alpha, gamma, std::log(gtr_normalization(alpha, gamma))) / mu
                  : std::numeric_limits<double>::infinity();
  }

 private:
  struct Table {
    std::vector<double> q;      // r = Λ/(x cos(πu/2)) at u_i = i/(n−1), x = tan²(πu/2) = α²tan²θ
    std::vector<double> slope;  // monotone cubic (Fritsch-Carlson) tangents
    double grazing_back_area = 0.0;  // ∫ D(m)(−v·m)⁺ dm at grazing v
  };

  static double D_of_cos(double z, double log_k, double alpha, double gamma) {
    const double a2 = alpha * alpha;
    return std::exp(log_k - gamma * std::log1p(z * z * (a2 - 1.0))) / kPi<double>;
  }
  // ∫ D(m)(−v·m)⁺ dm for v at cos θv = mu. With A = sinθv sinθm, B = cosθv cosθm and ψ ∈ [0, π] the
  // half-width of the back-facing azimuth range (cos ψ = B/A), the φm integral of (−v·m)⁺ is 2A(sin ψ − ψ cos
  // ψ); it vanishes for θm < t0 = π/2 − θv. A − B = sin(θm − t0) and A + B = cos(θm − θv) are used directly,
  // and the series of sin ψ − ψ cos ψ for small ψ, so the integrand has no cancellation near t0 (where it is
  // ~ψ³). The θm integral uses Gauss-Kronrod.
  static double back_area(double mu, double alpha, double gamma, double log_k) {
    const double sv = std::sqrt(std::max(0.0, 1.0 - mu * mu));
    if (!(sv > 0)) return 0.0;
    const double theta_v = std::acos(mu);
    const double t0 = 0.5 * kPi<double> - theta_v;
    auto f = [&](double tm) {
      const double amb = std::sin(tm - t0), apb = std::cos(tm - theta_v);
      if (!(amb > 0) || !(apb > 0)) return amb > 0 ? 0.0 : 0.0;
      const double cm = std::cos(tm), sm = std::sin(tm);
      const double A = sv * sm, B = mu * cm;
      const double psi = std::atan2(std::sqrt(amb * apb), B);
      const double p2 = psi * psi;
      const double g = psi < 0.1 ? psi * p2 * (1.0 / 3.0 - p2 * (1.0 / 30.0 - p2 / 840.0))
                                 : std::sin(psi) - psi * std::cos(psi);
      return D_of_cos(cm, log_k, alpha, gamma) * 2.0 * A * g * sm;
    };
    // Panels graded (×4) from α/8 so the NDF peak at θm = 0 (inside the range at grazing v) is resolved.
    std::vector<std::pair<double, double>> panels;
    for (double b = alpha / 8.0, lo = t0; lo < 0.5 * kPi<double>; b *= 4.0) {
      const double hi = std::min(b, 0.5 * kPi<double>);
      if (hi > lo) panels.emplace_back(lo, hi), lo = hi;
    }
    // Absolute tolerance 1e-11 × a first estimate of the whole integral, or 1e-10 relative per panel.
    double est = 0.0;
    for (const auto& p : panels) est += std::abs(gauss_kronrod(f, p.first, p.second, 1e300, 0.0));
    const double tol = 1e-11 * est / double(panels.size());
    double sum = 0.0;
    for (const auto& p : panels) sum += gauss_kronrod(f, p.first, p.second, std::max(tol, 1e-17), 1e-10);
    return sum;
  }

  static std::shared_ptr<const Table> build_table(double alpha, double gamma) {
    auto t = std::make_shared<Table>();
    const int n = kTableSize;
    if (std::isnan(alpha) || std::isnan(gamma)) {  // precondition violated: NaN out, no quadrature
      t->q.assign(size_t(n), std::numeric_limits<double>::quiet_NaN());
      t->slope = t->q;
      t->grazing_back_area = t->q[0];
      return t;
    }
    const double log_k = std::log(gtr_normalization(alpha, gamma));
    t->grazing_back_area = back_area(0.0, alpha, gamma, log_k);
    t->q.resize(size_t(n));
    for (int i = 0; i < n; ++i) {
      // u = 0 holds the limit at the pole (taken at u = 1e-5: r is flat there to O(u²)); u = 1 the grazing
      // limit r → back_area(μ = 0)/α.
      if (i == n - 1) {
        t->q[size_t(i)] = t->grazing_back_area / alpha;
        continue;
      }
      const double u = i == 0 ? 1e-5 : double(i) / (n - 1);
      const double x = sqr(std::tan(0.5 * kPi<double> * u));
      const double mu = 1.0 / std::sqrt(1.0 + x / (alpha * alpha));  // cos θ with α tanθ = tan(πu/2)
      t->q[size_t(i)] = back_area(mu, alpha, gamma, log_k) / mu * std::sqrt(1.0 + x) / x;
    }
    // Central-difference tangents limited as in Fritsch-Carlson (|m| ≤ 3 min|d|, 0 at extrema): third-order
    // accurate where q is smooth, and the interpolant keeps q's monotonicity (no overshoot).
    std::vector<double> d(size_t(n - 1));
    const double h = 1.0 / (n - 1);
    for (int i = 0; i + 1 < n; ++i) d[size_t(i)] = (t->q[size_t(i + 1)] - t->q[size_t(i)]) / h;
    t->slope.resize(size_t(n));
    t->slope[0] = d[0];
    t->slope[size_t(n - 1)] = d[size_t(n - 2)];
    for (int i = 1; i + 1 < n; ++i) {
      const double a = d[size_t(i - 1)], b = d[size_t(i)];
      const double m = 0.5 * (a + b), bound = 3.0 * std::min(std::abs(a), std::abs(b));
      t->slope[size_t(i)] = (a * b <= 0) ? 0.0 : (std::abs(m) > bound ? std::copysign(bound, m) : m);
    }
    return t;
  }

  double interp(double u) const {
    const int n = kTableSize;
    const double x = clamp(u, 0.0, 1.0) * (n - 1);
    const int i = std::min(int(x), n - 2);
    const double s = x - i, h = 1.0 / (n - 1);
    const double y0 = table_->q[size_t(i)], y1 = table_->q[size_t(i + 1)];
    const double m0 = table_->slope[size_t(i)] * h, m1 = table_->slope[size_t(i + 1)] * h;
    const double s2 = s * s, s3 = s2 * s;
    const double v =
        (2 * s3 - 3 * s2 + 1) * y0 + (s3 - 2 * s2 + s) * m0 + (-2 * s3 + 3 * s2) * y1 + (s3 - s2) * m1;
    return std::max(v, 0.0);
  }

  T a_, g_, log_k_;
  std::shared_ptr<const Table> table_;
};
static_assert(SmithDistribution<GTR<double>> && !VisibleNormalSampler<GTR<double>>);

}  // namespace msh
