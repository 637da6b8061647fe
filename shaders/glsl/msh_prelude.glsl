// microshadow: the GLSL prelude of the portable shader dialect (docs/shaders.md). Every shaders/glsl/<module>.glsl
// includes it before its body shaders/portable/<module>.h; users do not include it themselves. It holds only
// what differs from HLSL (its counterpart: shaders/hlsl/msh_prelude.hlsl): HLSL type names,
// msh_-prefixed spellings of the intrinsics whose names differ, row-wise matrix construction, `static const`,
// array initialisers, texture access. GLSL 4.50 / GLSL ES 3.20, and GLSL ES 3.00 (WebGL2) where it says so.
#ifndef MSH_PRELUDE_GLSL
#define MSH_PRELUDE_GLSL

#define float2 vec2
#define float3 vec3
#define float4 vec4
#define int2 ivec2
#define int3 ivec3
#define int4 ivec4
#define uint2 uvec2
#define uint3 uvec3
#define uint4 uvec4
#define float3x3 mat3

// A constant at global or function scope, and an array initialiser: MSH_ARRAY(float, 3) 1.0, 2.0, 3.0
// MSH_ARRAY_END (GLSL ES 3.00 has array constructors float[3](...), no {...} lists).
#define MSH_STATIC_CONST const
#define MSH_ARRAY(T, N) T[N](
#define MSH_ARRAY_END )

// Every function definition starts with MSH_FN and a constant at global scope with MSH_GLOBAL_CONST (C++:
// `inline` and `inline constexpr`, one definition across translation units).
#define MSH_FN
#define MSH_GLOBAL_CONST const

// Output parameters: MSH_OUT(float) x, MSH_INOUT(float3) y and an output array MSH_OUT_ARRAY(float3, p, 4)
// (references in the C++ prelude, include/microshadow/shader/cpp_prelude.h).
#define MSH_OUT(T) out T
#define MSH_INOUT(T) inout T
#define MSH_OUT_ARRAY(T, name, n) out T name[n]

#define msh_saturate(x) clamp((x), 0.0, 1.0)
#define msh_rsqrt(x) inversesqrt(x)
#define msh_atan2(y, x) atan(y, x)
#define msh_lerp(a, b, t) mix(a, b, t)
#define msh_frac(x) fract(x)
#define msh_asfloat(x) uintBitsToFloat(x)
#define msh_asuint(x) floatBitsToUint(x)
// Matrix times vector (or vector times matrix): the same math in both languages for matrices built by
// msh_float3x3_rows.
#define msh_mul(a, b) ((a) * (b))

// GLSL ES 3.00 (WebGL2, docs/viewer.md) has neither `precise` nor fma(): there an FMA contraction may differ
// from a desktop GPU by float rounding, and msh_mad is a * b + c (the compiler may or may not fuse it).
#if defined(GL_ES) && __VERSION__ < 320
#define MSH_PRECISE
#define msh_mad(a, b, c) ((a) * (b) + (c))
#else
#define MSH_PRECISE precise
#define msh_mad(a, b, c) fma(a, b, c)
#endif

// The 3x3 matrix whose rows are a, b, c (GLSL's mat3(a, b, c) takes columns). Exact.
float3x3 msh_float3x3_rows(float3 a, float3 b, float3 c) { return transpose(mat3(a, b, c)); }

// Bit reversal of a 32-bit word (HLSL reversebits). Exact. GLSL ES 3.00 (WebGL2, the browser viewer:
// docs/viewer.md) has no bitfieldReverse: the same bits by swaps.
#if defined(GL_ES) && __VERSION__ < 310
uint msh_reverse_bits(uint x) {
  x = ((x >> 1) & 0x55555555u) | ((x & 0x55555555u) << 1);
  x = ((x >> 2) & 0x33333333u) | ((x & 0x33333333u) << 2);
  x = ((x >> 4) & 0x0f0f0f0fu) | ((x & 0x0f0f0f0fu) << 4);
  x = ((x >> 8) & 0x00ff00ffu) | ((x & 0x00ff00ffu) << 8);
  return (x >> 16) | (x << 16);
}
#else
uint msh_reverse_bits(uint x) { return bitfieldReverse(x); }
#endif

// Textures: a parameter MSH_TEXTURE2D(t, s) / MSH_TEXTURE3D(t, s) is a sampler2D / sampler3D t in GLSL and a
// Texture2D/3D<float4> t with its SamplerState s in HLSL; MSH_TEXTURE_ARGS(t, s) passes it on;
// msh_sample_level0 samples mip 0 (linear filtering and addressing come from the sampler);
// msh_texture_size2/3 give the size in texels.
#define MSH_TEXTURE2D(t, s) sampler2D t
#define MSH_TEXTURE3D(t, s) sampler3D t
#define MSH_TEXTURE_ARGS(t, s) t
#define msh_sample_level0(t, s, uv) textureLod(t, uv, 0.0)
#define msh_texture_size2(t) textureSize(t, 0)
#define msh_texture_size3(t) textureSize(t, 0)

#endif  // MSH_PRELUDE_GLSL
