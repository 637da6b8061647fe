// Bounded VNDF sampling for Smith-GGX reflections, Eto & Tokuyoshi 2023 (SIGGRAPH Asia Technical
// Communications), built on the spherical-caps sampler of Dupuy & Benyoub 2023
// (GGX<T>::sample_vndf_spherical_caps). In the stretched (α = 1) configuration the visible normals are the
// half vectors between wi_std and a uniform point of the spherical cap z ≥ −wi_std.z; the bounded sampler
// shrinks the cap to z ≥ −k·wi_std.z, removing only microfacets whose reflection of wi would point below the
// horizon (k from their Eq. 5 with the bound α = min(αx, αy) of Eq. 6, for α ≤ 1). The result is a TRUNCATED
// distribution with a lower pdf variance for reflection sampling: never use it to estimate quantities of the
// full VNDF (e.g. the micro-shadowing ratio).
//
// Domain: wi in the upper hemisphere (wi.z < 0 is mirrored to −wi, as in GGX<T>::Sample_wm); u ∈ [0,1)².
#pragma once

#include <microshadow/math/vec.h>
#include <microshadow/microfacet/ggx.h>

#include <cmath>

namespace msh {

// Cap shrink factor k ∈ (0, 1] of Eto & Tokuyoshi 2023, Eq. 5: k = (1 − a²)s² / (s² + a²wi.z²),
// s = 1 + |wi.xy|, a = min(αx, αy, 1) (Eq. 6). wi.z is taken as |wi.z|; k = 1 for a ≥ 1 (no bound).
template <class T>
T bounded_vndf_k(const GGX<T>& g, const Vec3<T>& wi) {
  const T a = saturate(std::min(g.alpha_x(), g.alpha_y()));
  const T s = T(1) + std::sqrt(wi.x * wi.x + wi.y * wi.y);
  const T a2 = a * a, s2 = s * s;
  const T den = s2 + a2 * wi.z * wi.z;
  return den > T(0) ? (T(1) - a2) * s2 / den : T(1);
}

// Samples a microfacet normal m with pdf pdf_bounded_vndf(g, wi, m) (Eto & Tokuyoshi 2023, Listing 1).
template <class T>
Vec3<T> sample_bounded_vndf(const GGX<T>& g, const Vec3<T>& w, Vec2<T> u) {
  const T ax = g.alpha_x(), ay = g.alpha_y();
  const Vec3<T> wi = w.z < T(0) ? -w : w;
  const Vec3<T> wi_std = normalize(Vec3<T>(ax * wi.x, ay * wi.y, wi.z));
  const T b = bounded_vndf_k(g, wi) * wi_std.z;
  const T phi = T(2) * kPi<T> * u.x;
  const T z = (T(1) - u.y) * (T(1) + b) - b;
  const T st = safe_sqrt(T(1) - z * z);
  const Vec3<T> h = Vec3<T>(st * std::cos(phi), st * std::sin(phi), z) + wi_std;
  return normalize(Vec3<T>(ax * h.x, ay * h.y, std::max(T(0), h.z)));
}

// pdf over m (solid angle) of sample_bounded_vndf: D(m)·2(wi·m)/(k wi.z + t), t = |(αx wi.x, αy wi.y, wi.z)|
// (the VNDF scaled by (wi.z + t)/(k wi.z + t)), and 0 where the stretched reflection of wi about m falls
// outside the shrunk cap (z < −k·wi_std.z) or where wi·m ≤ 0.
template <class T>
T pdf_bounded_vndf(const GGX<T>& g, const Vec3<T>& w, const Vec3<T>& wm) {
  const T ax = g.alpha_x(), ay = g.alpha_y();
  const Vec3<T> wi = w.z < T(0) ? -w : w;
  const T wim = dot(wi, wm);
  if (!(wim > T(0)) || !(wm.z > T(0))) return T(0);
  const T t = std::sqrt(sqr(ax * wi.x) + sqr(ay * wi.y) + sqr(wi.z));
  const T k = bounded_vndf_k(g, wi);
  // Cap point = reflection of wi_std about the stretched normal h ∝ (m.x/αx, m.y/αy, m.z).
  const Vec3<T> wi_std = t > T(0) ? Vec3<T>(ax * wi.x, ay * wi.y, wi.z) / t : Vec3<T>(0, 0, 1);
  const Vec3<T> h = normalize(Vec3<T>(wm.x / ax, wm.y / ay, wm.z));
  const T cap_z = T(2) * dot(h, wi_std) * h.z - wi_std.z;
  if (cap_z < -k * wi_std.z) return T(0);
  const T den = k * wi.z + t;
  return den > T(0) ? g.D(wm) * T(2) * wim / den : T(0);
}

namespace reflection_jacobian {
// pdf over wo = reflect(wi, m) of a sampler of normals m with solid-angle pdf pdf_m(wi, m): pdf_m / (4 wi·m)
// at the half vector m = normalize(wi + wo), wi = w flipped into the upper hemisphere; 0 where the half
// vector is undefined or faces away from wi.
template <class T, class PdfM>
T reflected_pdf(const Vec3<T>& w, const Vec3<T>& wo, PdfM pdf_m) {
  const Vec3<T> wi = w.z < T(0) ? -w : w;
  const Vec3<T> sum = wi + wo;
  if (!(dot(sum, sum) > T(0))) return T(0);
  const Vec3<T> wm = normalize(sum);
  const T wim = dot(wi, wm);
  return wim > T(0) ? pdf_m(wi, wm) / (T(4) * wim) : T(0);
}
}  // namespace reflection_jacobian

// pdf over the reflected direction wo = reflect(wi, m) of the bounded sampler: pdf_bounded_vndf / (4 wi·m)
// = D(m) / (2(k wi.z + t)) inside the cap (Eto & Tokuyoshi 2023, Eq. 8 times the reflection Jacobian).
template <class T>
T pdf_bounded_vndf_reflection(const GGX<T>& g, const Vec3<T>& w, const Vec3<T>& wo) {
  return reflection_jacobian::reflected_pdf(
      w, wo, [&g](const Vec3<T>& wi, const Vec3<T>& wm) { return pdf_bounded_vndf(g, wi, wm); });
}

// pdf over wo of the unbounded VNDF reflection sampler (GGX<T>::Sample_wm then reflect), for comparison:
// D_wi(m) / (4 wi·m) = G1(wi) D(m) / (4 wi.z).
template <class T>
T pdf_vndf_reflection(const GGX<T>& g, const Vec3<T>& w, const Vec3<T>& wo) {
  return reflection_jacobian::reflected_pdf(
      w, wo, [&g](const Vec3<T>& wi, const Vec3<T>& wm) { return g.PDF(wi, wm); });
}

}  // namespace msh
