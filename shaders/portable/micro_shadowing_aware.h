// microshadow: shaders/portable/micro_shadowing_aware.h, written once for GLSL and HLSL in the portable dialect
// (docs/shaders.md): HLSL type names and the msh_* spellings that shaders/glsl/msh_prelude.glsl and
// shaders/hlsl/msh_prelude.hlsl define. Not included directly: GLSL `#include "shaders/glsl/micro_shadowing_aware.glsl"`,
// HLSL `#include "shaders/hlsl/micro_shadowing_aware.hlsl"` (their top comments say how).
// Micro-BRDF-aware micro-shadowing (docs/micro-shadowing-aware.md). Needs micro_shadowing (VNDF sampler, Sobol
// points, cone cosine, early-out) included first. Port of include/microshadow/occlusion/micro_shadowing_aware.h
// (namespace msh::micro_shadowing).
// Conventions as micro_shadowing: vis in [0,1] (projected solid angle), cone cos_t = sqrt(1 - vis), v and l
// unit in the shading frame (n = +z), GGX alpha = roughness^2. Precision: float32 on lavapipe against the C++
// float code on the same inputs, measured by tests/test_shaders_micro_shadowing_aware.cpp, stated per function.
#ifndef MSH_MICRO_SHADOWING_AWARE_PORTABLE_H
#define MSH_MICRO_SHADOWING_AWARE_PORTABLE_H

// Specular-aware term (micro_shadowing_aware.h, specular_aware): chi+(n.h - c) chi+(h.l - c), h = normalize(l + v).
// Exact (0 or 1) except within ~1 ulp of the two cone boundaries.
MSH_FN float msh_ms_specular_aware(float vis, float3 v, float3 l) {
  float V = clamp(vis, 0.0f, 1.0f);
  if (!(v.z > 0.0f) || !(l.z > 0.0f)) return 0.0f;
  if (V >= 1.0f) return 1.0f;
  float3 hs = v + l;
  float len2 = dot(hs, hs);
  if (!(len2 > 0.0f)) return 0.0f;
  float c = msh_ms_cone_cos(V), len = sqrt(len2);
  return (hs.z > c * len && 1.0f + dot(l, v) > c * len) ? 1.0f : 0.0f;
}

// Specular-aware term averaged over the relative azimuth with the GGX lobe's weight D(h) (micro_shadowing_aware.h,
// specular_aware_azimuth_mean, closed form). |shader - C++ float| <= 2e-4 (measured 9.7e-5) (the float closed form's own error
// against the exact mean is larger at low roughness: docs/micro-shadowing-aware.md).
MSH_FN float msh_ms_specular_aware_azimuth_mean(float vis, float alpha, float n_dot_l, float n_dot_v) {
  float V = clamp(vis, 0.0f, 1.0f), cl = clamp(n_dot_l, 0.0f, 1.0f), cv = clamp(n_dot_v, 0.0f, 1.0f);
  if (!(cl > 0.0f) || !(cv > 0.0f)) return 0.0f;
  if (V >= 1.0f) return 1.0f;
  if (msh_ms_exact_zero(V, cl) || V == 0.0f) return 0.0f;
  float a = clamp(alpha, 1e-4f, 1.0f), a2 = a * a;
  float c = msh_ms_cone_cos(V), c2 = c * c;
  float A = cl * cv, B = sqrt(max(0.0f, (1.0f - cl * cl) * (1.0f - cv * cv)));
  float K = 0.5f * (cl + cv) * (cl + cv);
  float x1n = 2.0f * c2 - 1.0f - A, x2n = K / c2 - 1.0f - A;
  if (!(B > 1e-7f)) return (x1n < 0.0f && x2n > 0.0f) ? 1.0f : 0.0f;
  float x1 = x1n / B, x2 = x2n / B;
  float p_lo = x2 >= 1.0f ? 0.0f : (x2 <= -1.0f ? MSH_MS_PI : acos(x2));
  float p_hi = x1 <= -1.0f ? MSH_MS_PI : (x1 >= 1.0f ? 0.0f : acos(x1));
  if (!(p_hi > p_lo)) return 0.0f;
  float beta = (a2 - 1.0f) * K;
  float aa = 1.0f + A + beta, b = B;
  float s2 = max((aa - b) * (aa + b), 1.17549435e-38f);
  float s = sqrt(s2), ra = sqrt(max(aa - b, 0.0f)), rb = sqrt(aa + b);
  float w[3];
  float phis[3] = MSH_ARRAY(float, 3) p_lo, p_hi, MSH_MS_PI MSH_ARRAY_END;
  for (int i = 0; i < 3; ++i) {
    float phi = phis[i];
    float j1 = 2.0f / s * msh_atan2(ra * sin(0.5f * phi), rb * cos(0.5f * phi));
    float j2 = (aa * j1 - b * sin(phi) / (aa + b * cos(phi))) / s2;
    w[i] = phi - 2.0f * beta * j1 + beta * beta * j2;
  }
  if (!(w[2] > 0.0f)) return 0.0f;
  return clamp((w[1] - w[0]) / w[2], 0.0f, 1.0f);
}

// Fraction of a Lambertian facet's reflected flux leaving through the cone n.w > c (micro_shadowing_aware.h,
// lambert_cap_fraction; Snyder 1996 cap form factor with horizon). |shader - C++ float| <= 1e-4 (measured 4.8e-5 on lavapipe:
// the GPU acos and atan).
MSH_FN float msh_ms_lambert_cap_fraction(float cos_m, float c) {
  float cm = clamp(cos_m, -1.0f, 1.0f), cc = clamp(c, 0.0f, 1.0f);
  float s2 = 1.0f - cc * cc, ss = sqrt(s2);
  float sm = sqrt(max(0.0f, 1.0f - cm * cm));
  if (cm >= ss) return cm * s2;
  if (cm <= -ss) return 0.0f;
  float y = clamp(-cc * cm / max(ss * sm, 1.17549435e-38f), -1.0f, 1.0f);
  float r = sm * sqrt(max(0.0f, 1.0f - y * y));
  float e = (cm * acos(y) - (cc / max(ss, 1.17549435e-38f)) * r) * s2 + msh_atan2(r * ss, cc);
  return clamp(e / MSH_MS_PI, 0.0f, 1.0f);
}

// Diffuse-aware term by n Owen-scrambled Sobol VNDF samples (micro_shadowing_aware.h, diffuse_aware_estimate):
// reciprocal = true weights each facet by (m.l)+ and tests n.m, m.l and m.v against the cone; false (flux) weights
// by (m.l)+ times the cap fraction. Matches the C++ float estimator to 1e-4 except where a sample sits within
// rounding of a cone boundary (then by one sample's weight).
MSH_FN float msh_ms_diffuse_aware_estimate(float vis, float2 alpha, float3 v, float3 l, int n, bool reciprocal, uint seed) {
  float V = clamp(vis, 0.0f, 1.0f);
  if (msh_ms_exact_zero(V, l.z) || V == 0.0f) return 0.0f;
  if (V >= 1.0f) return 1.0f;
  float c = msh_ms_cone_cos(V), cone = 0.0f, hemi = 0.0f;
  for (int i = 0; i < n; ++i) {
    float3 m = msh_ggx_sample_vndf(v, alpha, msh_sobol_2d(uint(i), seed));
    float ml = dot(m, l), nm = m.z;
    if (!(ml > 0.0f) || !(nm > 0.0f)) continue;
    bool in_cone = nm > c && ml > c;
    if (reciprocal) {
      hemi += ml;
      cone += (in_cone && dot(m, v) > c) ? ml : 0.0f;
    } else {
      hemi += ml * 0.5f * (1.0f + nm);
      cone += in_cone ? ml * msh_ms_lambert_cap_fraction(nm, c) : 0.0f;
    }
  }
  return hemi > 0.0f ? min(1.0f, cone / hemi) : 0.0f;
}

#endif  // MSH_MICRO_SHADOWING_AWARE_PORTABLE_H
