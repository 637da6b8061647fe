// microshadow: shaders/portable/micro_shadowing_aware_fit.h, written once for GLSL and HLSL in the portable dialect
// (docs/shaders.md): HLSL type names and the msh_* spellings that shaders/glsl/msh_prelude.glsl and
// shaders/hlsl/msh_prelude.hlsl define. Not included directly: GLSL `#include "shaders/glsl/micro_shadowing_aware_fit.glsl"`,
// HLSL `#include "shaders/hlsl/micro_shadowing_aware_fit.hlsl"` (their top comments say how).
// ALU-only diffuse micro-BRDF-aware micro-shadowing; needs nothing else.
// Port of msh::micro_shadowing::diffuse_aware_alu (include/microshadow/occlusion/micro_shadowing_aware_fit.h):
// ALU-only fit of the azimuth-mean diffuse micro-BRDF-aware term (reciprocal form, Lambertian facets;
// docs/micro-shadowing-aware.md, "Run-time form of the diffuse-aware term"). vis = micro-occlusion visibility
// in projected solid angle (cone cos_t = sqrt(1 - vis)); n_dot_l, n_dot_v the shading cosines; roughness
// perceptual (GGX alpha = roughness^2). Fitted over vis in [0,1], N.L and N.V in (0,1], roughness in [0.1,1];
// inputs clamped to [0,1] (roughness to [0.01,1]); NaN inputs are not guaranteed on GPUs. The early-outs
// 2 vis + N.L < 1 and 2 vis + N.V < 1 return exactly 0 (and N.L = 0), vis = 1 returns 1, as in C++.
#ifndef MSH_MICRO_SHADOWING_AWARE_FIT_PORTABLE_H
#define MSH_MICRO_SHADOWING_AWARE_FIT_PORTABLE_H

// Cubic forms a, q, g in (r, cos_t, w), 20 coefficients each (kDiffuseAwareAluReciprocal).
MSH_GLOBAL_CONST float MSH_AWARE_ALU_P[60] = MSH_ARRAY(float, 60)
    4.7413f, -9.98672f, 5.60447f, 2.29771f, 10.7242f, 14.5875f, -7.79898f, -27.395f, 4.65937f, -5.50467f,
    1.63791f, -6.25831f, 1.13435f, 8.15713f, -19.3248f, 2.49487f, -3.68374f, 13.559f, -5.30555f, 15.5449f,
    13.9158f, -21.439f, -1.45917f, 7.31156f, 16.3105f, -56.2036f, -6.02686f, 14.636f, -20.0127f, 20.4968f,
    -3.89923f, 47.3793f, -6.68909f, -11.7598f, 4.66624f, 19.3493f, -37.9807f, 9.45357f, 18.7872f, -4.47527f,
    -5.54821f, -3.8796f, 22.6404f, 3.55435f, -0.856421f, -33.7625f, -4.80667f, 25.9747f, -21.5183f, 4.97385f,
    3.87288f, 25.9899f, 2.75697f, -10.9443f, 4.71002f, -28.2844f, -15.3595f, -1.21187f, -0.210605f, 32.2277f MSH_ARRAY_END;

// fit_basis::fit_cubic at offset o (1, x, y, z, x2, y2, z2, xy, xz, yz, x3, y3, z3, x2y, x2z, y2x, y2z, z2x,
// z2y, xyz), grouped as in C++.
MSH_FN float msh_ms_aware_alu_cubic(int o, float x, float y, float z) {
  float px = MSH_AWARE_ALU_P[o + 1] + x * (MSH_AWARE_ALU_P[o + 4] + MSH_AWARE_ALU_P[o + 10] * x +
             MSH_AWARE_ALU_P[o + 13] * y + MSH_AWARE_ALU_P[o + 14] * z) +
             y * (MSH_AWARE_ALU_P[o + 7] + MSH_AWARE_ALU_P[o + 15] * y + MSH_AWARE_ALU_P[o + 19] * z) +
             z * (MSH_AWARE_ALU_P[o + 8] + MSH_AWARE_ALU_P[o + 17] * z);
  float py = MSH_AWARE_ALU_P[o + 2] + y * (MSH_AWARE_ALU_P[o + 5] + MSH_AWARE_ALU_P[o + 11] * y +
             MSH_AWARE_ALU_P[o + 16] * z) + z * (MSH_AWARE_ALU_P[o + 9] + MSH_AWARE_ALU_P[o + 18] * z);
  float pz = MSH_AWARE_ALU_P[o + 3] + z * (MSH_AWARE_ALU_P[o + 6] + MSH_AWARE_ALU_P[o + 12] * z);
  return MSH_AWARE_ALU_P[o] + x * px + y * py + z * pz;
}

// T_x L_x of one direction (aware_fit_terms::cone_factor).
MSH_FN float msh_ms_aware_alu_cone(float v, float c, float s, float nx, float a, float g) {
  float a2 = a * a, oma2 = 1.0f - a2;
  float nx2 = nx * nx, sx = sqrt(1.0f - nx2);
  float d = s * nx - c * sx;
  float inv_st = sqrt(a2 + oma2 * v) / max(s, 1e-6f);
  float p1 = 1.0f + d / sqrt(a2 + oma2 * (d * d)) * inv_st;
  float p2 = 1.0f + nx / sqrt(a2 + oma2 * nx2);
  return p1 * (v + g * (1.0f - v) * (nx - 1.0f)) / (v * p2);
}

// Precision vs the C++ float function: |diff| <= 1e-5, measured 3.6e-7 (tests/test_shaders_micro_shadowing_aware_fit.cpp,
// lavapipe, 19,123 random, boundary and degenerate inputs).
MSH_FN float msh_ms_diffuse_aware_alu(float vis, float n_dot_l, float n_dot_v, float roughness) {
  float v = msh_saturate(vis), nl = msh_saturate(n_dot_l), nv = msh_saturate(n_dot_v);
  float r = clamp(roughness, 0.01f, 1.0f);
  if (!(nl > 0.0f) || 2.0f * v + nl < 1.0f || 2.0f * v + nv < 1.0f || !(v > 0.0f)) return 0.0f;  // exact early-outs
  if (!(v < 1.0f)) return 1.0f;
  float omv = 1.0f - v, c = sqrt(omv), s = sqrt(v), alpha = r * r;
  float wl = nl / sqrt(nl * nl + alpha * alpha * (1.0f - nl * nl));
  float wv = nv / sqrt(nv * nv + alpha * alpha * (1.0f - nv * nv));
  float a_l = alpha * exp2(msh_ms_aware_alu_cubic(0, r, c, wv));
  float a_v = alpha * exp2(msh_ms_aware_alu_cubic(0, r, c, wl));
  float q = alpha * alpha * exp2(msh_ms_aware_alu_cubic(20, r, c, wl * wv));
  float fl = msh_ms_aware_alu_cone(v, c, s, nl, a_l, msh_ms_aware_alu_cubic(40, r, c, wv));
  float fv = msh_ms_aware_alu_cone(v, c, s, nv, a_v, msh_ms_aware_alu_cubic(40, r, c, wl));
  return msh_saturate(fl * fv * (v / (v + omv * q)));
}

#endif  // MSH_MICRO_SHADOWING_AWARE_FIT_PORTABLE_H
