// The bump-terminator fix: a shadowing factor for the light when the shading normal is perturbed (bump or
// normal map) away from the geometric normal, which otherwise lets light leak past the geometric terminator
// and then cut off hard (docs/theory.md §4).
//
//   Conty Estevez, Lecocq, Stein 2019, "A Microfacet-Based Shadowing Function to Solve the Bump Terminator
//   Problem" (Ray Tracing Gems ch. 12, listing 12.1): treat the perturbation as a GGX roughness,
//   α² = clamp(tan²θ_d / 8, 0, 1), θ_d = angle(N_g, N_s), and multiply the light by the Smith GGX G1 of the
//   light direction about N_g.
//   Chiang, Li, Burley 2019, "Taming the Shadow Terminator" (SIGGRAPH Talks): g = (N_g·L)/((N_s·L)(N_g·N_s)),
//   1 if g ≥ 1, 0 if g < 0, else the cubic −g³ + g² + g.
//
// Conventions shared by every function here:
//   * ng = geometric (unperturbed) normal, ns = shading (bumped) normal, l = direction to the light, all
//     pointing away from the surface. They need NOT be unit length: every term is written so that it is
//     invariant under positive (and negative, see below) scaling of each vector, through
//     |a × b|² / (a·b)² = tan² angle(a, b) (Lagrange's identity), so no normalization is needed.
//   * Sign conventions: as in Conty Estevez et al. 2019 (listing 12.1), the Conty term uses |N_g·N_s| and
//     |N_g·L|; Chiang's ratio g is unchanged by flipping any one of the three vectors. Both terms are
//     therefore symmetric under ng → −ng, ns → −ns and l → −l separately (bit-exactly).
//   * HemisphereTest::kOn additionally returns 0 unless the light is strictly above both the geometric and
//     the shading hemisphere (N_g·L > 0 and N_s·L > 0). Orient ng and ns to the side being shaded (e.g. flip
//     both when N_g·V < 0) before using it; the sign symmetry above then no longer holds, by design.
//   * Degenerate inputs: a zero-length or non-finite vector gives 1 (no correction) with the hemisphere test
//     off, and 0 with it on (the strict test fails). The result is always finite and in [0, 1].
#pragma once

#include <microshadow/math/vec.h>
#include <microshadow/occlusion/shadow_terminator_offset.h>  // Hanika 2021 shadow-ray origin

#include <cmath>
#include <limits>
#include <string>
#include <string_view>

namespace msh::bump {

// Whether a light below the geometric or the shading hemisphere is rejected (returns 0).
enum class HemisphereTest { kOff, kOn };

// The bump-terminator methods; kNone returns 1 (apart from the optional hemisphere test).
enum class Method { kNone, kConty2019, kChiang2019 };

// The registry of the bump-terminator methods: the one list the CLI, the renderer's scene files, the viewer
// (its bump_methods.js is generated from it) and Python read. name is the CLI / file name; glsl the viewer's
// float expression over vec3 ng, ns, wl (towards the light) and bool u_bump_hemi, calling requires_fn
// (shaders/glsl/bump_terminator.glsl; empty: none).
struct MethodInfo {
  Method method;
  std::string_view name, label, summary, glsl, requires_fn;
};
inline constexpr MethodInfo kMethods[] = {
    {Method::kNone, "none", "none", "no correction: the term is 1", "1.0", ""},
    {Method::kConty2019, "conty-2019", "Conty Estevez et al. 2019",
     "GGX G1 of the light about N_g, alpha from the normal perturbation (Conty Estevez, Lecocq, Stein 2019)",
     "msh_bump_conty2019(ng, ns, wl, u_bump_hemi)", "msh_bump_conty2019"},
    {Method::kChiang2019, "chiang-2019", "Chiang et al. 2019",
     "the cubic-smoothed ratio g = (N_g.L)/((N_s.L)(N_g.N_s)) (Chiang, Li, Burley 2019)",
     "msh_bump_chiang2019(ng, ns, wl, u_bump_hemi)", "msh_bump_chiang2019"},
};

// The CLI / file name of a method (its registry entry's name).
inline std::string_view method_name(Method m) {
  for (const MethodInfo& i : kMethods)
    if (i.method == m) return i.name;
  return "none";
}
// Inverse of method_name; returns false for an unknown name.
inline bool parse_method(std::string_view s, Method& out) {
  for (const MethodInfo& i : kMethods)
    if (s == i.name) return out = i.method, true;
  return false;
}
// Every name, "none, conty-2019, chiang-2019" (for messages and help).
inline std::string method_names() {
  std::string s;
  for (const MethodInfo& i : kMethods) {
    if (!s.empty()) s += ", ";
    s += i.name;
  }
  return s;
}

// ---------------------------------------------------------------------------------------------------------
// The GGX variance metric and the perturbation → roughness mapping (Conty Estevez et al. 2019, §12.3.1).
// Reused by normal/roughness filtering (Toksvig-style variance mapping).

// GGX slope variance σ² = 2α² (Conty 2019 §12.3.1: GGX's Cauchy-like slope distribution has no variance; this
// is their numerical fit with the tail ignored). Domain α ≥ 0; NaN → 0.
template <class T>
T ggx_variance(T alpha) {
  return std::isfinite(alpha) ? T(2) * alpha * alpha : (alpha > T(0) ? std::numeric_limits<T>::max() : T(0));
}
// Inverse of ggx_variance: α = sqrt(σ²/2). Domain σ² ≥ 0 (negative and NaN → 0).
template <class T>
T ggx_alpha_from_variance(T variance) {
  return variance > T(0) ? std::sqrt(T(0.5) * std::min(variance, std::numeric_limits<T>::max())) : T(0);
}
// The Beckmann roughness with the same slope variance (Beckmann's tangent variance is α_b²): α_b = √2·α_ggx
// (Conty 2019 §12.3.1). Domain α ≥ 0.
template <class T>
T beckmann_alpha_from_ggx(T alpha_ggx) {
  return T(1.41421356237309504880) * alpha_ggx;
}
// GGX α² for a normal perturbation of tan²θ_d: the perturbation is taken as two standard deviations,
// tan θ_d = 2σ, so α² = σ²/2 = tan²θ_d/8, clamped to [0, 1] (Conty 2019 eq. 12.2). Domain tan² ≥ 0;
// +Inf → 1, NaN → 0.
template <class T>
T alpha2_from_tan2_perturbation(T tan2_d) {
  const T a2 = T(0.125) * tan2_d;
  return a2 > T(0) ? (a2 < T(1) ? a2 : T(1)) : T(0);
}
// The same from cos θ_d, exactly as listing 12.1 writes it: cos_d = min(|cos|, 1). Domain: any cos; 0 → 1.
template <class T>
T alpha2_from_cos_perturbation(T cos_d) {
  const T c = std::abs(cos_d);
  if (!(c < T(1))) return T(0);  // |cos| ≥ 1: no perturbation (NaN also lands here)
  const T c2 = c * c;
  // tan²/8 ≥ 1 ⇔ 1 − c² ≥ 8c²: clamp without dividing (c = 0 would give +Inf).
  return (T(1) - c2) < T(8) * c2 ? (T(1) - c2) / (T(8) * c2) : T(1);
}
// α² from the two normals (Conty 2019 eq. 12.2 via tan²θ_d = |ng × ns|²/(ng·ns)²). Any scaling of either
// vector; perpendicular normals → 1; a zero or non-finite vector → 0 (no perturbation known).
template <class T>
T alpha2_from_normals(const Vec3<T>& ng, const Vec3<T>& ns) {
  const Vec3<T> x = cross(ng, ns);
  const T s2 = dot(x, x), c = dot(ng, ns), c8 = T(8) * c * c;
  if (s2 < c8) return s2 / c8;  // includes s2 = 0 → exactly 0
  return s2 > T(0) && s2 <= std::numeric_limits<T>::max() ? T(1) : T(0);
}

// Smith GGX G1 of the light about ng for a roughness α²: 2 / (1 + sqrt(1 + α² tan²θ_i)) (RTR4 9.24 with the
// GGX Λ 9.37; listing 12.1). |cos θ_i| is clamped to ≥ 1e-6 as in the listing, so grazing light gives a
// small positive value (≈ 2e-6/α), not 0. Domain α² ∈ [0, 1] (clamped, NaN → 0); any scaling of ng and l;
// a zero or non-finite vector → 1.
template <class T>
T smith_g1_light(T alpha2, const Vec3<T>& ng, const Vec3<T>& l) {
  const T a2 = saturate(alpha2);
  const Vec3<T> x = cross(ng, l);
  const T s2 = dot(x, x), c = dot(ng, l), c2 = c * c;
  const T n2 = s2 + c2;  // |ng|²|l|² (Lagrange's identity)
  if (!(n2 > T(0) && n2 <= std::numeric_limits<T>::max())) return T(1);
  const T tan2 = s2 / std::max(c2, T(1e-12) * n2);
  const T t = tan2 < T(1e12) ? tan2 : T(1e12);  // underflowed n2: keep the listing's bound, finite product
  return T(2) / (T(1) + std::sqrt(T(1) + a2 * t));
}

namespace bump_geometry {
template <class T>
bool above_both(const Vec3<T>& ng, const Vec3<T>& ns, const Vec3<T>& l) {
  return dot(ng, l) > T(0) && dot(ns, l) > T(0);
}
}  // namespace bump_geometry

// Conty Estevez et al. 2019 bump shadowing term (listing 12.1): G1 of the light with α² from the angle
// between ng and ns. Domain: any vectors (see the header comment); result in (0, 1], exactly 1 when
// ns ∥ ng or l ∥ ng; 0 only through the hemisphere test.
template <class T>
T conty2019(const Vec3<T>& ng, const Vec3<T>& ns, const Vec3<T>& l,
            HemisphereTest test = HemisphereTest::kOff) {
  if (test == HemisphereTest::kOn && !bump_geometry::above_both(ng, ns, l)) return T(0);
  return smith_g1_light(alpha2_from_normals(ng, ns), ng, l);
}

// The smoothing cubic of Chiang et al. 2019, −g³ + g² + g on [0, 1], 0 below, 1 above. It has p(0) = 0,
// p(1) = 1, p'(1) = 0 and p' = (1 − g)(1 + 3g) ≥ 0, so it is monotone. NaN → 0.
template <class T>
T chiang_smooth(T g) {
  if (!(g > T(0))) return T(0);
  if (g >= T(1)) return T(1);
  return g * (T(1) + g * (T(1) - g));
}

// Chiang, Li, Burley 2019 "Taming the Shadow Terminator": g = (ng·l)/((ns·l)(ng·ns)) with ns normalized,
// then chiang_smooth(g). Written division-safe and scale-free as g = (ng·l)|ns|² / ((ns·l)(ng·ns)):
//   * denominator 0 (light on the shading horizon, N_s·L = 0, or ns ⟂ ng): g = ±∞ or 0/0 → 1 (the lit-side
//     limit; the light's cosine on the shading normal is 0 there anyway);
//   * N_s·L < 0 with N_g·L > 0 and N_g·N_s > 0 gives g < 0 → 0, so the term already removes light below the
//     shading hemisphere when ns and ng agree; the hemisphere test adds the other cases.
// Result in [0, 1]; exactly 1 when ns = ng (same bits).
template <class T>
T chiang2019(const Vec3<T>& ng, const Vec3<T>& ns, const Vec3<T>& l,
             HemisphereTest test = HemisphereTest::kOff) {
  if (test == HemisphereTest::kOn && !bump_geometry::above_both(ng, ns, l)) return T(0);
  T num = dot(ng, l) * dot(ns, ns);
  T den = dot(ns, l) * dot(ng, ns);
  if (!(std::abs(num) <= std::numeric_limits<T>::max() && std::abs(den) <= std::numeric_limits<T>::max()))
    return T(1);  // non-finite input: no correction
  if (den == T(0)) return T(1);
  if (den < T(0)) num = -num, den = -den;
  if (num >= den) return T(1);     // g ≥ 1
  if (!(num > T(0))) return T(0);  // g ≤ 0
  return chiang_smooth(num / den);
}

// Dispatch on the method. Domain and degenerate-input rules as for the individual terms.
template <class T>
T term(Method m, const Vec3<T>& ng, const Vec3<T>& ns, const Vec3<T>& l,
       HemisphereTest test = HemisphereTest::kOff) {
  switch (m) {
    case Method::kConty2019:
      return conty2019(ng, ns, l, test);
    case Method::kChiang2019:
      return chiang2019(ng, ns, l, test);
    default:
      return test == HemisphereTest::kOn && !bump_geometry::above_both(ng, ns, l) ? T(0) : T(1);
  }
}

}  // namespace msh::bump
