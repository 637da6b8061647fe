// Cloth BRDFs (RTR4 §9.10): empirical (Uncharted 2 rim/inner diffuse 9.70, wrap lighting 9.71, Disney sheen
// 9.72), microfacet (generalized velvet NDF 9.73 with the Ashikhmin-Premože BRDF 9.74; Imageworks sheen
// NDF 9.75 with the Estevez & Kulla 2017 fitted Smith Λ) and micro-cylinder (Kajiya-Kay 1989). Local shading
// frame: n = +z, t = x; directions point away from the surface. Header-only, templated on the scalar; every
// function returns finite values for every finite input (grazing, backfacing, zero parameters).
#pragma once

#include <microshadow/math/color.h>
#include <microshadow/math/sampling.h>
#include <microshadow/math/vec.h>

namespace msh::bsdf {

// ---------------------------------------------------------------------------------------------------------------
// Empirical models

// Uncharted 2 cloth diffuse (RTR4 9.70; Hable 2010): ρ/π (k_rim (v·n)⁺^a_rim + k_inner (1 − (v·n)⁺)^a_inner +
// k_diff). View-dependent only, so not reciprocal. Domain: exponents ≥ 0 (0^0 = 1). Directional albedo
// (closed form, since the value does not depend on l): ρ (k_rim μ^a_rim + k_inner (1−μ)^a_inner + k_diff).
template <class T>
Rgb<T> uncharted2_cloth_diffuse(const Rgb<T>& rho, T cos_v, T k_rim, T a_rim, T k_inner, T a_inner,
                                T k_diff) {
  const T mu = saturate(cos_v);
  const T s = k_rim * std::pow(mu, std::max(a_rim, T(0))) +
              k_inner * std::pow(T(1) - mu, std::max(a_inner, T(0))) + k_diff;
  return rho * (s * kInvPi<T>);
}

// Wrap lighting (RTR4 9.71, Uncharted 4): REPLACES f_diff(l,v)(n·l)⁺ by
// ρ/π · sat(c_scatter + sat(n·l)) · sat((n·l + w)/(1 + w)). Nonzero down to n·l = −w. Domain: w in [0,1]
// (clamped). The clamp is read as enclosing the whole fraction (the classic wrap term, Green 2004, GPU Gems
// ch. 16); RTR4's typesetting of 9.71 puts it on the numerator only, which would halve normal incidence
// when w = 1. c_scatter = 0, w = 0 gives ρ/π (n·l)² as printed, not Lambert: the scatter factor acts as a
// tint. Not a BRDF in the strict sense: it modifies the cosine too (use `wrap_diffuse_brdf` for f alone).
template <class T>
Rgb<T> wrap_diffuse_lighting(const Rgb<T>& rho, const Rgb<T>& c_scatter, T cos_l, T w) {
  w = saturate(w);
  const T nl = saturate(cos_l);
  const Rgb<T> s(saturate(c_scatter.r + nl), saturate(c_scatter.g + nl), saturate(c_scatter.b + nl));
  return rho * s * (kInvPi<T> * saturate((cos_l + w) / (T(1) + w)));
}

// 9.71 divided by (n·l)⁺, i.e. the equivalent BRDF above the horizon (zero for n·l ≤ 0, where the wrapped
// light is lost in a BRDF interface). (n·l) is floored at 1e-4 so the grazing value stays finite.
template <class T>
Rgb<T> wrap_diffuse_brdf(const Rgb<T>& rho, const Rgb<T>& c_scatter, T cos_l, T w) {
  if (!(cos_l > T(0))) return Rgb<T>(T(0));
  return wrap_diffuse_lighting(rho, c_scatter, cos_l, w) / std::max(cos_l, T(1e-4));
}

// Disney sheen colour (Burley 2012 via RTR4 §9.10.1): lerp(white, ρ/lum(ρ), tint). lum(ρ) = 0 gives white.
template <class T>
Rgb<T> disney_sheen_color(const Rgb<T>& rho, T tint) {
  const T lum = luminance(rho);
  const Rgb<T> hue = lum > T(0) ? rho / lum : Rgb<T>(T(1));
  return lerp(saturate(tint), Rgb<T>(T(1)), hue);
}

// Disney sheen (RTR4 9.72): k_sheen c_sheen (1 − (h·l)⁺)⁵. Reciprocal (h·l = h·v). Zero below either horizon.
template <class T>
Rgb<T> disney_sheen(const Vec3<T>& wo, const Vec3<T>& wi, const Rgb<T>& c_sheen, T k_sheen) {
  if (!(wo.z > T(0) && wi.z > T(0))) return Rgb<T>(T(0));
  const Vec3<T> h = normalize(wo + wi);
  const T m = T(1) - saturate(dot(h, wi));
  const T m2 = m * m;
  return c_sheen * (k_sheen * m2 * m2 * m);
}

// ---------------------------------------------------------------------------------------------------------------
// Generalized velvet (inverted Gaussian) NDF, RTR4 9.73 (Ashikhmin & Premože 2007; Neubelt & Pettineo 2013):
// D(m) = χ⁺(n·m)/(π(1 + k α²)) (1 + k exp(−cos²/(α² sin²)) / sin⁴). Normalized: ∫ D (n·m) dm = 1 for every
// α > 0, k ≥ 0 (the inverted-Gaussian part integrates to k α²). Domain: α clamped to ≥ 1e-3, k ≥ 0.
template <class T>
struct VelvetNdf {
  T alpha = T(0.5), k_amp = T(1);

  VelvetNdf(T a, T k) : alpha(std::max(a, T(1e-3))), k_amp(std::max(k, T(0))) {}

  T D(T cos_m) const {
    if (!(cos_m > T(0))) return T(0);
    const T c2 = std::min(cos_m * cos_m, T(1));
    const T s2 = T(1) - c2;
    const T a2 = alpha * alpha;
    T bump = T(0);
    // cot²/α² = c2/(α² s2): the exponential underflows to 0 long before s2 → 0, so skip it there (no 0/0).
    if (s2 > T(0)) {
      const T x = c2 / (a2 * s2);
      if (x < T(700)) bump = k_amp * std::exp(-x) / (s2 * s2);
    }
    return (T(1) + bump) / (kPi<T> * (T(1) + k_amp * a2));
  }

  // Samples m with pdf D(m)(n·m): a mixture of the cosine lobe (weight 1/(1 + kα²)) and the inverted Gaussian
  // (weight kα²/(1 + kα²)), whose cot θ = α sqrt(−ln(1 − ξ)) (cot² ~ Exponential with mean α²). Exact
  // inverse.
  Vec3<T> sample_ndf(Vec2<T> u) const {
    const T a2 = alpha * alpha;
    const T w_cos = T(1) / (T(1) + k_amp * a2);
    const T phi_u = u.y;
    if (u.x < w_cos) {
      const T ux = u.x / w_cos;  // reuse the stratum
      const T cos_t = std::sqrt(T(1) - std::min(ux, kOneMinusEpsilon<T>));
      return spherical_direction(cos_t, T(2) * kPi<T> * phi_u);
    }
    const T ux = std::min((u.x - w_cos) / (T(1) - w_cos), kOneMinusEpsilon<T>);
    const T cot = alpha * std::sqrt(-std::log1p(-ux));
    const T cos_t = cot / std::sqrt(T(1) + cot * cot);
    return spherical_direction(cos_t, T(2) * kPi<T> * phi_u);
  }
  T pdf_ndf(const Vec3<T>& wm) const { return D(wm.z) * std::max(wm.z, T(0)); }
};

// Ashikhmin-Premože "smooth" microfacet denominator used with 9.73 (RTR4 9.74): 1 / (4(n·l + n·v −
// (n·l)(n·v))), no masking-shadowing term. Finite for n·l, n·v ≥ 0 (the sum is 0 only when both are 0:
// returns 0 there).
template <class T>
T ashikhmin_denominator(T cos_l, T cos_v) {
  const T l = saturate(cos_l), v = saturate(cos_v);
  const T s = l + v - l * v;
  return s > T(0) ? T(1) / (T(4) * s) : T(0);
}

// Full cloth BRDF of RTR4 9.74 (The Order: 1886): (1 − F(h,l)) ρ/π + F(h,l) D(h) / (4(n·l + n·v −
// (n·l)(n·v))) with Schlick F (9.16) and the velvet NDF 9.73. Reciprocal. Zero below either horizon.
template <class T>
Rgb<T> velvet_cloth(const Vec3<T>& wo, const Vec3<T>& wi, const Rgb<T>& rho, const Rgb<T>& f0,
                    const VelvetNdf<T>& ndf) {
  if (!(wo.z > T(0) && wi.z > T(0))) return Rgb<T>(T(0));
  const Vec3<T> h = normalize(wo + wi);
  const T m = T(1) - saturate(dot(h, wi));
  const T w = m * m * m * m * m;
  const Rgb<T> F = f0 + (Rgb<T>(T(1)) - f0) * w;
  return (Rgb<T>(T(1)) - F) * rho * kInvPi<T> + F * (ndf.D(h.z) * ashikhmin_denominator(wi.z, wo.z));
}

// ---------------------------------------------------------------------------------------------------------------
// Imageworks sheen NDF (RTR4 9.75; Conty & Kulla 2017): D(m) = χ⁺(n·m)(2 + 1/α)(1 − (n·m)²)^(1/(2α)) / (2π).
// Normalized: ∫ D (n·m) dm = 1. Domain: α in (0,1], clamped to ≥ 1e-3 (at 1e-3 the lobe is a thin grazing
// ring).
template <class T>
struct SheenNdf {
  T alpha = T(0.5);

  explicit SheenNdf(T a) : alpha(clamp(a, T(1e-3), T(1))) {}

  T D(T cos_m) const {
    if (!(cos_m > T(0))) return T(0);
    const T s2 = std::max(T(0), T(1) - cos_m * cos_m);
    const T inv = T(1) / alpha;
    return (T(2) + inv) * std::pow(s2, T(0.5) * inv) / (T(2) * kPi<T>);
  }

  // pdf D(m)(n·m) is p(s) ∝ s^(1/α + 1) in s = sin θ on [0,1] (with ds = cos θ dθ): s = u^(α/(1 + 2α)).
  Vec3<T> sample_ndf(Vec2<T> u) const {
    const T s = std::pow(u.x, alpha / (T(1) + T(2) * alpha));
    const T c = safe_sqrt(T(1) - s * s);
    const T phi = T(2) * kPi<T> * u.y;
    return {s * std::cos(phi), s * std::sin(phi), c};
  }
  T pdf_ndf(const Vec3<T>& wm) const { return D(wm.z) * std::max(wm.z, T(0)); }

  // Estevez & Kulla 2017, "Production Friendly Microfacet Sheen BRDF", Table 1: Smith Λ of this NDF fitted as
  // L(x) = a/(1 + b x^c) + d x + e, Λ(μ) = exp(L(μ)) for μ < 1/2 and exp(2 L(1/2) − L(1 − μ)) otherwise; the
  // five coefficients are interpolated between the α = 0 and α = 1 fits with t = (1 − α)².
  // Domain: μ = |cos θ| in [0,1]; Λ(0) = +∞ is returned as the largest finite T.
  T Lambda(T cos_w) const {
    const T mu = std::min(std::abs(cos_w), T(1));
    if (!(mu > T(0))) return std::numeric_limits<T>::max();
    const T l = mu < T(0.5) ? fit_L(mu) : T(2) * fit_L(T(0.5)) - fit_L(T(1) - mu);
    return std::exp(l);
  }
  T G1(T cos_w) const { return T(1) / (T(1) + Lambda(cos_w)); }
  // Height-correlated G2 = 1/(1 + Λ(v) + Λ(l)) (RTR4 9.31), written through G1 so grazing stays finite.
  T G2(T cos_v, T cos_l) const {
    const T gv = G1(cos_v), gl = G1(cos_l);
    const T den = gv + gl - gv * gl;
    return den > T(0) ? gv * gl / den : T(0);
  }

 private:
  T fit_L(T x) const {
    const T t = sqr(T(1) - alpha);
    const T a = lerp(t, T(21.5473), T(25.3245));
    const T b = lerp(t, T(3.82987), T(3.32435));
    const T c = lerp(t, T(0.19823), T(0.16801));
    const T d = lerp(t, T(-1.97760), T(-1.27393));
    const T e = lerp(t, T(-4.32054), T(-4.85967));
    return a / (T(1) + b * std::pow(x, c)) + d * x + e;
  }
};

// Imageworks sheen BRDF: c_sheen D(h) G2(v,l) / (4 (n·v)(n·l)) (the microfacet BRDF 9.34 with F = 1, 9.75 and
// the fitted Λ). Reciprocal. Zero below either horizon.
template <class T>
Rgb<T> imageworks_sheen(const Vec3<T>& wo, const Vec3<T>& wi, const Rgb<T>& c_sheen, const SheenNdf<T>& ndf) {
  if (!(wo.z > T(0) && wi.z > T(0))) return Rgb<T>(T(0));
  const Vec3<T> h = normalize(wo + wi);
  // G2/(4 μo μi) through G1/μ = 1/(μ(1+Λ)): finite as μ → 0 because Λ grows faster than 1/μ.
  const T g = ndf.G2(wo.z, wi.z);
  const T v = g / (T(4) * wo.z * wi.z);
  return c_sheen * (ndf.D(h.z) * (std::isfinite(v) ? v : T(0)));
}

// ---------------------------------------------------------------------------------------------------------------
// Kajiya-Kay micro-cylinder specular (Kajiya & Kay 1989; Banks 1994; RTR4 §9.10.3): fibers along tangent t;
// the cone of mirror directions gives cos β = sin_l sin_v − (t·l)(t·v) (= 1 on the cone, since the mirror of
// l about a fiber normal has t·r = −t·l). f = k_d/π + k_s/π max(0, cos β)^p. Empirical and unnormalized (the
// original form, as used for silk/velvet in Uncharted 4): a lobe around a cone has no simple normalization,
// so the albedo is ≤ k_d + k_s (at p = 0) and falls with p. Reciprocal.
template <class T>
Rgb<T> kajiya_kay(const Vec3<T>& wo, const Vec3<T>& wi, const Vec3<T>& t, const Rgb<T>& k_d,
                  const Rgb<T>& k_s, T p) {
  if (!(wo.z > T(0) && wi.z > T(0))) return Rgb<T>(T(0));
  const T tl = clamp(dot(t, wi), T(-1), T(1)), tv = clamp(dot(t, wo), T(-1), T(1));
  const T cb = safe_sqrt(T(1) - tl * tl) * safe_sqrt(T(1) - tv * tv) - tl * tv;
  p = std::max(p, T(0));
  const T spec = cb > T(0) ? kInvPi<T> * std::pow(std::min(cb, T(1)), p) : T(0);
  return k_d * kInvPi<T> + k_s * spec;
}

}  // namespace msh::bsdf
