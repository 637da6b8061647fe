// microshadow: shaders/portable/bump_terminator.h, written once for GLSL and HLSL in the portable dialect
// (docs/shaders.md): HLSL type names and the msh_* spellings that shaders/glsl/msh_prelude.glsl and
// shaders/hlsl/msh_prelude.hlsl define. Not included directly: GLSL `#include "shaders/glsl/bump_terminator.glsl"`,
// HLSL `#include "shaders/hlsl/bump_terminator.hlsl"` (their top comments say how).
// Port of include/microshadow/occlusion/bump_terminator.h and shadow_terminator_offset.h; see
// docs/bump-terminator.md. Vectors: ng = geometric normal, ns = shading (bumped) normal, l = direction to the
// light, all pointing away from the surface; none needs to be unit length (every term is scale-invariant).
// Precision (float32, measured against a double-precision evaluation of the closed forms on the same inputs):
// Conty |err| <= 1e-6 for |cos(ng,l)| >= 0.05, <= 5e-6 for >= 0.01; closer to grazing the term is steep
// (dG/dcos ~ 2/alpha) and the error is bounded by ~1.2e-7/alpha from the rounding of dot(ng,l) alone (7e-6
// measured over 300k random inputs). Chiang |err| <= 2e-5 for |cos(ns,l)| > 1e-3. Zero vectors give 1 (no
// correction); NaN/Inf inputs are not guaranteed on GPUs (compilers may assume finite math).
// GLSL ES 3.00 (WebGL2, docs/viewer.md) has no `precise` (MSH_PRECISE is empty there): an FMA contraction may
// leave ns = ng a hair above alpha^2 = 0 (a term within float rounding of 1 instead of exactly 1).
#ifndef MSH_BUMP_TERMINATOR_PORTABLE_H
#define MSH_BUMP_TERMINATOR_PORTABLE_H

// GGX alpha^2 from the normal perturbation: clamp(tan^2(theta_d)/8, 0, 1) (Conty Estevez et al. 2019, RTG
// eq. 12.2; tan theta_d = 2 sigma, GGX variance sigma^2 = 2 alpha^2). float32, exact 0 for ns parallel to ng.
MSH_FN float msh_bump_alpha2(float3 ng, float3 ns) {
  // Written out and `precise` (no FMA contraction) so that ns = ng gives exactly 0, hence the term exactly 1.
  MSH_PRECISE float3 x = float3(ng.y * ns.z - ng.z * ns.y, ng.z * ns.x - ng.x * ns.z, ng.x * ns.y - ng.y * ns.x);
  float s2 = dot(x, x);
  float c = dot(ng, ns);
  float c8 = 8.0f * c * c;
  if (s2 < c8) return s2 / c8;
  return s2 > 0.0f ? 1.0f : 0.0f;
}

// Smith GGX G1 of the light about ng: 2 / (1 + sqrt(1 + alpha^2 tan^2 theta_i)), |cos theta_i| >= 1e-6 as in
// listing 12.1 (Conty 2019; RTR4 9.24 + 9.37). float32, see the precision note above.
MSH_FN float msh_bump_smith_g1_light(float alpha2, float3 ng, float3 l) {
  // cross(ng, l) written out; exactly 0 for l = ng
  MSH_PRECISE float3 x = float3(ng.y * l.z - ng.z * l.y, ng.z * l.x - ng.x * l.z, ng.x * l.y - ng.y * l.x);
  float s2 = dot(x, x);
  float c = dot(ng, l);
  float c2 = c * c;
  float n2 = s2 + c2;
  if (!(n2 > 0.0f)) return 1.0f;
  float tan2 = min(s2 / max(c2, 1e-12f * n2), 1e12f);
  return 2.0f / (1.0f + sqrt(1.0f + msh_saturate(alpha2) * tan2));
}

// Light above both the geometric and the shading hemisphere (the optional hemisphere-validity test).
MSH_FN bool msh_bump_above_both(float3 ng, float3 ns, float3 l) { return dot(ng, l) > 0.0f && dot(ns, l) > 0.0f; }

// Conty Estevez, Lecocq, Stein 2019 (Ray Tracing Gems ch. 12, listing 12.1) bump shadowing term. float32.
MSH_FN float msh_bump_conty2019(float3 ng, float3 ns, float3 l, bool hemisphere_test) {
  if (hemisphere_test && !msh_bump_above_both(ng, ns, l)) return 0.0f;
  return msh_bump_smith_g1_light(msh_bump_alpha2(ng, ns), ng, l);
}

// Chiang, Li, Burley 2019 "Taming the Shadow Terminator": g = (ng.l)/((ns.l)(ng.ns)) (ns normalized), then
// -g^3 + g^2 + g on [0,1]; a zero denominator gives 1. float32, see the precision note above.
MSH_FN float msh_bump_chiang2019(float3 ng, float3 ns, float3 l, bool hemisphere_test) {
  if (hemisphere_test && !msh_bump_above_both(ng, ns, l)) return 0.0f;
  float num = dot(ng, l) * dot(ns, ns);
  float den = dot(ns, l) * dot(ng, ns);
  if (den == 0.0f) return 1.0f;
  if (den < 0.0f) {
    num = -num;
    den = -den;
  }
  if (num >= den) return 1.0f;
  if (!(num > 0.0f)) return 0.0f;
  float g = num / den;
  return g * (1.0f + g * (1.0f - g));
}

// Hanika 2021 "Hacking the Shadow Terminator" (Ray Tracing Gems II ch. 4): shadow-ray origin for a
// smooth-shaded triangle, p' = p - sum_i b_i min(0, (p - p_i).n_i) n_i / |n_i|^2. b = barycentrics of p.
// float32; use p' only as the origin of shadow rays.
MSH_FN float3 msh_hanika2021_shadow_origin(float3 p, float3 p0, float3 p1, float3 p2, float3 n0, float3 n1, float3 n2,
                                    float3 b) {
  float3 q = p;
  float n2_0 = dot(n0, n0), n2_1 = dot(n1, n1), n2_2 = dot(n2, n2);
  if (n2_0 > 0.0f) q -= b.x * min(0.0f, dot(p - p0, n0) / n2_0) * n0;
  if (n2_1 > 0.0f) q -= b.y * min(0.0f, dot(p - p1, n1) / n2_1) * n1;
  if (n2_2 > 0.0f) q -= b.z * min(0.0f, dot(p - p2, n2) / n2_2) * n2;
  return q;
}

#endif  // MSH_BUMP_TERMINATOR_PORTABLE_H
