// microshadow: shaders/portable/directional.h, written once for GLSL and HLSL in the portable dialect
// (docs/shaders.md): HLSL type names and the msh_* spellings that shaders/glsl/msh_prelude.glsl and
// shaders/hlsl/msh_prelude.hlsl define. Not included directly: GLSL `#include "shaders/glsl/directional.glsl"`,
// HLSL `#include "shaders/hlsl/directional.hlsl"` (their top comments say how).
// Directional micro-occlusion, the run-time reconstruction: port of include/microshadow/occlusion/directional.h
// (directional_transport, directional_term, directional_view_transport, directional_view_term,
// decode_unorm8); needs nothing else.
//
// Data: 9 linear channels per texel (render/directional_bake.h bakes them; `microshadow bake directional`
// writes them with their box-filtered mips), the weighted least-squares fit of the diffuse transport
// lit * max(n_fine . l, 0) over the upper hemisphere with the degree-2 polynomials, channel order
//   b(l) = (1, x, y, z, x z, y z, x^2 - y^2, x y, z^2).
// Fetch them with ordinary trilinear/anisotropic filtering (their box mean is the coarse texel's own fit),
// e.g. as two RGBA textures c0 = channels 0..3, c1 = channels 4..7 and one R texture c8 = channel 8.
// Tangent space of the normal map (render/texture_gen.h normal_map_from_height): x = +u (columns), y = +v
// (rows, top to bottom), z = the flat surface normal (the height map's +z, not the texel's own normal).
// l (the direction to the light) and n (the engine's coarse shading normal) are unit vectors in that frame.
//
// Precision vs the C++ float functions (tests/test_shaders_directional.cpp on lavapipe, random, flat and
// baked channel sets with their mips, lights above and below the horizon): the transport within
// 1e-6 * S, S = sum_i |c_i| |b_i(l)| (|b_6| read as x^2 + y^2), i.e. a few float roundings of the 9-term
// sum (measured 1.9e-7 * S); the term within 1e-6 * S / (n . l) + (1e-6 + 2.5e-7 * sum_i |n_i l_i| / (n . l))
// * term, the last part the rounding of n . l near the coarse terminator. Both early-outs (l.z <= 0,
// n . l <= 1e-4) return exactly 0 as in C++. NaN inputs are not guaranteed on GPUs (compilers may assume
// finite math).
#ifndef MSH_DIRECTIONAL_PORTABLE_H
#define MSH_DIRECTIONAL_PORTABLE_H

// The 9 basis functions at l: (1, x, y, z) and (x z, y z, x^2 - y^2, x y); z^2 is l.z * l.z. Port of
// msh::directional::poly2_basis. Exact up to one rounding per product.
MSH_FN float4 msh_dir_basis_hi(float3 l) { return float4(l.x * l.z, l.y * l.z, l.x * l.x - l.y * l.y, l.x * l.y); }

// sum_i c_i b_i(l) with the channels packed as c0 = (c_0..c_3), c1 = (c_4..c_7), c8 = c_8: the fitted
// transport before the clamp. float32, 9 products summed (within 1e-6 * S of C++, see the top).
MSH_FN float msh_dir_poly(float4 c0, float4 c1, float c8, float3 l) {
  return dot(c0, float4(1.0f, l)) + dot(c1, msh_dir_basis_hi(l)) + c8 * (l.z * l.z);
}

// a0 + a1 x + a2 y + a3 z + a4 xz + a5 yz (l = (x, y, z), h = msh_dir_basis_hi(l)), summed in the C++ order:
// the first six functions of the basis, shared by T and the slopes G_x, G_y. Exact (the same operations).
MSH_FN float msh_dir_sum6(float a0, float a1, float a2, float a3, float a4, float a5, float3 l, float4 h) {
  float s = a0;
  s += a1 * l.x;
  s += a2 * l.y;
  s += a3 * l.z;
  s += a4 * h.x;
  s += a5 * h.y;
  return s;
}

// Mean diffuse transport over the texel's footprint, lit * max(n_fine . l, 0), of a directional light:
// max(0, sum_i c_i b_i(l)), 0 for l.z <= 0. Port of msh::directional::directional_transport (degree-2
// weighted least-squares transport, docs/shaders.md "Directional micro-occlusion"; SSBump, Green 2007
// "Efficient self-shadowed radiosity normal mapping" stores the same kind of projection on 3 directions).
// Diffuse radiance = albedo / pi * E * transport, in place of max(n . l, 0) * micro-shadowing. float32,
// within 1e-6 * S of C++; exactly 0 below the horizon.
MSH_FN float msh_dir_transport(float4 c0, float4 c1, float c8, float3 l) {
  if (!(l.z > 0.0f)) return 0.0f;
  return max(msh_dir_poly(c0, c1, c8, l), 0.0f);
}

// The same with the channels as an array c[0..8] (the C++ order, summed in the C++ order). float32, within
// 1e-6 * S of C++; exactly 0 below the horizon.
MSH_FN float msh_dir_transport(float c[9], float3 l) {
  if (!(l.z > 0.0f)) return 0.0f;
  float4 h = msh_dir_basis_hi(l);
  float s = msh_dir_sum6(c[0], c[1], c[2], c[3], c[4], c[5], l, h);
  s += c[6] * h.z;
  s += c[7] * h.w;
  s += c[8] * (l.z * l.z);
  return max(s, 0.0f);
}

// The transport as a factor on the engine's max(n . l, 0) (n = the coarse shading normal, tangent space):
// transport / (n . l), 0 where n . l <= 1e-4. Not clamped to 1: near the coarse terminator lit facets can
// exceed the coarse cosine. Port of msh::directional::directional_term. float32, within the term's bound at
// the top of this file; exactly 0 at both early-outs.
MSH_FN float msh_dir_term(float4 c0, float4 c1, float c8, float3 l, float3 n) {
  float nl = dot(n, l);
  if (!(nl > 1e-4f)) return 0.0f;
  return msh_dir_transport(c0, c1, c8, l) / nl;
}

// The same with the channels as an array c[0..8]. float32, as above.
MSH_FN float msh_dir_term(float c[9], float3 l, float3 n) {
  float nl = dot(n, l);
  if (!(nl > 1e-4f)) return 0.0f;
  return msh_dir_transport(c, l) / nl;
}

// ---- The view correction (21 channels) ----
// Port of msh::directional::directional_view_transport / directional_view_term (docs/directional-occlusion.md,
// "The view-light correlation floor"): a camera along v sees each facet with its projected area
// (n . v)+ / n_z, so the footprint's mean it averages is T(l) + (G_x(l) v_x + G_y(l) v_y) / v_z, G_x, G_y
// the same kind of weighted least-squares fits of lit * max(n . l, 0) * n_x / n_z and * n_y / n_z, on the
// first 6 basis functions (1, x, y, z, xz, yz). v: unit, toward the camera, tangent space; v_z taken >= 0.1.
// Data: 21 linear channels per texel, channels 0-8 the transport, 9-14 G_x, 15-20 G_y, packed in 6 float4 as
// gen-material writes them (mips/directional_0 .. directional_5): c[k] = channels 4k .. 4k+3 (c[5] holds
// channel 20 in x; the rest unused). Fetch with ordinary trilinear/anisotropic filtering.
// Precision vs C++ float (tests/test_shaders_directional.cpp on lavapipe, random, flat and baked channel sets
// with their mips, views down to grazing): within 1e-6 * S_v, S_v = S_T + (S_x |v_x| + S_y |v_y|) / max(v_z,
// 0.5), S_* = sum_i |c_i| |b_i(l)| of each sum; the term within that / (n . l) plus the n . l rounding as
// msh_dir_term. Both early-outs return exactly 0 as in C++.

// Mean diffuse transport over the texel's footprint as a camera along v averages it: max(0, T + (G_x v_x +
// G_y v_y) / max(v_z, 0.5)), 0 for l.z <= 0 (v_z at least 0.5: beyond 60 deg off the normal the linear
// correction, which leaves masking out, would overshoot); each sum in the C++ order. float32, within 1e-6 *
// S_v of C++.
MSH_FN float msh_dir_view_transport(float4 c[6], float3 l, float3 v) {
  if (!(l.z > 0.0f)) return 0.0f;
  float4 h = msh_dir_basis_hi(l);
  float t = msh_dir_sum6(c[0].x, c[0].y, c[0].z, c[0].w, c[1].x, c[1].y, l, h);  // channels 0-8: T
  t += c[1].z * h.z;
  t += c[1].w * h.w;
  t += c[2].x * (l.z * l.z);
  float gx = msh_dir_sum6(c[2].y, c[2].z, c[2].w, c[3].x, c[3].y, c[3].z, l, h);  // channels 9-14: G_x
  float gy = msh_dir_sum6(c[3].w, c[4].x, c[4].y, c[4].z, c[4].w, c[5].x, l, h);  // channels 15-20: G_y
  float vz = max(v.z, 0.5f);
  return max(t + (gx * v.x + gy * v.y) / vz, 0.0f);
}

// The same as a factor on the engine's max(n . l, 0): msh_dir_view_transport / (n . l), 0 where n . l <=
// 1e-4; not clamped to 1. Port of msh::directional::directional_view_term. float32, within 1e-6 * S_v /
// (n . l) plus the n . l rounding (as msh_dir_term); exactly 0 at both early-outs.
MSH_FN float msh_dir_view_term(float4 c[6], float3 l, float3 v, float3 n) {
  float nl = dot(n, l);
  if (!(nl > 1e-4f)) return 0.0f;
  return msh_dir_view_transport(c, l, v) / nl;
}

// ---- Compact forms (a per-material linear code of the 21 channels) ----
// Port of msh::directional::decode_folded_code (docs/directional-occlusion.md, "Compact forms"): K UNORM
// coefficients per texel, 4 per RGBA8 texture (gen-material --directional-form pca<K>:
// mips/directional_compact_<t>), fetched with ordinary filtering (the code is linear, so the mips stay exact),
// decode to the 21 channels packed as msh_dir_view_transport takes them: channel i = fm_i + sum_k fb_ik u_k,
// fm / fb = mips.json's folded_mean / folded_basis (the material's uniforms). fm: 6 float4 (channel i in
// fm[i / 4][i % 4]); fb: one float4 per channel and fetched texture (rows 21-23 unread). float32: each channel
// within a few roundings of the (K + 1)-term sum, 1e-6 * (|fm_i| + sum_k |fb_ik| u_k) (measured in
// tests/test_shaders_directional.cpp on lavapipe).

// K <= 4 coefficients (one fetch): fb[i] = (fb_i0, fb_i1, fb_i2, fb_i3), 24 rows.
MSH_FN void msh_dir_code4_decode(float4 u, float4 fm[6], float4 fb[24], MSH_OUT_ARRAY(float4, c, 6)) {
  // Unrolled (as compilers would): 21 dot products, each row written once.
  c[0] = fm[0] + float4(dot(fb[0], u), dot(fb[1], u), dot(fb[2], u), dot(fb[3], u));
  c[1] = fm[1] + float4(dot(fb[4], u), dot(fb[5], u), dot(fb[6], u), dot(fb[7], u));
  c[2] = fm[2] + float4(dot(fb[8], u), dot(fb[9], u), dot(fb[10], u), dot(fb[11], u));
  c[3] = fm[3] + float4(dot(fb[12], u), dot(fb[13], u), dot(fb[14], u), dot(fb[15], u));
  c[4] = fm[4] + float4(dot(fb[16], u), dot(fb[17], u), dot(fb[18], u), dot(fb[19], u));
  c[5] = fm[5] + float4(dot(fb[20], u), 0.0f, 0.0f, 0.0f);
}

// K <= 8 coefficients (two fetches u0 = u_0..3, u1 = u_4..7): fb[2 i] = (fb_i0 .. fb_i3), fb[2 i + 1] =
// (fb_i4 .. fb_i7), 48 rows.
MSH_FN void msh_dir_code8_decode(float4 u0, float4 u1, float4 fm[6], float4 fb[48], MSH_OUT_ARRAY(float4, c, 6)) {
  // Unrolled: 42 dot products.
  c[0] = fm[0] + float4(dot(fb[0], u0) + dot(fb[1], u1), dot(fb[2], u0) + dot(fb[3], u1),
                        dot(fb[4], u0) + dot(fb[5], u1), dot(fb[6], u0) + dot(fb[7], u1));
  c[1] = fm[1] + float4(dot(fb[8], u0) + dot(fb[9], u1), dot(fb[10], u0) + dot(fb[11], u1),
                        dot(fb[12], u0) + dot(fb[13], u1), dot(fb[14], u0) + dot(fb[15], u1));
  c[2] = fm[2] + float4(dot(fb[16], u0) + dot(fb[17], u1), dot(fb[18], u0) + dot(fb[19], u1),
                        dot(fb[20], u0) + dot(fb[21], u1), dot(fb[22], u0) + dot(fb[23], u1));
  c[3] = fm[3] + float4(dot(fb[24], u0) + dot(fb[25], u1), dot(fb[26], u0) + dot(fb[27], u1),
                        dot(fb[28], u0) + dot(fb[29], u1), dot(fb[30], u0) + dot(fb[31], u1));
  c[4] = fm[4] + float4(dot(fb[32], u0) + dot(fb[33], u1), dot(fb[34], u0) + dot(fb[35], u1),
                        dot(fb[36], u0) + dot(fb[37], u1), dot(fb[38], u0) + dot(fb[39], u1));
  c[5] = fm[5] + float4(dot(fb[40], u0) + dot(fb[41], u1), 0.0f, 0.0f, 0.0f);
}

// 8-bit storage: a channel fetched from a UNORM texture (u in [0, 1], already filtered) mapped back to
// the material's range [lo, hi] (the fine level's min and max, the same for every mip level):
// lo + (hi - lo) * u (`unorm` is an HLSL keyword). Port of msh::directional::decode_unorm8. float32, within 2 roundings of C++ (one
// if the compiler fuses it). Decode after filtering: the map is affine, so it commutes with the box mean.
MSH_FN float msh_dir_decode_unorm8(float u, float lo, float hi) { return lo + (hi - lo) * u; }

// Four channels at once (one RGBA8 fetch). float32, as above.
MSH_FN float4 msh_dir_decode_unorm8(float4 u, float4 lo, float4 hi) { return lo + (hi - lo) * u; }

#endif  // MSH_DIRECTIONAL_PORTABLE_H
