// The Smith microfacet interface shared by every NDF class (GGX, Beckmann, BlinnPhong, GTR), written once.
//
// A distribution supplies its NDF D(m) (normalized: ∫ D(m) (n·m) dm = 1, RTR4 9.21), its Smith Λ(w), the
// finite-at-grazing ratio G1(w)/|cos θ_w| and plain NDF sampling; SmithMicrofacet<Derived, T> (a CRTP base)
// derives the rest from them with the same formulas for every distribution:
//   G1(w) = 1/(1 + Λ(w))                                 RTR4 9.24 without χ⁺ (a class may override it with a
//                                                         closed form, as GGX does)
//   G1(w, m) = χ⁺((w·m)(w·n)) G1(w)                      9.24
//   G2(wo, wi) = 1/(1 + Λ(wo) + Λ(wi))                   9.31, height-correlated, written through G1 so that
//                                                         grazing directions stay finite
//   D_w(m) = G1(w) (w·m)⁺ D(m) / |w·n|                   Heitz 2014, eq. 16: the visible normals
//   PDF(w, m) = D_w(m)                                   only for classes that sample it (Sample_wm)
//   pdf_ndf(m) = D(m) (n·m)⁺                             pdf of sample_ndf
// Heitz 2014, "Understanding the Masking-Shadowing Function in Microfacet-Based BRDFs"; docs/theory.md §2.
// The concepts below state that interface, so generic code can require it.
#pragma once

#include <microshadow/math/vec.h>

#include <algorithm>
#include <cmath>
#include <concepts>
#include <limits>

namespace msh {

// A microfacet distribution with the Smith masking function, over directions in the shading frame (n = +z):
//   D(m), Lambda(w), G1(w), G1(w, m), G2(wo, wi), G1_over_cos(w), D(w, m) (visible normals),
//   sample_ndf(u) with pdf pdf_ndf(m) = D(m)(n·m)⁺.
// Every member is finite for finite unit inputs (grazing, backfacing, the pole included).
template <class Dist>
concept SmithDistribution = requires(const Dist& d, const Vec3<typename Dist::Scalar>& w,
                                     Vec2<typename Dist::Scalar> u) {
  typename Dist::Scalar;
  { d.D(w) } -> std::same_as<typename Dist::Scalar>;
  { d.Lambda(w) } -> std::same_as<typename Dist::Scalar>;
  { d.G1(w) } -> std::same_as<typename Dist::Scalar>;
  { d.G1(w, w) } -> std::same_as<typename Dist::Scalar>;
  { d.G2(w, w) } -> std::same_as<typename Dist::Scalar>;
  { d.G1_over_cos(w) } -> std::same_as<typename Dist::Scalar>;
  { d.D(w, w) } -> std::same_as<typename Dist::Scalar>;
  { d.sample_ndf(u) } -> std::same_as<Vec3<typename Dist::Scalar>>;
  { d.pdf_ndf(w) } -> std::same_as<typename Dist::Scalar>;
};

// A Smith distribution that also samples its visible normals exactly: Sample_wm(w, u) draws m with pdf
// PDF(w, m) = D(w, m) (GGX, Beckmann; not BlinnPhong or GTR, whose Λ is not exact for their D).
template <class Dist>
concept VisibleNormalSampler = SmithDistribution<Dist> &&
    requires(const Dist& d, const Vec3<typename Dist::Scalar>& w, Vec2<typename Dist::Scalar> u) {
  { d.Sample_wm(w, u) } -> std::same_as<Vec3<typename Dist::Scalar>>;
  { d.PDF(w, w) } -> std::same_as<typename Dist::Scalar>;
};

// CRTP base: Derived provides D(m), Lambda(w), G1_over_cos(w), sample_ndf(u) (and optionally its own G1(w)
// and Sample_wm). Derived classes re-export the overloads with `using Base::D; using Base::G1;`.
template <class Derived, class T>
class SmithMicrofacet {
 public:
  using Scalar = T;

  // G1(w) = 1/(1 + Λ(w)); 0 where Λ is the largest finite T (grazing).
  T G1(const Vec3<T>& w) const {
    const T l = self().Lambda(w);
    return l < std::numeric_limits<T>::max() ? T(1) / (T(1) + l) : T(0);
  }
  // G1(w, m) with the χ⁺ factor: zero when w sees the back of the microfacet (sign(w·m) ≠ sign(w·n)).
  T G1(const Vec3<T>& w, const Vec3<T>& wm) const { return dot(w, wm) * w.z > T(0) ? self().G1(w) : T(0); }
  // Height-correlated G2 without χ⁺ factors: 1/(1/G1o + 1/G1i − 1) = G1o G1i/(G1o + G1i − G1o G1i).
  T G2(const Vec3<T>& wo, const Vec3<T>& wi) const {
    const T go = self().G1(wo), gi = self().G1(wi);
    const T den = go + gi - go * gi;
    return den > T(0) ? go * gi / den : T(0);
  }
  // Visible normals D_w(m) = G1(w) (w·m)⁺ D(m) / |w·n|; w.z < 0 uses −w (as the samplers do). Integrates to
  // 1 over m exactly where Λ is exact for D (GGX, Beckmann; GTR up to its Λ table, BlinnPhong only
  // approximately).
  T D(const Vec3<T>& w, const Vec3<T>& wm) const {
    const Vec3<T> wu = w.z < T(0) ? -w : w;
    const T d = self().D(wm);
    return d > T(0) ? self().G1_over_cos(wu) * std::max(T(0), dot(wu, wm)) * d : T(0);
  }
  // pdf (solid angle, over m) of Sample_wm: the visible-normal distribution. (The constraint is on a
  // defaulted template parameter so that it is checked where Derived is complete: clang 14 checks it too
  // early otherwise.)
  template <class Self = Derived>
  requires requires(const Self& d, const Vec3<T>& v) { d.Sample_wm(v, Vec2<T>()); }
  T PDF(const Vec3<T>& w, const Vec3<T>& wm) const { return D(w, wm); }
  // pdf of sample_ndf (solid angle): D(m) (n·m)⁺.
  T pdf_ndf(const Vec3<T>& wm) const { return self().D(wm) * std::max(T(0), wm.z); }

 protected:
  SmithMicrofacet() = default;

 private:
  const Derived& self() const { return static_cast<const Derived&>(*this); }
};

// Anisotropic roughness (αx along t, αy along b) of the shape-invariant distributions GGX and Beckmann.
// Precondition: α is not NaN. Finite (and −∞) values below kMinAlpha are clamped to it, so roughness 0 is a
// very sharp but finite lobe; a NaN α is not clamped (it would silently become a mirror): it propagates as
// NaN, and the CLI and the BRDF registry reject it as an input error before it gets here.
template <class T>
class AnisotropicAlpha {
 public:
  // Below this α the lobe is treated as a (near) mirror; D stays finite in float.
  static constexpr T kMinAlpha = T(1e-4);

  T alpha_x() const { return ax_; }
  T alpha_y() const { return ay_; }
  bool is_isotropic() const { return ax_ == ay_; }
  // Roughness so small that a renderer should treat the lobe as a delta: both αx and αy below 1e-3. We test
  // max(αx, αy) so that an anisotropic lobe that is sharp along one axis but rough along the other keeps its
  // microfacet evaluation (a delta would drop its spread). pbrt-v4's TrowbridgeReitzDistribution uses the
  // same 1e-3 but on min(αx, αy), so it treats such a lobe as specular. Nothing in the library calls this.
  bool effectively_smooth() const { return std::max(ax_, ay_) < T(1e-3); }

  // Projected roughness α(φ_w)² = αx² cos²φ + αy² sin²φ times sin²θ: the stretched tangential length²
  // (RTR4 9.51).
  T projected_alpha2_sin2(const Vec3<T>& w) const { return sqr(ax_ * w.x) + sqr(ay_ * w.y); }

  // Inherited as the constructors of GGX and Beckmann: D(), D(α), D(αx, αy).
  AnisotropicAlpha() = default;
  explicit AnisotropicAlpha(T alpha) : AnisotropicAlpha(alpha, alpha) {}
  AnisotropicAlpha(T alpha_x, T alpha_y) : ax_(clamp_alpha(alpha_x)), ay_(clamp_alpha(alpha_y)) {}

 protected:
  static T clamp_alpha(T a) { return a > kMinAlpha || std::isnan(a) ? a : kMinAlpha; }

  // Azimuth of a plain NDF sample of an anisotropic shape-invariant NDF, tan φ = (αy/αx) tan(2π u), and
  // 1/α(φ)² = cos²φ/αx² + sin²φ/αy² (Walter et al. 2007, eq. 28 generalized; RTR4 9.51).
  void ndf_sample_azimuth(T u, T& cos_phi, T& sin_phi, T& inv_alpha2) const {
    const T a = T(2) * kPi<T> * u;
    const T phi = std::atan2(ay_ * std::sin(a), ax_ * std::cos(a));
    cos_phi = std::cos(phi), sin_phi = std::sin(phi);
    inv_alpha2 = sqr(cos_phi / ax_) + sqr(sin_phi / ay_);
  }

  // The direction of a plain NDF sample with tan²θ = tan2 at azimuth (cos φ, sin φ).
  static Vec3<T> ndf_sample_direction(T tan2, T cos_phi, T sin_phi) {
    const T cos_t = T(1) / std::sqrt(T(1) + tan2);
    const T sin_t = safe_sqrt(T(1) - cos_t * cos_t);
    return {sin_t * cos_phi, sin_t * sin_phi, cos_t};
  }

  T ax_ = T(0.5), ay_ = T(0.5);
};

// The two Smith masking-shadowing forms G2 (Real-Time Rendering 4th ed., §9.7; Heitz 2014, "Understanding the
// Masking-Shadowing Function in Microfacet-Based BRDFs"): height-correlated, eq. 9.31, 1 / (1 + Λ(v) + Λ(l));
// separable (also called uncorrelated), eq. 9.27, G1(v) G1(l). The one enum of the library.
enum class G2Form {
  HeightCorrelated,
  Separable,
  Uncorrelated = Separable,  // Zurita 2026's name for the same form
};

// Smith G2 from the two G1 values (no χ⁺: the caller has checked the facet's sidedness). Height-correlated
// written as G1o G1i / (G1o + G1i − G1o G1i) = 1/(1 + Λo + Λi): finite at grazing.
template <class T>
T smith_g2(T g1o, T g1i, G2Form form) {
  if (form == G2Form::Separable) return g1o * g1i;
  const T den = g1o + g1i - g1o * g1i;
  return den > T(0) ? g1o * g1i / den : T(0);
}

// G2 / G1(wo): the weight of an estimator that samples the VNDF of wo. Height-correlated:
// G1i / (G1o + G1i − G1o G1i), which is 1 at G1o = 0 (grazing view), so the weight stays finite where both G2
// and G1(wo) vanish.
template <class T>
T smith_g2_over_g1o(T g1o, T g1i, G2Form form) {
  if (form == G2Form::Separable) return g1i;
  const T den = g1o + g1i - g1o * g1i;
  return den > T(0) ? g1i / den : T(0);
}

}  // namespace msh
