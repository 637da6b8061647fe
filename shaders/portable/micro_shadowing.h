// microshadow: shaders/portable/micro_shadowing.h, written once for GLSL and HLSL in the portable dialect
// (docs/shaders.md): HLSL type names and the msh_* spellings that shaders/glsl/msh_prelude.glsl and
// shaders/hlsl/msh_prelude.hlsl define. Not included directly: GLSL `#include "shaders/glsl/micro_shadowing.glsl"`,
// HLSL `#include "shaders/hlsl/micro_shadowing.hlsl"` (their top comments say how).
// Micro-shadowing terms.
// Port of include/microshadow/occlusion/micro_shadowing.h (namespace msh::micro_shadowing), the GGX VNDF
// sampler of include/microshadow/microfacet/ggx.h, the Sobol sequence of math/sampling.h and the LUT sampler
// of include/microshadow/lut/micro_shadowing_lut.h; see docs/shaders.md and docs/micro-shadowing.md.
//
// Conventions (docs/conventions.md, docs/micro-shadowing.md): vis = micro-occlusion visibility in projected solid angle, in [0,1]; the
// visibility cone has cos_t = sqrt(1 - vis). Vectors v (view) and l (light) are unit vectors in the shading
// frame (n = +z, tangent = +x, bitangent = +y), pointing away from the surface: use
// msh_ms_to_shading_frame(). GGX alpha = perceptual roughness^2; alpha_x along the tangent.
// Precision (float32 on lavapipe, vs the C++ float code and a double evaluation on the same inputs, stated
// per function; measured by tests/test_shaders_micro_shadowing.cpp). Inputs outside the domain are clamped
// like the C++ code; NaN/Inf inputs are not guaranteed on GPUs (compilers may assume finite math).
#ifndef MSH_MICRO_SHADOWING_PORTABLE_H
#define MSH_MICRO_SHADOWING_PORTABLE_H

#define MSH_MS_PI 3.14159265358979323846f
// Smallest GGX alpha (GGX<T>::kMinAlpha): alpha 0 is a very sharp but finite lobe.
#define MSH_MS_MIN_ALPHA 1e-4f

// ---- Closed-form terms -------------------------------------------------------------------------------------

// (dot(w,t), dot(w,b), dot(w,n)): a world-space direction in the shading frame (t, b, n orthonormal).
MSH_FN float3 msh_ms_to_shading_frame(float3 w, float3 t, float3 b, float3 n) {
  return float3(dot(w, t), dot(w, b), dot(w, n));
}

// Cosine of the visibility cone's half-angle, sqrt(1 - vis) (Zurita 2026 Part 2, Nusselt analog). |err| <= 1.2e-7.
MSH_FN float msh_ms_cone_cos(float vis) { return sqrt(1.0f - clamp(vis, 0.0f, 1.0f)); }

// Reference term (Zurita 2026 Part 2): step(cos_t, N.L), lit iff N.L > cos_t (strict). Exact except within ~1 ulp of
// the cone boundary N.L = cos_t (where the GPU's sqrt may round differently).
MSH_FN float msh_ms_reference_step(float vis, float n_dot_l) {
  return clamp(n_dot_l, 0.0f, 1.0f) > msh_ms_cone_cos(vis) ? 1.0f : 0.0f;
}

// Brinck & Maximov 2016 (Naughty Dog, Uncharted 4), AO = vis: saturate(N.L + 2 vis^2 - 1). |err| <= 2.4e-7.
MSH_FN float msh_ms_brinck_maximov2016(float vis, float n_dot_l) {
  float v = clamp(vis, 0.0f, 1.0f);
  return clamp(clamp(n_dot_l, 0.0f, 1.0f) + 2.0f * v * v - 1.0f, 0.0f, 1.0f);
}

// Chan 2018 (Activision, CoD WWII; Filament's computeMicroShadowing): saturate(N.L / sqrt(1 - vis))^2.
// vis = 1 gives 1 for N.L > 0, else 0 (the limit). |err| <= 1e-6 (1.6e-7 measured).
MSH_FN float msh_ms_chan2018(float vis, float n_dot_l) {
  float nl = clamp(n_dot_l, 0.0f, 1.0f);
  float c = msh_ms_cone_cos(vis);
  if (!(c > 0.0f)) return nl > 0.0f ? 1.0f : 0.0f;
  float x = clamp(nl / c, 0.0f, 1.0f);
  return x * x;
}

// Part 1 "analytical alternative" (Zurita 2026, Part 1, as reported by third-party copies): vis in {0,1} returns vis; else
// pow(saturate(N.L / sqrt(1 - vis^5)), 0.75 / vis). Precision limited by pow (exp2/log2): |err| <= 2e-6 for
// vis >= 0.05 (1.1e-6 measured); below, the exponent 0.75/vis is large: |err| <= 2e-5 (6.5e-6 measured).
MSH_FN float msh_ms_part1_analytic(float vis, float n_dot_l) {
  float v = clamp(vis, 0.0f, 1.0f);
  if (v == 0.0f || v == 1.0f) return v;
  float nl = clamp(n_dot_l, 0.0f, 1.0f);
  float v2 = v * v;
  float cp = sqrt(1.0f - v2 * v2 * v);
  if (!(cp > 0.0f)) return nl > 0.0f ? 1.0f : 0.0f;  // vis^5 rounded to 1
  float x = clamp(nl / cp, 0.0f, 1.0f);
  return x > 0.0f ? pow(x, 0.75f / v) : 0.0f;  // pow(0, y) avoided: exp2(y * log2(0)) is not portable
}

// Unity HDRP's Micro Shadows (ComputeMicroShadowing, HDRP 2019+): Brinck & Maximov 2016 faded by an opacity,
// lerp(1, saturate(N.L + 2 vis^2 - 1), opacity), at the 0.85 opacity of HDRP's documentation example (the
// volume's default, 1, is Brinck & Maximov itself). |err| <= 5e-7.
#define MSH_MS_HDRP_OPACITY 0.85f
MSH_FN float msh_ms_hdrp_micro_shadows(float vis, float n_dot_l) {
  return 1.0f - MSH_MS_HDRP_OPACITY * (1.0f - msh_ms_brinck_maximov2016(vis, n_dot_l));
}

// Exact early-out (Zurita 2026 Part 2; proof in docs/micro-shadowing.md): 2 vis + N.L < 1 => the generic term is exactly 0 for every
// roughness and view. Exact (two roundings, as in C++).
MSH_FN bool msh_ms_exact_zero(float vis, float n_dot_l) {
  return 2.0f * clamp(vis, 0.0f, 1.0f) + clamp(n_dot_l, 0.0f, 1.0f) < 1.0f;
}

// ---- GGX VNDF sampling, Smith weights ---------------------------------------------------------------------

// normalize() with the C++ fallback: a zero (or denormal-length) vector gives +z.
MSH_FN float3 msh_ms_safe_normalize(float3 a) {
  float l2 = dot(a, a);
  if (!(l2 > 1.17549435e-38f)) return float3(0.0f, 0.0f, 1.0f);
  return a / sqrt(l2);
}

// Dupuy & Benyoub 2023, "Sampling Visible GGX Normals with Spherical Caps" (HPG): microfacet normal m with
// pdf D_v(m) (the VNDF of v), u in [0,1)^2; v.z < 0 is mirrored to -v. |m - m_C++float| <= 5e-6 (1.8e-6
// measured); vs double <= 1e-5 for alpha >= 0.01 and u.y not within 1e-4 of 1 (5.5e-6 measured; the
// C++ float code: 6.8e-6); outside that the float algorithm itself is ill-conditioned (C++ float likewise).
// Depends on the GPU's sin/cos: Vulkan only guarantees 2^-11 absolute, other GPUs may differ more.
MSH_FN float3 msh_ggx_sample_vndf(float3 v, float2 alpha, float2 u) {
  float2 a = max(alpha, float2(MSH_MS_MIN_ALPHA, MSH_MS_MIN_ALPHA));
  float3 wi = msh_ms_safe_normalize(float3(a.x * v.x, a.y * v.y, v.z));
  if (wi.z < 0.0f) wi = -wi;
  float phi = 2.0f * MSH_MS_PI * u.x;
  // sin^2 = (1 - z)(1 + z) from factors without cancellation (as ggx.h): exact near both poles.
  float z = (1.0f - u.y) * (1.0f + wi.z) - wi.z;
  float s = sqrt(max((u.y * (1.0f + wi.z)) * ((1.0f - u.y) * (1.0f + wi.z) + (1.0f - wi.z)), 0.0f));
  float3 h = float3(s * cos(phi), s * sin(phi), z) + wi;
  return msh_ms_safe_normalize(float3(a.x * h.x, a.y * h.y, max(0.0f, h.z)));
}
// Isotropic GGX: msh_ggx_sample_vndf with alpha_x = alpha_y.
MSH_FN float3 msh_ggx_sample_vndf_isotropic(float3 v, float alpha, float2 u) {
  return msh_ggx_sample_vndf(v, float2(alpha, alpha), u);
}

// Projected roughness alpha(phi_w) = sqrt(ax^2 cos^2 phi + ay^2 sin^2 phi) along the azimuth of w (Zurita 2026 Part 2
// ProjectRoughnessGGX; RTR4 9.51); sqrt((ax^2 + ay^2)/2) at the pole. |err| <= 2.5e-7 relative.
MSH_FN float msh_ggx_projected_alpha(float3 w, float2 alpha) {
  float2 a = max(alpha, float2(MSH_MS_MIN_ALPHA, MSH_MS_MIN_ALPHA));
  float s2 = w.x * w.x + w.y * w.y;
  if (!(s2 > 0.0f)) return sqrt(0.5f * (a.x * a.x + a.y * a.y));
  float2 p = a * float2(w.x, w.y);
  return sqrt(dot(p, p) / s2);
}

// Perceptual roughness for the isotropic LUT at anisotropic GGX alpha = (alpha_x, alpha_y): the rms of the
// roughness projected along v and along l, r = sqrt(sqrt((alpha(v)^2 + alpha(l)^2) / 2)). Port of
// ms::micro_shadowing_isotropic_roughness (include/microshadow/occlusion/micro_shadowing_anisotropic.h); its
// as-used error against the exact anisotropic term is in docs/micro-shadowing.md. |err| <= 1e-6 relative.
MSH_FN float msh_ms_lut_roughness_anisotropic(float3 v, float3 l, float2 alpha) {
  float av = msh_ggx_projected_alpha(v, alpha), al = msh_ggx_projected_alpha(l, alpha);
  return sqrt(sqrt(0.5f * (av * av + al * al)));
}

// Smith GGX G1(w) = 1 / (1 + Lambda(w)) (RTR4 9.24, 9.37) from the projected roughness, written as
// 2|z| / (|z| + sqrt(z^2 + alpha^2 (x^2 + y^2))): finite and exact at grazing. |err| <= 5e-7.
MSH_FN float msh_ggx_g1_projected(float3 w, float projected_alpha) {
  float z = abs(w.z);
  float den = z + sqrt(w.z * w.z + projected_alpha * projected_alpha * (w.x * w.x + w.y * w.y));
  return den > 0.0f ? 2.0f * z / den : 1.0f;
}

// G2(v,l,m)/G1(v,m) for the Smith profile with m.l > 0, m.v > 0 (Zurita 2026 Part 2 table), from the G1 of l and v:
// uncorrelated G1(l); height-correlated G1(l) / (G1(l) + G1(v) - G1(l) G1(v)). |err| <= 1e-6.
MSH_FN float msh_ms_smith_g2_over_g1(float g1_l, float g1_v, bool height_correlated) {
  if (!height_correlated) return g1_l;
  float den = g1_l + g1_v - g1_l * g1_v;
  return den > 0.0f ? g1_l / den : 0.0f;
}

// The seed's per-microfacet function GenericM_m (Zurita 2026 Part 2, MicroShadowingTermPZGenericVNDFBased), anisotropic
// GGX, shading frame: m from the VNDF of v (Dupuy-Benyoub 2023), weight G2/G1 from the projected roughness of
// v and l. cone/hemisphere are 0 or the weight; exact (bit-identical decisions) except where n.m or m.l lies
// within ~1e-5 of cos_t (the sampler's precision; 0 mismatches measured away from 1e-4 of the thresholds);
// weight |err| <= 1e-6 (1.8e-7 measured).
MSH_FN void msh_ms_generic_vndf_sample(float cos_t, float2 alpha, float3 v, float3 l, float2 u, bool height_correlated,
                                MSH_OUT(float) cone, MSH_OUT(float) hemisphere, MSH_OUT(float) weight) {
  float3 m = msh_ggx_sample_vndf(v, alpha, u);
  float alpha_v = msh_ggx_projected_alpha(v, alpha);  // project GGX roughness onto v
  float alpha_l = msh_ggx_projected_alpha(l, alpha);  // ... and onto l
  float n_dot_m = clamp(m.z, 0.0f, 1.0f);
  float m_dot_l = clamp(dot(m, l), 0.0f, 1.0f);
  float c = clamp(cos_t, 0.0f, 1.0f);
  weight = m_dot_l > 0.0f ? msh_ms_smith_g2_over_g1(msh_ggx_g1_projected(l, alpha_l),
                                                   msh_ggx_g1_projected(v, alpha_v), height_correlated)
                         : 0.0f;
  hemisphere = (n_dot_m > 0.0f && m_dot_l > 0.0f) ? weight : 0.0f;
  cone = (n_dot_m - c > 0.0f && m_dot_l - c > 0.0f) ? weight : 0.0f;
}

// Isotropic GenericM_m (Zurita 2026 Part 2, MicroShadowingTermPZGenericVNDFBased_Isotropic): the same with one alpha.
MSH_FN void msh_ms_generic_vndf_sample_isotropic(float cos_t, float alpha, float3 v, float3 l, float2 u,
                                          bool height_correlated, MSH_OUT(float) cone, MSH_OUT(float) hemisphere,
                                          MSH_OUT(float) weight) {
  float3 m = msh_ggx_sample_vndf_isotropic(v, alpha, u);
  float a = max(alpha, MSH_MS_MIN_ALPHA);
  float n_dot_m = clamp(m.z, 0.0f, 1.0f);
  float m_dot_l = clamp(dot(m, l), 0.0f, 1.0f);
  float c = clamp(cos_t, 0.0f, 1.0f);
  weight = m_dot_l > 0.0f ? msh_ms_smith_g2_over_g1(msh_ggx_g1_projected(l, a), msh_ggx_g1_projected(v, a),
                                                   height_correlated)
                         : 0.0f;
  hemisphere = (n_dot_m > 0.0f && m_dot_l > 0.0f) ? weight : 0.0f;
  cone = (n_dot_m - c > 0.0f && m_dot_l - c > 0.0f) ? weight : 0.0f;
}

// ---- Low-discrepancy points (bit-identical to msh::sobol_2d / msh::hammersley_2d) ---------------------------

// msh_reverse_bits(x), the bit reversal of a 32-bit word, is in the prelude (it differs per language).
// msh_hash_u32 and msh_hash_combine (the seeds of the scrambled sequence) are in hash.h, which the C++ library
// shares (msh::hash_u32, math/sampling.h).
// Burley 2020, "Practical Hash-based Owen Scrambling" (JCGT 9(4)): Laine-Karras permutation, reversed bits.
MSH_FN uint msh_nested_uniform_scramble(uint x, uint seed) {
  x = msh_reverse_bits(x);
  x += seed;
  x ^= x * 0x6c50b47cu;
  x ^= x * 0xb82f1e52u;
  x ^= x * 0xc7afe638u;
  x ^= x * 0x8d22f6e6u;
  return msh_reverse_bits(x);
}
// Sobol dimension 1: direction numbers v_0 = 2^31, v_k = v_{k-1} ^ (v_{k-1} >> 1).
MSH_FN uint msh_sobol_dim1(uint index) {
  uint r = 0u, v = 0x80000000u;
  for (; index != 0u; index >>= 1, v ^= v >> 1)
    if ((index & 1u) != 0u) r ^= v;
  return r;
}
// 32-bit fixed point to [0, 1): x 2^-32, at most the largest float below 1.
MSH_FN float msh_u32_to_unit(uint x) { return min(float(x) * 2.3283064365386963e-10f, msh_asfloat(0x3f7fffffu)); }
// Point `index` of the 2D Sobol sequence; seed 0: plain, else Owen-scrambled and index-shuffled (Burley 2020
// §4). Bit-identical to msh::sobol_2d<float> (integer arithmetic; correctly rounded uint -> float).
MSH_FN float2 msh_sobol_2d(uint index, uint seed) {
  if (seed == 0u) return float2(msh_u32_to_unit(msh_reverse_bits(index)), msh_u32_to_unit(msh_sobol_dim1(index)));
  uint i = msh_nested_uniform_scramble(index, seed);
  return float2(msh_u32_to_unit(msh_nested_uniform_scramble(msh_reverse_bits(i), msh_hash_combine(seed, 0u))),
              msh_u32_to_unit(msh_nested_uniform_scramble(msh_sobol_dim1(i), msh_hash_combine(seed, 1u))));
}
// Hammersley point i of n: (i/n, radical inverse of i). Bit-identical to msh::hammersley_2d<float>.
MSH_FN float2 msh_hammersley_2d(uint i, uint n) { return float2(float(i) / float(n), msh_u32_to_unit(msh_reverse_bits(i))); }

// GenericM_g (Zurita 2026 Part 2) estimated with n samples of msh_sobol_2d(i, seed) (the C++ estimator
// msh::ms::generic_vndf_estimate uses seed 1 by default): sum(cone) / sum(hemisphere); 0 when no sample reaches
// the hemisphere or when the exact early-out holds (no samples taken). The same points as C++, so the result
// differs from the C++ float estimate only by samples whose decision flips within the sampler's precision
// (tested |diff| <= 2/n; 8e-7 measured, no flips). QMC error vs the exact term: docs/shaders.md.
MSH_FN float msh_ms_generic_vndf_estimate(float vis, float2 alpha, float3 v, float3 l, int n, bool height_correlated,
                                   uint seed) {
  float V = clamp(vis, 0.0f, 1.0f);
  if (msh_ms_exact_zero(V, l.z)) return 0.0f;
  float c = msh_ms_cone_cos(V);
  float cone_sum = 0.0f, hemi_sum = 0.0f;
  for (int i = 0; i < n; ++i) {
    float cone, hemi, w;
    msh_ms_generic_vndf_sample(c, alpha, v, l, msh_sobol_2d(uint(i), seed), height_correlated, cone, hemi, w);
    cone_sum += cone;
    hemi_sum += hemi;
  }
  return hemi_sum > 0.0f ? min(1.0f, cone_sum / hemi_sum) : 0.0f;
}

// ---- LUT sampling (Zurita 2026, "Improving Direct Lighting Material Occlusion - Part 2", "LUT-Based Approximation"; layout docs/lut.md) ---------------------------------
// RGBA float texture (GLSL sampler2D/3D; HLSL Texture2D/3D<float4> + a SamplerState), linear filtering, clamp-to-edge, no mips:
// x = vis, y = N.L, z = N.V; channel c holds
// roughness knots[c] (default 0.1, 0.4, 0.7, 1.0). Texel i of an axis of n texels holds i/(n-1).
// Precision vs the C++ sampler (msh::lut::sample_micro_shadowing*) on lavapipe: see each function; on other GPUs
// the filter weights are quantized (Vulkan: subTexelPrecisionBits >= 4, commonly 8), which adds up to
// 2^-(bits+1) times the difference of neighbouring texels.

// Half-texel remap u' = (u (n-1) + 0.5) / n: the texel centres then hold the values at i/(n-1).
MSH_FN float msh_ms_lut_coord(float u, float n) { return (clamp(u, 0.0f, 1.0f) * (n - 1.0f) + 0.5f) / n; }

// Linear interpolation across the roughness channels, as msh::lut::interpolate_roughness: roughness clamped to
// [knots[0], knots[channels-1]], then a lerp between the two bracketing channels. Same arithmetic as C++.
MSH_FN float msh_ms_lut_roughness(float4 ch, float roughness, float4 knots, int channels) {
  if (channels <= 1) return ch[0];
  float r = roughness;
  if (!(r > knots[0])) r = knots[0];
  if (r > knots[channels - 1]) r = knots[channels - 1];
  int j = 0;
  while (j + 2 < channels && r > knots[j + 1]) ++j;
  float r0 = knots[j], r1 = knots[j + 1];
  float t = r1 > r0 ? clamp((r - r0) / (r1 - r0), 0.0f, 1.0f) : 0.0f;
  return ch[j] + t * (ch[j + 1] - ch[j]);
}
// The default channels r, g, b, a = roughness 0.1, 0.4, 0.7, 1.0 (Zurita 2026 Part 2).
MSH_FN float msh_ms_lut_roughness_default(float4 ch, float roughness) {
  return msh_ms_lut_roughness(ch, roughness, float4(0.1f, 0.4f, 0.7f, 1.0f), 4);
}

// Trilinear fetch of the four roughness channels at (vis, N.L, N.V), with the half-texel remap (no early-out):
// for tables with other roughness knots, pass the result to msh_ms_lut_roughness.
MSH_FN float4 msh_ms_lut_fetch(MSH_TEXTURE3D(lut, smp), float vis, float n_dot_l, float n_dot_v) {
  float3 n = float3(msh_texture_size3(lut));
  float3 uvw = float3(msh_ms_lut_coord(vis, n.x), msh_ms_lut_coord(n_dot_l, n.y), msh_ms_lut_coord(n_dot_v, n.z));
  return msh_sample_level0(lut, smp, uvw);
}

// 3D LUT (Zurita 2026 Part 2): early-out before the fetch, trilinear fetch, roughness interpolation. The table holds the
// mean over the relative azimuth. Perceptual roughness. |shader - C++| <= 1e-6 on lavapipe (1.8e-7 measured).
MSH_FN float msh_ms_lut_sample(MSH_TEXTURE3D(lut, smp), float vis, float n_dot_l, float n_dot_v,
                        float roughness) {
  if (msh_ms_exact_zero(vis, n_dot_l)) return 0.0f;
  float4 ch = msh_ms_lut_fetch(MSH_TEXTURE_ARGS(lut, smp), vis, n_dot_l, n_dot_v);
  return clamp(msh_ms_lut_roughness_default(ch, roughness), 0.0f, 1.0f);
}

// 2D LUT (Zurita 2026 Part 2): the N.V = 1 slice, x = vis, y = N.L. |shader - C++| <= 1e-6 on lavapipe (1.2e-7 meas.).
MSH_FN float msh_ms_lut_sample_2d(MSH_TEXTURE2D(lut, smp), float vis, float n_dot_l, float roughness) {
  if (msh_ms_exact_zero(vis, n_dot_l)) return 0.0f;
  float2 n = float2(msh_texture_size2(lut));
  float2 uv = float2(msh_ms_lut_coord(vis, n.x), msh_ms_lut_coord(n_dot_l, n.y));
  return clamp(msh_ms_lut_roughness_default(msh_sample_level0(lut, smp, uv), roughness), 0.0f, 1.0f);
}

// Relative azimuth cosine of v and l (tangent-plane projections), 1 when either projection vanishes
// (msh::lut::relative_azimuth_cos).
MSH_FN float msh_ms_relative_azimuth_cos(float3 v, float3 l) {
  float d = sqrt((v.x * v.x + v.y * v.y) * (l.x * l.x + l.y * l.y));
  if (!(d > 0.0f)) return 1.0f;
  return clamp((v.x * l.x + v.y * l.y) / d, -1.0f, 1.0f);
}

// Azimuth-aware LUT (msh::lut::sample_micro_shadowing_azimuth, `bake micro-shadowing --azimuth H`): the depth
// holds H+1 slabs of n_nv = depth/(H+1) slices; slab h holds the cos(h phi) Fourier coefficient, so the term is
// a_0 + sum_h a_h cos(h phi), cos(h phi) by the Chebyshev recurrence. The z coordinate stays inside a slab
// (texel centres of its first and last slice), so slabs never bleed. A 2D azimuth table (n_nv = 1) is a 3D
// texture of depth H+1. |shader - C++| <= 1e-6 on lavapipe (1.8e-7 measured).
MSH_FN float msh_ms_lut_sample_azimuth(MSH_TEXTURE3D(lut, smp), int harmonics, float vis,
                                float n_dot_l, float n_dot_v, float roughness, float cos_phi) {
  if (msh_ms_exact_zero(vis, n_dot_l)) return 0.0f;
  int3 size = msh_texture_size3(lut);
  int n_nv = size.z / (harmonics + 1);
  float2 uv = float2(msh_ms_lut_coord(vis, float(size.x)), msh_ms_lut_coord(n_dot_l, float(size.y)));
  float zt = clamp(n_dot_v, 0.0f, 1.0f) * float(n_nv - 1) + 0.5f;  // texel coordinate within a slab, + 0.5
  float c1 = clamp(cos_phi, -1.0f, 1.0f);
  float sum = msh_ms_lut_roughness_default(msh_sample_level0(lut, smp, float3(uv, zt / float(size.z))), roughness);
  float t_prev = 1.0f, t = c1;  // cos((h-1) phi), cos(h phi)
  for (int h = 1; h <= harmonics; ++h) {
    float3 uvw = float3(uv, (float(h * n_nv) + zt) / float(size.z));
    sum += t * msh_ms_lut_roughness_default(msh_sample_level0(lut, smp, uvw), roughness);
    float next = 2.0f * c1 * t - t_prev;
    t_prev = t;
    t = next;
  }
  return clamp(sum, 0.0f, 1.0f);
}

// ---- Cone-layout LUT (the default table; docs/lut.md) ----------------------------------------------------
// A 3D texture, linear filtering, clamp-to-edge, no mips: x = t (the cone half-angle relative to the light,
// t = 0 at the early-out boundary 2 vis + N.L = 1, t = 1 at vis = 1 or, for grazing light, a little past it), y = N.L coordinate, z = N.V coordinate
// + n_nv * roughness slab (depth = n_nv * n_rough); channel h = the cos(h phi) coefficient a_h (a plain table
// has channel r = a_0 only). Two fetches per light: the two roughness slabs around the roughness, blended in
// the shader. The constants are the baker's defaults (ConeLayoutParams); a table baked with other warps
// needs the same values here. Same arithmetic as msh::lut::fetch_cone (C++ float); |shader - C++| on
// lavapipe: docs/shaders.md.
#define MSH_MS_CONE_ROUGHNESS_MIN 0.1f
#define MSH_MS_CONE_ROUGHNESS_MAX 1.0f
#define MSH_MS_CONE_WARP_SCALE 2.0f
#define MSH_MS_CONE_NV_SCALE 3.0f
#define MSH_MS_CONE_TOP_SCALE 3.0f

// u(d) = d / (a + |d|): the warp of d = sin(theta - theta_l).
MSH_FN float msh_ms_cone_warp_u(float d, float a) { return d / (a + abs(d)); }

// t in [0, 1] for visibility vis, N.L and warp width a (msh::lut::cone_t).
MSH_FN float msh_ms_cone_t(float vis, float n_dot_l, float a) {
  float V = clamp(vis, 0.0f, 1.0f), zl = clamp(n_dot_l, 0.0f, 1.0f);
  float sl = sqrt(max(0.0f, 1.0f - zl * zl));
  float d = sqrt(V) * zl - sqrt(1.0f - V) * sl;
  float ulo = msh_ms_cone_warp_u(-sqrt(0.5f * (1.0f - zl)), a);
  float e = MSH_MS_CONE_TOP_SCALE * a / (1.0f + MSH_MS_CONE_TOP_SCALE * a);
  float utop = msh_ms_cone_warp_u(sqrt(zl * zl + e * e * (1.0f - zl * zl)), a);  // just past V = 1
  return clamp((msh_ms_cone_warp_u(d, a) - ulo) / (utop - ulo), 0.0f, 1.0f);
}

// The channels a_0..a_3 of a cone-layout table at (vis, N.L, N.V, roughness), no early-out; n_rough = the
// number of roughness slabs (sidecar "roughness_slabs"). Roughness is clamped to [0.1, 1].
MSH_FN float4 msh_ms_lut_fetch_cone(MSH_TEXTURE3D(lut, smp), int n_rough, float vis, float n_dot_l,
                             float n_dot_v, float roughness) {
  int3 size = msh_texture_size3(lut);
  int n_nv = size.z / n_rough;
  float r = roughness;
  if (!(r > MSH_MS_CONE_ROUGHNESS_MIN)) r = MSH_MS_CONE_ROUGHNESS_MIN;
  if (r > MSH_MS_CONE_ROUGHNESS_MAX) r = MSH_MS_CONE_ROUGHNESS_MAX;
  float alpha = max(r * r, 1e-4f);
  float t = msh_ms_cone_t(vis, n_dot_l, MSH_MS_CONE_WARP_SCALE * alpha);
  float nlc = clamp(n_dot_l, 0.0f, 1.0f);
  float s = 0.5f * (sqrt(nlc) + 1.0f - sqrt(1.0f - nlc));  // N.L warp: dense near N.L = 0 and 1
  float c = clamp(n_dot_v, 0.0f, 1.0f), b = MSH_MS_CONE_NV_SCALE * alpha;
  float w = clamp(c / sqrt(b * b + c * c) * sqrt(b * b + 1.0f), 0.0f, 1.0f);  // N.V warp: dense below N.V ~ alpha
  float q = clamp((sqrt(r) - sqrt(MSH_MS_CONE_ROUGHNESS_MIN)) /
                      (sqrt(MSH_MS_CONE_ROUGHNESS_MAX) - sqrt(MSH_MS_CONE_ROUGHNESS_MIN)), 0.0f, 1.0f) *
            float(n_rough - 1);  // slabs uniform in sqrt(roughness)
  int j = min(int(q), max(n_rough - 2, 0));
  float f = n_rough > 1 ? clamp(q - float(j), 0.0f, 1.0f) : 0.0f;
  float2 uv = float2(msh_ms_lut_coord(t, float(size.x)), msh_ms_lut_coord(s, float(size.y)));
  float zt = w * float(n_nv - 1) + 0.5f;  // texel coordinate within a slab, + 0.5: slabs never bleed
  float4 a = msh_sample_level0(lut, smp, float3(uv, (float(j * n_nv) + zt) / float(size.z)));
  float4 bb = msh_sample_level0(lut, smp, float3(uv, (float((j + 1) * n_nv) + zt) / float(size.z)));
  return a + f * (bb - a);
}

// Plain cone-layout table (msh::lut::sample_micro_shadowing): early-out before any fetch, two fetches,
// the azimuth mean a_0.
MSH_FN float msh_ms_lut_sample_cone(MSH_TEXTURE3D(lut, smp), int n_rough, float vis, float n_dot_l,
                             float n_dot_v, float roughness) {
  if (msh_ms_exact_zero(vis, n_dot_l)) return 0.0f;
  return clamp(msh_ms_lut_fetch_cone(MSH_TEXTURE_ARGS(lut, smp), n_rough, vis, n_dot_l, n_dot_v, roughness).x, 0.0f,
               1.0f);
}

// Azimuth-aware cone-layout table (`bake micro-shadowing --azimuth`, RGBA = a_0..a_3; harmonics <= 3):
// a_0 + sum_h a_h cos(h phi), cos(h phi) by the Chebyshev recurrence from cos_phi
// (msh_ms_relative_azimuth_cos). Two fetches.
MSH_FN float msh_ms_lut_sample_cone_azimuth(MSH_TEXTURE3D(lut, smp), int n_rough, int harmonics,
                                     float vis, float n_dot_l, float n_dot_v, float roughness, float cos_phi) {
  if (msh_ms_exact_zero(vis, n_dot_l)) return 0.0f;
  float4 a = msh_ms_lut_fetch_cone(MSH_TEXTURE_ARGS(lut, smp), n_rough, vis, n_dot_l, n_dot_v, roughness);
  float c1 = clamp(cos_phi, -1.0f, 1.0f);
  float sum = a.x, t_prev = 1.0f, t = c1;
  for (int h = 1; h <= harmonics && h < 4; ++h) {
    sum += t * a[h];
    float next = 2.0f * c1 * t - t_prev;
    t_prev = t;
    t = next;
  }
  return clamp(sum, 0.0f, 1.0f);
}

#endif  // MSH_MICRO_SHADOWING_PORTABLE_H
