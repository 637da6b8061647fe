// Beckmann microfacet distribution with the Smith masking function (same interface as GGX<T>).
// RTR4 eqs. 9.35 (isotropic), 9.52 (anisotropic), 9.37–9.39 (Λ), 9.51 (anisotropic a); Heitz 2014,
// "Understanding the Masking-Shadowing Function"; visible-normal sampling: Heitz & d'Eon 2014, "Importance
// Sampling Microfacet-Based BSDFs using the Distribution of Visible Normals", with the numerical inversion of
// the slope CDF by Newton-bisection (Jakob 2014, as in Mitsuba and pbrt-v3).
//
// The Smith members shared with the other NDFs (G1, G1(w, m), G2, D(w, m), PDF, pdf_ndf) are in smith.h.
//
// Domain: alpha_x, alpha_y ≥ 0, not NaN (clamped to kMinAlpha; see AnisotropicAlpha); unit directions in the
// shading frame (n = +z). Every member returns a finite value for any finite unit input (grazing, backfacing,
// the pole).
#pragma once

#include <microshadow/math/sampling.h>
#include <microshadow/math/vec.h>
#include <microshadow/microfacet/smith.h>

#include <cmath>
#include <limits>

namespace msh {

// Inverse error function on (−1, 1); ±1 and beyond give ±(largest finite erfinv of T's last value below 1).
// Giles 2012 ("Approximating the erfinv function", GPU Computing Gems) single-precision polynomial, then
// Newton steps on std::erf (one for float, two for double) to full precision.
template <class T>
T erf_inv(T y) {
  const T ymax = T(1) - std::numeric_limits<T>::epsilon();
  if (!(y == y)) return T(0);
  y = clamp(y, -ymax, ymax);
  const double yd = double(y);
  double w = -std::log((1.0 - yd) * (1.0 + yd)), p;
  if (w < 5.0) {
    w -= 2.5;
    p = 2.81022636e-08;
    p = 3.43273939e-07 + p * w;
    p = -3.5233877e-06 + p * w;
    p = -4.39150654e-06 + p * w;
    p = 0.00021858087 + p * w;
    p = -0.00125372503 + p * w;
    p = -0.00417768164 + p * w;
    p = 0.246640727 + p * w;
    p = 1.50140941 + p * w;
  } else {
    w = std::sqrt(w) - 3.0;
    p = -0.000200214257;
    p = 0.000100950558 + p * w;
    p = 0.00134934322 + p * w;
    p = -0.00367342844 + p * w;
    p = 0.00573950773 + p * w;
    p = -0.0076224613 + p * w;
    p = 0.00943887047 + p * w;
    p = 1.00167406 + p * w;
    p = 2.83297682 + p * w;
  }
  double x = p * yd;
  for (int i = 0; i < (sizeof(T) > sizeof(float) ? 2 : 1); ++i) {
    const double d = 1.1283791670955126 * std::exp(-x * x);  // erf'(x) = 2/√π e^{−x²}
    if (d > 0) x -= (std::erf(x) - yd) / d;
  }
  return T(x);
}

template <class T>
class Beckmann : public SmithMicrofacet<Beckmann<T>, T>, public AnisotropicAlpha<T> {
 public:
  // Beckmann(), Beckmann(α), Beckmann(αx, αy); α below kMinAlpha is clamped, a NaN α propagates
  // (AnisotropicAlpha).
  using AnisotropicAlpha<T>::AnisotropicAlpha;
  using SmithMicrofacet<Beckmann<T>, T>::D;

  // D(m), 9.52: exp(−(x²/αx² + y²/αy²)/z²) / (π αx αy z⁴). Zero for m.z ≤ 0; underflows to 0 near the
  // horizon.
  T D(const Vec3<T>& wm) const {
    if (!(wm.z > T(0))) return T(0);
    const T z2 = sqr(wm.z);
    const T e = (sqr(wm.x / this->ax_) + sqr(wm.y / this->ay_)) / z2;  // tan²θ/α(φ)²
    if (!(e < T(700))) return T(0);
    return std::exp(-e) / (kPi<T> * this->ax_ * this->ay_ * z2 * z2);
  }

  // a = |n·s| / sqrt(αx²(t·s)² + αy²(b·s)²) (9.37, 9.51); +∞ at the pole.
  T a(const Vec3<T>& w) const {
    const T den = std::sqrt(this->projected_alpha2_sin2(w));
    return den > T(0) ? std::abs(w.z) / den : std::numeric_limits<T>::infinity();
  }

  // Exact Smith Λ (9.38): (erf(a) − 1)/2 + exp(−a²)/(2a√π). Written as (exp(−a²)/√π − a·erfc(a))/(2a), which
  // has no cancellation between erf(a) and 1 at large a; Λ = 0 beyond a = 26 (exp underflows in double).
  // Grazing (a = 0) gives the largest finite T.
  T Lambda(const Vec3<T>& w) const { return lambda_of_a(a(w)); }
  static T lambda_of_a(T a) {
    if (!(a > T(0))) return std::numeric_limits<T>::max();
    if (a > T(26)) return T(0);
    const double ad = double(a);
    // erfc(a) ≈ exp(−a²)/(a√π)(1 − 1/(2a²) + …) cancels the first term at large a: use the asymptotic series.
    double l;
    if (ad > 4.0) {
      const double inv2 = 1.0 / (2.0 * ad * ad);  // Λ ≈ e^{−a²}/(2a√π) · (1/(2a²) − 3/(4a⁴) + 15/(8a⁶) − …)
      const double s = inv2 * (1.0 - 3.0 * inv2 + 15.0 * inv2 * inv2 - 105.0 * inv2 * inv2 * inv2);
      l = std::exp(-ad * ad) / (2.0 * ad * 1.7724538509055160) * s;
    } else {
      l = (std::exp(-ad * ad) / 1.7724538509055160 - ad * std::erfc(ad)) / (2.0 * ad);
    }
    const double lmax = double(std::numeric_limits<T>::max());
    return T(l < lmax ? l : lmax);
  }
  // Walter et al. 2007 rational approximation (9.39): (1 − 1.259a + 0.396a²)/(3.535a + 2.181a²) for a < 1.6,
  // else 0. Stated accuracy: G1 = 1/(1 + Λ) within 0.35% of the exact form.
  T Lambda_approx(const Vec3<T>& w) const { return lambda_approx_of_a(a(w)); }
  static T lambda_approx_of_a(T a) {
    if (!(a > T(0))) return std::numeric_limits<T>::max();
    if (a >= T(1.6)) return T(0);
    const T l = (T(1) - T(1.259) * a + T(0.396) * a * a) / (T(3.535) * a + T(2.181) * a * a);
    return l < std::numeric_limits<T>::max() ? l : std::numeric_limits<T>::max();
  }

  // G1(w)/|cos θ| = 1/(|z|(1 + Λ)): finite at grazing (→ 2/(α(φ) sinθ)·… for large Λ via Λ·|z| limit).
  T G1_over_cos(const Vec3<T>& w) const {
    const T z = std::abs(w.z);
    const T s = std::sqrt(this->projected_alpha2_sin2(w));
    if (!(s > T(0))) return z > T(0) ? T(1) / z : T(0);
    // |z|·Λ(a) with a = z/s: as z → 0, zΛ → s/(2√π) (the first term of 9.38), so the sum stays positive.
    const T a = z / s;
    T zl;
    if (a < T(1e-6))
      zl = s * T(0.28209479177387814) - z * T(0.5);  // s/(2√π) − z/2 + O(a²)
    else
      zl = z * lambda_of_a(a);
    const T den = z + zl;
    return den > T(0) ? T(1) / den : T(0);
  }

  // Visible-normal sampling (Heitz & d'Eon 2014): stretch w to α = 1, sample the visible slope distribution
  // of the standard Beckmann surface (x by numerically inverting its CDF, y ~ N(0, 1/2)), rotate, unstretch.
  // pdf = D(w, m). w.z < 0 is mirrored to −w.
  Vec3<T> Sample_wm(const Vec3<T>& w, Vec2<T> u) const {
    Vec3<T> ws = normalize(Vec3<T>(this->ax_ * w.x, this->ay_ * w.y, w.z));
    if (ws.z < T(0)) ws = -ws;
    T sx, sy;
    sample_slopes_11(ws.z, u, sx, sy);
    const T cp = cos_phi(ws), sp = sin_phi(ws);
    const T x = (cp * sx - sp * sy) * this->ax_, y = (sp * sx + cp * sy) * this->ay_;
    return normalize(Vec3<T>(-x, -y, T(1)));
  }

  // Plain NDF sampling, pdf D(m)(n·m): anisotropic azimuth tan φ = (αy/αx) tan(2π u.y), then
  // tan²θ = −α(φ)² ln(1 − u.x) with 1/α(φ)² = cos²φ/αx² + sin²φ/αy² (Walter et al. 2007, eq. 28).
  Vec3<T> sample_ndf(Vec2<T> u) const {
    T c, s, inv_a2;
    this->ndf_sample_azimuth(u.y, c, s, inv_a2);
    const T tan2 = -std::log1p(-std::min(u.x, kOneMinusEpsilon<T>)) / inv_a2;
    return this->ndf_sample_direction(tan2, c, s);
  }

 private:
  // Slopes (x̃, ỹ) of a visible normal of the α = 1 Beckmann surface seen from cos θ = cos_t at φ = 0. The
  // marginal CDF of x̃ (x̃ < cot θ) in the variable b = erf(x̃) is ∝ 1 + b + tanθ e^{−x̃²}/√π; it is inverted by
  // safeguarded Newton iterations (bisection when a step leaves the bracket).
  static void sample_slopes_11(T cos_t, Vec2<T> u, T& sx, T& sy) {
    const double c = clamp(double(cos_t), 0.0, 1.0);
    const double u1 = clamp(double(u.x), 1e-7, 1.0 - 1e-7), u2 = clamp(double(u.y), 1e-7, 1.0 - 1e-7);
    sy = T(erf_inv(2.0 * u2 - 1.0));
    if (c > 0.99999) {  // normal incidence: the slope distribution is the NDF's, r² ~ Exp(1)
      const double r = std::sqrt(-std::log1p(-u1)), phi = 2.0 * kPi<double> * u2;
      sx = T(r * std::cos(phi)), sy = T(r * std::sin(phi));
      return;
    }
    const double s = std::sqrt(std::max(0.0, 1.0 - c * c));
    const double tan_t = c > 0 ? s / c : 1e300, cot_t = s > 0 ? c / s : 1e300;
    constexpr double kInvSqrtPi = 0.56418958354775628;
    double lo = -1.0, hi = std::erf(cot_t);
    const double norm =
        1.0 / (1.0 + hi + (tan_t < 1e150 ? kInvSqrtPi * tan_t * std::exp(-cot_t * cot_t) : 0.0));
    // Initial guess: a fit of the inverse CDF in θ (Jakob 2014).
    const double theta = std::acos(c);
    const double fit = 1.0 + theta * (-0.876 + theta * (0.4265 - 0.0594 * theta));
    double b = hi - (1.0 + hi) * std::pow(1.0 - u1, fit);
    const double tol = sizeof(T) > sizeof(float) ? 1e-12 : 1e-6;
    for (int it = 0; it < 40; ++it) {
      if (!(b >= lo && b <= hi)) b = 0.5 * (lo + hi);
      const double x = erf_inv(b);
      const double value = norm * (1.0 + b + kInvSqrtPi * tan_t * std::exp(-x * x)) - u1;
      const double deriv = norm * (1.0 - x * tan_t);
      if (std::abs(value) < tol) break;
      if (value > 0)
        hi = b;
      else
        lo = b;
      b -= value / deriv;
    }
    sx = T(erf_inv(b));
  }
};
static_assert(VisibleNormalSampler<Beckmann<float>> && VisibleNormalSampler<Beckmann<double>>);

}  // namespace msh
