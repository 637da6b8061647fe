// LEAN mapping (Olano & Baker 2010, "LEAN Mapping", I3D) and CLEAN mapping (Baker 2011, "Spectacular
// Specular: LEAN and CLEAN Specular Highlights", GDC); RTR4 §9.13.1. A normal n is stored as its slope
// b = (−n_x/n_z, −n_y/n_z) plus the second moments M = b bᵀ + Σ_base; both filter linearly (mipmaps,
// bilinear), and the filtered covariance Σ = M̄ − b̄ b̄ᵀ is the width of the combined NDF. Roughness link: a
// Beckmann lobe of roughness α has per-axis slope variance α²/2 (D ∝ exp(−|b|²/α²)); GGX uses the same
// mapping, as the variance-based family does in practice (RTR4 §9.13.1: GGX variance is undefined).
// Header-only, templated on the scalar, no I/O.
#pragma once

#include <microshadow/math/vec.h>

namespace msh::filter {

// Linear moments of a texel (or of a filtered footprint). Add and scale to filter; divide by the weight sum.
template <class T>
struct LeanMoments {
  T bx = 0, by = 0;             // mean slope
  T mxx = 0, myy = 0, mxy = 0;  // mean second moments, including the base roughness
  T weight = 0;                 // sum of weights (the filter's normalisation)

  // Slope and moments of a unit normal (n_z clamped to ≥ 1e-4) with base roughness α_x, α_y (per-axis slope
  // variance k α²/2 added on the diagonal; k = 1 is the Beckmann mapping, see variance_mapping.h). Weight 1.
  static LeanMoments from_normal(const Vec3<T>& n, T alpha_x, T alpha_y, T k = T(1)) {
    const Vec3<T> u = normalize(n);
    const T z = std::max(u.z, T(1e-4));
    LeanMoments m;
    m.bx = -u.x / z;
    m.by = -u.y / z;
    m.mxx = m.bx * m.bx + T(0.5) * k * alpha_x * alpha_x;
    m.myy = m.by * m.by + T(0.5) * k * alpha_y * alpha_y;
    m.mxy = m.bx * m.by;
    m.weight = T(1);
    return m;
  }
  LeanMoments& operator+=(const LeanMoments& o) {
    bx += o.bx, by += o.by, mxx += o.mxx, myy += o.myy, mxy += o.mxy, weight += o.weight;
    return *this;
  }
  // Mean over the accumulated weight (weight becomes 1). Zero weight → zero moments.
  LeanMoments normalized() const {
    if (!(weight > T(0))) return {};
    const T s = T(1) / weight;
    return {bx * s, by * s, mxx * s, myy * s, mxy * s, T(1)};
  }
};

// Filtered covariance Σ = M̄ − b̄ b̄ᵀ (Olano & Baker 2010, §3), of normalized moments. Diagonal clamped ≥ 0.
template <class T>
struct SlopeCovariance {
  T xx = 0, yy = 0, xy = 0;
};
template <class T>
SlopeCovariance<T> lean_covariance(const LeanMoments<T>& m) {
  return {std::max(T(0), m.mxx - m.bx * m.bx), std::max(T(0), m.myy - m.by * m.by), m.mxy - m.bx * m.by};
}

// Axis-aligned anisotropic α from Σ (α² = 2 σ² per axis); the off-diagonal (oriented anisotropy) is dropped.
template <class T>
Vec2<T> lean_alpha_xy(const SlopeCovariance<T>& s) {
  return {std::sqrt(T(2) * s.xx), std::sqrt(T(2) * s.yy)};
}
// Isotropic α: α² = σ_xx + σ_yy (twice the mean per-axis variance). The CLEAN-mapping result.
template <class T>
T lean_alpha_isotropic(const SlopeCovariance<T>& s) {
  return std::sqrt(s.xx + s.yy);
}

// CLEAN mapping: only b and the scalar m = |b|² + α² (i.e. 2 × mean per-axis variance) are stored;
// α'² = m̄ − |b̄|². Isotropic. Equivalent to lean_alpha_isotropic for the same inputs.
template <class T>
struct CleanMoments {
  T bx = 0, by = 0, m = 0, weight = 0;
  static CleanMoments from_normal(const Vec3<T>& n, T alpha) {
    const Vec3<T> u = normalize(n);
    const T z = std::max(u.z, T(1e-4));
    const T bx = -u.x / z, by = -u.y / z;
    return {bx, by, bx * bx + by * by + alpha * alpha, T(1)};
  }
  CleanMoments& operator+=(const CleanMoments& o) {
    bx += o.bx, by += o.by, m += o.m, weight += o.weight;
    return *this;
  }
  T alpha() const {
    if (!(weight > T(0))) return T(0);
    const T s = T(1) / weight;
    return safe_sqrt(m * s - sqr(bx * s) - sqr(by * s));
  }
};

}  // namespace msh::filter
