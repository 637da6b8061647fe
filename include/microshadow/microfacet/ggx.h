// GGX / Trowbridge-Reitz microfacet distribution with the Smith masking function.
// RTR4 eqs. 9.41 (isotropic), 9.53 (anisotropic), 9.24 (G1), 9.31 (height-correlated G2); Heitz 2014,
// "Understanding the Masking-Shadowing Function in Microfacet-Based BRDFs". All directions are in the local
// shading frame (n = +z, t = x, b = y) and need not be in the upper hemisphere unless stated. The Smith
// members shared with the other NDFs (G1(w, m), G2, D(w, m), PDF, pdf_ndf) are in smith.h.
//
// Domain: alpha_x, alpha_y ≥ 0, not NaN (values below kMinAlpha are clamped to it, so roughness 0 is a very
// sharp but finite lobe; see AnisotropicAlpha); unit-length directions. Every member returns a finite value
// for any finite unit input, including grazing (z = 0) and backfacing directions.
#pragma once

#include <microshadow/math/sampling.h>
#include <microshadow/math/vec.h>
#include <microshadow/microfacet/smith.h>

#include <limits>

namespace msh {

template <class T>
class GGX : public SmithMicrofacet<GGX<T>, T>, public AnisotropicAlpha<T> {
 public:
  // GGX(), GGX(α), GGX(αx, αy); α below kMinAlpha is clamped, a NaN α propagates (AnisotropicAlpha).
  using AnisotropicAlpha<T>::AnisotropicAlpha;
  using SmithMicrofacet<GGX<T>, T>::D;
  using SmithMicrofacet<GGX<T>, T>::G1;

  // NDF D(m), 9.53, written as 1 / (π αx αy (x²/αx² + y²/αy² + z²)²): no tan, exact at the pole.
  // Normalized so that ∫ D(m) (n·m) dm = 1. Zero for m.z ≤ 0.
  T D(const Vec3<T>& wm) const {
    if (!(wm.z > T(0))) return T(0);
    const T k = sqr(wm.x / this->ax_) + sqr(wm.y / this->ay_) + sqr(wm.z);
    return T(1) / (kPi<T> * this->ax_ * this->ay_ * k * k);
  }

  // Projected roughness along the azimuth of w (Zurita 2026b, "Improving Direct Lighting Material Occlusion –
  // Part 2": ProjectRoughnessGGX; RTR4 (9.51)). α at the pole.
  T projected_alpha(const Vec3<T>& w) const {
    const T s2 = sqr(w.x) + sqr(w.y);
    if (!(s2 > T(0))) return std::sqrt(T(0.5) * (this->ax_ * this->ax_ + this->ay_ * this->ay_));
    return std::sqrt(this->projected_alpha2_sin2(w) / s2);
  }

  // Smith Λ(w) = (−1 + sqrt(1 + α²tan²θ)) / 2 (9.37 with a from 9.51), in the cancellation-free form
  // x / (2(1 + sqrt(1 + x))), x = α²tan²θ. Even in w.z. Grazing w (z = 0) gives the largest finite T.
  T Lambda(const Vec3<T>& w) const {
    const T z2 = sqr(w.z);
    const T x = this->projected_alpha2_sin2(w) / z2;
    if (!(x < std::numeric_limits<T>::infinity())) return std::numeric_limits<T>::max();
    return x / (T(2) * (T(1) + std::sqrt(T(1) + x)));
  }

  // G1(w) = 1 / (1 + Λ(w)) (9.24 without the χ⁺ factor).
  T G1(const Vec3<T>& w) const {
    // 2|z| / (|z| + sqrt(z² + αx²x² + αy²y²)): the same value, finite and exact at grazing.
    const T z = std::abs(w.z);
    const T den = z + std::sqrt(sqr(w.z) + this->projected_alpha2_sin2(w));
    return den > T(0) ? T(2) * z / den : T(1);
  }
  // G1(w) / |cos θ_w| = 2 / (|z| + sqrt(z² + αx²x² + αy²y²)): finite at grazing, where both factors vanish.
  T G1_over_cos(const Vec3<T>& w) const {
    const T den = std::abs(w.z) + std::sqrt(sqr(w.z) + this->projected_alpha2_sin2(w));
    return den > T(0) ? T(2) / den : T(0);
  }

  // Default visible-normal sampler: Dupuy & Benyoub 2023.
  Vec3<T> Sample_wm(const Vec3<T>& w, Vec2<T> u) const { return sample_vndf_spherical_caps(w, u); }

  // Dupuy & Benyoub 2023, "Sampling Visible GGX Normals with Spherical Caps" (HPG): in the stretched
  // (α = 1) configuration the visible normals are the half vectors between w and a uniform point on the
  // spherical cap z ≥ −w.z. Samples m with pdf D(w, m). w.z < 0 is mirrored to −w.
  Vec3<T> sample_vndf_spherical_caps(const Vec3<T>& w, Vec2<T> u) const {
    Vec3<T> wi = normalize(Vec3<T>(this->ax_ * w.x, this->ay_ * w.y, w.z));
    if (wi.z < T(0)) wi = -wi;
    const T phi = T(2) * kPi<T> * u.x;
    return sample_vndf_spherical_caps_stretched(wi, u.y, std::cos(phi), std::sin(phi));
  }

  // The same sampler for a caller that hoists the per-direction and per-azimuth work out of a loop (the LUT
  // baker): wi = the stretched, normalized w with wi.z ≥ 0; (cos_phi, sin_phi) = the cosine and sine of 2π
  // u.x.
  Vec3<T> sample_vndf_spherical_caps_stretched(const Vec3<T>& wi, T u_y, T cos_phi, T sin_phi) const {
    // z = (1 − u.y)(1 + wi.z) − wi.z. sin² = 1 − z² = (1 − z)(1 + z) with 1 − z = u.y(1 + wi.z) and
    // 1 + z = (1 − u.y)(1 + wi.z) + (1 − wi.z): no cancellation at either pole (1 − z² lost ~1e-4 in float).
    const T one_minus_z = u_y * (T(1) + wi.z);
    const T one_plus_z = (T(1) - u_y) * (T(1) + wi.z) + (T(1) - wi.z);
    const T z = (T(1) - u_y) * (T(1) + wi.z) - wi.z;
    const T s = safe_sqrt(one_minus_z * one_plus_z);
    const Vec3<T> h = Vec3<T>(s * cos_phi, s * sin_phi, z) + wi;
    return normalize(Vec3<T>(this->ax_ * h.x, this->ay_ * h.y, std::max(T(0), h.z)));
  }

  // Heitz 2018, "Sampling the GGX Distribution of Visible Normals" (JCGT 7(4)): stretch, sample the projected
  // hemisphere as a disk warped by s = (1 + z)/2, unstretch. Same distribution as the spherical-caps sampler.
  Vec3<T> sample_vndf_heitz2018(const Vec3<T>& w, Vec2<T> u) const {
    Vec3<T> vh = normalize(Vec3<T>(this->ax_ * w.x, this->ay_ * w.y, w.z));
    if (vh.z < T(0)) vh = -vh;
    const T lensq = vh.x * vh.x + vh.y * vh.y;
    const Vec3<T> t1 = lensq > T(0) ? Vec3<T>(-vh.y, vh.x, T(0)) / std::sqrt(lensq) : Vec3<T>(1, 0, 0);
    const Vec3<T> t2 = cross(vh, t1);
    const T r = std::sqrt(u.x);
    const T phi = T(2) * kPi<T> * u.y;
    const T p1 = r * std::cos(phi);
    const T sblend = T(0.5) * (T(1) + vh.z);
    const T p2 = (T(1) - sblend) * safe_sqrt(T(1) - p1 * p1) + sblend * r * std::sin(phi);
    const Vec3<T> nh = p1 * t1 + p2 * t2 + safe_sqrt(T(1) - p1 * p1 - p2 * p2) * vh;
    return normalize(Vec3<T>(this->ax_ * nh.x, this->ay_ * nh.y, std::max(T(0), nh.z)));
  }

  // Plain NDF sampling: m with pdf D(m) (n·m) (solid angle). Anisotropic azimuth from
  // tan φ = (αy/αx) tan(2π u.y), then tan²θ = α(φ)² u.x / (1 − u.x) with 1/α(φ)² = cos²φ/αx² + sin²φ/αy².
  Vec3<T> sample_ndf(Vec2<T> u) const {
    T c, s, inv_a2;
    this->ndf_sample_azimuth(u.y, c, s, inv_a2);
    const T tan2 = u.x / ((T(1) - u.x) * inv_a2);
    return this->ndf_sample_direction(tan2, c, s);
  }
};
static_assert(VisibleNormalSampler<GGX<float>> && VisibleNormalSampler<GGX<double>>);

// User-facing perceptual roughness r ∈ [0,1] to GGX/Beckmann α = r² (Burley 2012; docs/theory.md §1).
template <class T>
constexpr T roughness_to_alpha(T r) {
  return r * r;
}

}  // namespace msh
