// microshadow: shaders/portable/micro_shadowing_fit.h, written once for GLSL and HLSL in the portable dialect
// (docs/shaders.md): HLSL type names and the msh_* spellings that shaders/glsl/msh_prelude.glsl and
// shaders/hlsl/msh_prelude.hlsl define. Not included directly: GLSL `#include "shaders/glsl/micro_shadowing_fit.glsl"`,
// HLSL `#include "shaders/hlsl/micro_shadowing_fit.hlsl"` (their top comments say how).
// ALU-only approximations (no texture) of the azimuth-mean generic VNDF micro-shadowing term; needs nothing
// else. Ports of
// include/microshadow/occlusion/micro_shadowing_fit.h (form, coefficients, fit, operation counts and
// measured error: docs/micro-shadowing.md, "ALU-only approximation").
//
// vis = micro-occlusion visibility in projected solid angle (cone cos_t = sqrt(1 - vis)); n_dot_l, n_dot_v
// the shading cosines; roughness perceptual (GGX alpha = roughness^2), isotropic Smith-GGX. Fitted over vis
// in [0,1], N.L and N.V in (0,1], roughness in [0.1,1]. Inputs are clamped to [0,1] (roughness to [0.01,1]);
// NaN inputs are not guaranteed on GPUs (compilers may assume finite math).
// Precision vs the C++ float functions: |diff| <= 1e-5 (tests/test_shaders_micro_shadowing_fit.cpp on
// lavapipe, 2^14 random and degenerate inputs); the early-out 2 vis + N.L < 1 returns exactly 0 as in C++.
#ifndef MSH_MICRO_SHADOWING_FIT_PORTABLE_H
#define MSH_MICRO_SHADOWING_FIT_PORTABLE_H

// One call: port of msh::ms::generic_vndf_alu. 40 arithmetic operations after the input clamps
// (docs/micro-shadowing.md). Error vs the exact azimuth mean (20000 stratified random inputs over the domain):
// RMS 4.2/255, p99 17/255, max 37/255 (docs/micro-shadowing.md).
MSH_FN float msh_ms_generic_vndf_alu(float vis, float n_dot_l, float n_dot_v, float roughness) {
  float v = msh_saturate(vis), nl = msh_saturate(n_dot_l), nv = msh_saturate(n_dot_v);
  float r = clamp(roughness, 0.01f, 1.0f);
  if (2.0f * v + nl < 1.0f) return 0.0f;  // exact early-out (msh::ms::exact_zero)
  float omv = 1.0f - v;
  float c = sqrt(omv), s = sqrt(v);              // cos, sin of the cone half-angle
  float nl2 = nl * nl, sl = sqrt(1.0f - nl2);
  float d = s * nl - c * sl;                     // sin(theta_c - theta_l)
  float alpha = r * r;
  float k = nv / (nv + alpha);
  float a = alpha * (1.39397f - 0.796604f * r + 0.332797f * v - 0.467188f * k);
  float a2 = a * a, oma2 = 1.0f - a2;
  float q = a2 * (6.28222f + 0.384725f * v - 6.03135f * k);
  float g = (-0.00902245f + 0.555965f * r) * omv;
  float p1 = 1.0f + d * msh_rsqrt(msh_mad(oma2, d * d, a2));
  float p2 = 1.0f + nl * msh_rsqrt(msh_mad(oma2, nl2, a2));
  return msh_saturate(p1 * (v + g * (nl - 1.0f)) / ((v + omv * q) * p2));
}

// Two stages: ports of msh::ms::generic_vndf_alu_pixel (once per pixel, 80 operations) and
// msh::ms::generic_vndf_alu_light (per light, 23 operations). More accurate than the one-call form: see
// docs/micro-shadowing.md: RMS 0.95/255, p99 3.2/255, max 9.0/255 (5.2/255 for N.V >= 0.1).
struct MshMsAluPixel {
  float vis, c, s, a2, oma2, inv_st, g, den;
};

MSH_FN float msh_ms_alu_cubic_a(float x, float y, float z) {
  float px = -2.9439f + x * (0.471315f + 0.396493f * x - 0.427877f * y - 0.437596f * z) + y * (1.08175f + 0.634181f * y - 1.61536f * z) +
             z * (1.66018f + 1.05468f * z);
  float py = 2.9061f + y * (-3.2708f + 0.342605f * y + 2.39379f * z) + z * (-2.8354f + 0.407305f * z);
  float pz = -0.670065f + z * (-0.396618f + 0.0423424f * z);
  return 1.0217f + x * px + y * py + z * pz;
}

MSH_FN float msh_ms_alu_cubic_q(float x, float y, float z) {
  float px = -9.6416f + x * (7.56448f - 2.27743f * x - 0.05405f * y - 2.87783f * z) + y * (6.01259f - 1.88619f * y - 1.3212f * z) +
             z * (0.966796f + 2.61554f * z);
  float py = -26.1472f + y * (26.5267f - 9.77157f * y - 6.78087f * z) + z * (8.15792f + 3.37417f * z);
  float pz = -0.739559f + z * (-4.27069f - 1.07619f * z);
  return 11.644f + x * px + y * py + z * pz;
}

MSH_FN float msh_ms_alu_cubic_g(float x, float y, float z) {
  float px = 3.81808f + x * (1.04404f - 0.682536f * x - 0.962631f * y + 0.460372f * z) + y * (-5.48228f + 2.19737f * y + 2.98356f * z) +
             z * (-3.36957f + 0.488589f * z);
  float py = 2.24386f + y * (-2.27448f + 1.15732f * y - 0.0851906f * z) + z * (-0.812951f + 0.139112f * z);
  float pz = 0.55774f + z * (0.640291f - 0.665058f * z);
  return -0.9204f + x * px + y * py + z * pz;
}

MSH_FN MshMsAluPixel msh_ms_generic_vndf_alu_pixel(float vis, float n_dot_v, float roughness) {
  float v = msh_saturate(vis), nv = msh_saturate(n_dot_v);
  float r = clamp(roughness, 0.01f, 1.0f);
  MshMsAluPixel px;
  float omv = 1.0f - v;
  px.vis = v;
  px.c = sqrt(omv);
  px.s = sqrt(v);
  float alpha = r * r, nv2 = nv * nv;
  float wz = nv * msh_rsqrt(nv2 + alpha * alpha * (1.0f - nv2));  // z of the stretched view direction
  float a = alpha * exp2(msh_ms_alu_cubic_a(r, px.c, wz));
  px.a2 = a * a;
  px.oma2 = 1.0f - px.a2;
  float q = px.a2 * exp2(msh_ms_alu_cubic_q(r, px.c, wz));
  px.g = msh_ms_alu_cubic_g(r, px.c, wz) * omv;
  px.inv_st = sqrt(msh_mad(px.oma2, v, px.a2)) / max(px.s, 1e-6f);
  px.den = v + omv * q;
  return px;
}

MSH_FN float msh_ms_generic_vndf_alu_light(MshMsAluPixel px, float n_dot_l) {
  float nl = msh_saturate(n_dot_l);
  if (2.0f * px.vis + nl < 1.0f) return 0.0f;  // exact early-out (msh::ms::exact_zero)
  if (!(px.vis < 1.0f)) return 1.0f;
  float nl2 = nl * nl, sl = sqrt(1.0f - nl2);
  float d = px.s * nl - px.c * sl;
  float p1 = 1.0f + d * msh_rsqrt(msh_mad(px.oma2, d * d, px.a2)) * px.inv_st;
  float p2 = 1.0f + nl * msh_rsqrt(msh_mad(px.oma2, nl2, px.a2));
  return msh_saturate(p1 * (px.vis + px.g * (nl - 1.0f)) / (px.den * p2));
}

#endif  // MSH_MICRO_SHADOWING_FIT_PORTABLE_H
