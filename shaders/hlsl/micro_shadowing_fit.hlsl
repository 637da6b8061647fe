// microshadow: ALU-only approximation of the azimuth-mean generic VNDF micro-shadowing term, for HLSL (SM 5.0+
// / DXC / glslang's HLSL front end). Include-only; needs nothing else. Port of generic_vndf_alu in
// include/microshadow/occlusion/micro_shadowing_fit.h (form, fit and measured error: docs/micro-shadowing.md,
// "ALU-only approximation").
//
// vis = micro-occlusion visibility in projected solid angle (cone cos_t = sqrt(1 - vis)); n_dot_l, n_dot_v
// the shading cosines; roughness perceptual (GGX alpha = roughness^2), isotropic. Fitted on vis in [0,1],
// N.L, N.V in (0,1], roughness in [0.1,1]; inputs are clamped to [0,1].
// Error vs the exact azimuth mean (20000 stratified random inputs over that domain, docs/micro-shadowing.md):
// RMS 4.6/255, p99 18/255, max 40/255 (targets RMS 2/255, max 8/255: not met). Shader vs C++ float:
// |diff| <= 1e-5 (tests/test_shaders_micro_shadowing_fit.cpp, lavapipe); the early-out 2 vis + N.L < 1 gives
// exactly 0 as in C++. Cost: 40 arithmetic operations after the 4 input clamps (docs/micro-shadowing.md).
#ifndef MSH_MICRO_SHADOWING_FIT_HLSL
#define MSH_MICRO_SHADOWING_FIT_HLSL

// Coefficients p0..p7 (kGenericVndfAluCoeffs in micro_shadowing_fit.h; scripts/fit_micro_shadowing.py).
#define MSH_MS_ALU_P0 1.16147
#define MSH_MS_ALU_P1 -0.735958
#define MSH_MS_ALU_P2 0.39027
#define MSH_MS_ALU_P3 -0.260151
#define MSH_MS_ALU_P4 12.5356
#define MSH_MS_ALU_P5 -3.04389
#define MSH_MS_ALU_P6 -0.0466582
#define MSH_MS_ALU_P7 -10.5623

// f = Pcap (1 + S(tan(theta_c - theta_l)/a)) / (1 + S(cot theta_l / a)), S(z) = z / sqrt(1 + z^2) (the GGX
// 1D slope CDF, Walter et al. 2007), Pcap = vis / (vis + (1 - vis) q), a and q fitted linear forms in
// (roughness, vis, k = N.V / (N.V + alpha)). Source: micro_shadowing_fit.h (docs/micro-shadowing.md).
float msh_ms_generic_vndf_alu(float vis, float n_dot_l, float n_dot_v, float roughness) {
  float v = saturate(vis), nl = saturate(n_dot_l);
  float nv = saturate(n_dot_v), r = saturate(roughness);
  if (2.0 * v + nl < 1.0) return 0.0;  // exact early-out (as msh::ms::exact_zero)
  float omv = 1.0 - v;
  float c = sqrt(omv), s = sqrt(v);
  float nl2 = nl * nl, sl = sqrt(1.0 - nl2);
  float d = s * nl - c * sl;
  float alpha = max(r * r, 1e-4);
  float k = nv / (nv + alpha);
  float a = alpha * (MSH_MS_ALU_P0 + MSH_MS_ALU_P1 * r + MSH_MS_ALU_P2 * v + MSH_MS_ALU_P3 * k);
  float a2 = a * a, oma2 = 1.0 - a2;
  float q = a2 * (MSH_MS_ALU_P4 + MSH_MS_ALU_P5 * r + MSH_MS_ALU_P6 * v + MSH_MS_ALU_P7 * k);
  float p1 = 1.0 + d * rsqrt(a2 + oma2 * (d * d));
  float p2 = 1.0 + nl * rsqrt(a2 + oma2 * nl2);
  float f = v * p1 / ((v + omv * q) * p2);
  return saturate(f);
}

#endif  // MSH_MICRO_SHADOWING_FIT_HLSL
