// Layered material: a clear coat over any base BRDF (RTR4 §9.12). The coat is a smooth-to-rough dielectric
// interface (GGX, exact dielectric Fresnel) with its own normal; the base is attenuated by the Fresnel
// transmission through the coat on the way in and out (the "Fresnel energy trade-off" of Disney 2012 / Unreal
// / Filament, here with the exact dielectric Fresnel at the coat normal), optionally tinted by Beer-Lambert
// absorption along the refracted path inside the coat (RTR4 §9.12, PxrSurface / Imageworks style).
//
// f(v, l) = f_coat(v, l) + (1 − F(n_c·v))(1 − F(n_c·l)) · τ^(1/cos θt(v) + 1/cos θt(l)) · f_base(v, l)
// where τ = the coat colour = transmittance of one vertical traversal (exp(−σ_a d)), cos θt = cosine of the
// direction refracted into the coat (Snell, IOR η). The base is evaluated with the unrefracted directions
// (as in the real-time clear coats RTR4 cites). Reciprocal when the base is. Directions in the shading frame
// (n = +z); the coat normal n_c is a unit vector in that frame (n_c = n for a flat coat).
#pragma once

#include <microshadow/bsdf/fresnel.h>
#include <microshadow/math/color.h>
#include <microshadow/math/vec.h>
#include <microshadow/microfacet/ggx.h>

namespace msh::bsdf {

template <class T>
struct ClearCoat {
  T ior = T(1.5);                     // coat IOR η relative to the outside, > 1 for a visible coat
  T alpha = T(0.01);                  // coat GGX α (= roughness²)
  Rgb<T> tint = Rgb<T>(T(1));         // transmittance of one vertical traversal, in [0,1]; 1 = clear
  Vec3<T> normal = Vec3<T>(0, 0, 1);  // coat normal in the shading frame

  ClearCoat() = default;
  ClearCoat(T ior_, T alpha_, const Rgb<T>& tint_, const Vec3<T>& n_c)
      : ior(std::max(ior_, T(1e-3))), alpha(alpha_), tint(tint_), normal(normalize(n_c)) {}

  // Coat specular lobe (microfacet BRDF 9.34 with GGX 9.41, height-correlated G2 9.31, exact dielectric F at
  // h·l) in the coat-normal frame. Zero unless both directions are above the geometric and the coat horizons.
  Rgb<T> f_coat(const Vec3<T>& wo, const Vec3<T>& wi) const {
    if (!(wo.z > T(0) && wi.z > T(0))) return Rgb<T>(T(0));
    const Frame<T> fr = Frame<T>::from_z(normal);
    const Vec3<T> o = fr.to_local(wo), i = fr.to_local(wi);
    if (!(o.z > T(0) && i.z > T(0))) return Rgb<T>(T(0));
    const GGX<T> ggx(alpha);
    const Vec3<T> h = normalize(o + i);
    const T F = fresnel_dielectric(dot(h, i), ior);
    // D G2 / (4 μo μi) via G1/μ (finite at grazing).
    const T go = ggx.G1(o), gi = ggx.G1(i);
    const T den = go + gi - go * gi;
    if (!(den > T(0))) return Rgb<T>(T(0));
    const T val = ggx.D(h) * ggx.G1_over_cos(o) * ggx.G1_over_cos(i) / (T(4) * den);
    return Rgb<T>(F * (std::isfinite(val) ? val : T(0)));
  }

  // Cosine of the direction refracted into the coat (Snell, RTR4 §9.5): sqrt(1 − (1 − μ²)/η²).
  T cos_refracted(T mu) const {
    const T m = saturate(mu);
    return safe_sqrt(T(1) - (T(1) - m * m) / (ior * ior));
  }

  // Multiplier applied to the base BRDF: Fresnel transmission in and out times Beer-Lambert absorption.
  Rgb<T> base_weight(const Vec3<T>& wo, const Vec3<T>& wi) const {
    const T co = dot(normal, wo), ci = dot(normal, wi);
    const T t_in = T(1) - fresnel_dielectric(saturate(ci), ior);
    const T t_out = T(1) - fresnel_dielectric(saturate(co), ior);
    // Path length through a coat of unit optical depth: 1/cos θt on each leg; cos θt ≥ sqrt(1 − 1/η²) > 0 for
    // η > 1. For η ≤ 1 the refracted cosine can reach 0: floor it so the exponent stays finite.
    const T path = T(1) / std::max(cos_refracted(co), T(1e-3)) + T(1) / std::max(cos_refracted(ci), T(1e-3));
    const auto absorb = [&](T c) { return c > T(0) ? std::pow(std::min(c, T(1)), path) : T(0); };
    return Rgb<T>(absorb(tint.r), absorb(tint.g), absorb(tint.b)) * (t_in * t_out);
  }

  // The layered BRDF given the base BRDF value f_base(wo, wi) (any model).
  Rgb<T> f(const Vec3<T>& wo, const Vec3<T>& wi, const Rgb<T>& f_base) const {
    if (!(wo.z > T(0) && wi.z > T(0))) return Rgb<T>(T(0));
    return f_coat(wo, wi) + base_weight(wo, wi) * f_base;
  }
};

}  // namespace msh::bsdf
