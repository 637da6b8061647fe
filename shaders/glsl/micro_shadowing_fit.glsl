// microshadow: ALU-only approximations (no texture) of the azimuth-mean generic VNDF micro-shadowing term for
// GLSL 4.50 / GLSL ES 3.20. Include-only: no #version line; needs nothing else. Ports of
// include/microshadow/occlusion/micro_shadowing_fit.h (form, coefficients, fit, operation counts and
// measured error: docs/micro-shadowing.md, "ALU-only approximation").
//
// vis = micro-occlusion visibility in projected solid angle (cone cos_t = sqrt(1 - vis)); n_dot_l, n_dot_v
// the shading cosines; roughness perceptual (GGX alpha = roughness^2), isotropic Smith-GGX. Fitted over vis
// in [0,1], N.L and N.V in (0,1], roughness in [0.1,1]. Inputs are clamped to [0,1] (roughness to [0.01,1]);
// NaN inputs are not guaranteed on GPUs (compilers may assume finite math).
// Precision vs the C++ float functions: |diff| <= 1e-5 (tests/test_shaders_micro_shadowing_fit.cpp on
// lavapipe, 2^14 random and degenerate inputs); the early-out 2 vis + N.L < 1 returns exactly 0 as in C++.
#ifndef MSH_MICRO_SHADOWING_FIT_GLSL
#define MSH_MICRO_SHADOWING_FIT_GLSL

// One call: port of msh::ms::generic_vndf_alu. 40 arithmetic operations after the input clamps
// (docs/micro-shadowing.md). Error vs the exact azimuth mean (20000 stratified random inputs over the domain):
// RMS 4.2/255, p99 17/255, max 37/255 (docs/micro-shadowing.md).
float msh_ms_generic_vndf_alu(float vis, float n_dot_l, float n_dot_v, float roughness) {
  float v = clamp(vis, 0.0, 1.0), nl = clamp(n_dot_l, 0.0, 1.0), nv = clamp(n_dot_v, 0.0, 1.0);
  float r = clamp(roughness, 0.01, 1.0);
  if (2.0 * v + nl < 1.0) return 0.0;  // exact early-out (msh::ms::exact_zero)
  float omv = 1.0 - v;
  float c = sqrt(omv), s = sqrt(v);              // cos, sin of the cone half-angle
  float nl2 = nl * nl, sl = sqrt(1.0 - nl2);
  float d = s * nl - c * sl;                     // sin(theta_c - theta_l)
  float alpha = r * r;
  float k = nv / (nv + alpha);
  float a = alpha * (1.39397 - 0.796604 * r + 0.332797 * v - 0.467188 * k);
  float a2 = a * a, oma2 = 1.0 - a2;
  float q = a2 * (6.28222 + 0.384725 * v - 6.03135 * k);
  float g = (-0.00902245 + 0.555965 * r) * omv;
  float p1 = 1.0 + d * inversesqrt(fma(oma2, d * d, a2));
  float p2 = 1.0 + nl * inversesqrt(fma(oma2, nl2, a2));
  return clamp(p1 * (v + g * (nl - 1.0)) / ((v + omv * q) * p2), 0.0, 1.0);
}

// Two stages: ports of msh::ms::generic_vndf_alu_pixel (once per pixel, 50 operations) and
// msh::ms::generic_vndf_alu_light (per light, 23 operations). More accurate than the one-call form: see
// docs/micro-shadowing.md: RMS 1.4/255, p99 5.2/255, max 16.5/255 (9.7/255 for N.V >= 0.1).
struct MshMsAluPixel {
  float vis, c, s, a2, oma2, inv_st, g, den;
};

float msh_ms_alu_quad_a(float x, float y, float z) {
  return 1.26083 + x * (-2.30117 + 0.260731 * x + 0.108275 * y + 1.73798 * z) + y * (0.949957 - 0.251089 * y - 0.881026 * z) +
         z * (-1.5246 + 0.381768 * z);
}

float msh_ms_alu_quad_q(float x, float y, float z) {
  return 7.05684 + x * (-1.96525 + 0.844748 * x + 3.31171 * y - 2.41379 * z) + y * (-11.4716 + 3.97505 * y + 2.59036 * z) +
         z * (-0.277242 - 1.00192 * z);
}

float msh_ms_alu_quad_g(float x, float y, float z) {
  return 0.573811 + x * (0.891258 - 0.347745 * x - 0.239399 * y + 0.130381 * z) + y * (-0.778977 + 0.182337 * y + 0.762701 * z) +
         z * (-0.310037 - 0.461357 * z);
}

MshMsAluPixel msh_ms_generic_vndf_alu_pixel(float vis, float n_dot_v, float roughness) {
  float v = clamp(vis, 0.0, 1.0), nv = clamp(n_dot_v, 0.0, 1.0);
  float r = clamp(roughness, 0.01, 1.0);
  MshMsAluPixel px;
  float omv = 1.0 - v;
  px.vis = v;
  px.c = sqrt(omv);
  px.s = sqrt(v);
  float alpha = r * r, nv2 = nv * nv;
  float wz = nv * inversesqrt(nv2 + alpha * alpha * (1.0 - nv2));  // z of the stretched view direction
  float a = alpha * exp2(msh_ms_alu_quad_a(r, px.c, wz));
  px.a2 = a * a;
  px.oma2 = 1.0 - px.a2;
  float q = px.a2 * exp2(msh_ms_alu_quad_q(r, px.c, wz));
  px.g = msh_ms_alu_quad_g(r, px.c, wz) * omv;
  px.inv_st = sqrt(fma(px.oma2, v, px.a2)) / max(px.s, 1e-6);
  px.den = v + omv * q;
  return px;
}

float msh_ms_generic_vndf_alu_light(MshMsAluPixel px, float n_dot_l) {
  float nl = clamp(n_dot_l, 0.0, 1.0);
  if (2.0 * px.vis + nl < 1.0) return 0.0;  // exact early-out (msh::ms::exact_zero)
  if (!(px.vis < 1.0)) return 1.0;
  float nl2 = nl * nl, sl = sqrt(1.0 - nl2);
  float d = px.s * nl - px.c * sl;
  float p1 = 1.0 + d * inversesqrt(fma(px.oma2, d * d, px.a2)) * px.inv_st;
  float p2 = 1.0 + nl * inversesqrt(fma(px.oma2, nl2, px.a2));
  return clamp(p1 * (px.vis + px.g * (nl - 1.0)) / (px.den * p2), 0.0, 1.0);
}

#endif  // MSH_MICRO_SHADOWING_FIT_GLSL
