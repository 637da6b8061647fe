// microshadow: the HLSL prelude of the portable shader dialect (docs/shaders.md). Every shaders/hlsl/<module>.hlsl
// includes it before its body shaders/portable/<module>.h; users do not include it themselves. It holds only
// what differs from GLSL (its counterpart: shaders/glsl/msh_prelude.glsl): msh_-prefixed spellings of
// the intrinsics whose names differ, row-wise matrix construction, `static const`, array initialisers,
// texture access. SM 5.0+ (DXC, FXC) and glslang's HLSL front end.
#ifndef MSH_PRELUDE_HLSL
#define MSH_PRELUDE_HLSL

// A constant at global or function scope, and an array initialiser: MSH_ARRAY(float, 3) 1.0, 2.0, 3.0
// MSH_ARRAY_END.
#define MSH_STATIC_CONST static const
#define MSH_ARRAY(T, N) {
#define MSH_ARRAY_END }

// Every function definition starts with MSH_FN and a constant at global scope with MSH_GLOBAL_CONST (C++:
// `inline` and `inline constexpr`, one definition across translation units).
#define MSH_FN
#define MSH_GLOBAL_CONST static const

// Output parameters: MSH_OUT(float) x, MSH_INOUT(float3) y and an output array MSH_OUT_ARRAY(float3, p, 4)
// (references in the C++ prelude, include/microshadow/shader/cpp_prelude.h).
#define MSH_OUT(T) out T
#define MSH_INOUT(T) inout T
#define MSH_OUT_ARRAY(T, name, n) out T name[n]

#define msh_saturate(x) saturate(x)
#define msh_rsqrt(x) rsqrt(x)
#define msh_atan2(y, x) atan2(y, x)
#define msh_lerp(a, b, t) lerp(a, b, t)
#define msh_frac(x) frac(x)
#define msh_asfloat(x) asfloat(x)
#define msh_asuint(x) asuint(x)
// Matrix times vector (or vector times matrix) for matrices built by msh_float3x3_rows.
#define msh_mul(a, b) mul(a, b)

#define MSH_PRECISE precise
#define msh_mad(a, b, c) mad(a, b, c)

// The 3x3 matrix whose rows are a, b, c. Exact.
float3x3 msh_float3x3_rows(float3 a, float3 b, float3 c) { return float3x3(a, b, c); }

// Bit reversal of a 32-bit word. Exact.
uint msh_reverse_bits(uint x) { return reversebits(x); }

// Textures: see shaders/glsl/msh_prelude.glsl. A Texture2D/3D<float4> t with its SamplerState s.
#define MSH_TEXTURE2D(t, s) Texture2D<float4> t, SamplerState s
#define MSH_TEXTURE3D(t, s) Texture3D<float4> t, SamplerState s
#define MSH_TEXTURE_ARGS(t, s) t, s
#define msh_sample_level0(t, s, uv) t.SampleLevel(s, uv, 0.0)
int2 msh_texture_size2(Texture2D<float4> t) {
  uint w, h;
  t.GetDimensions(w, h);
  return int2(int(w), int(h));
}
int3 msh_texture_size3(Texture3D<float4> t) {
  uint w, h, d;
  t.GetDimensions(w, h, d);
  return int3(int(w), int(h), int(d));
}

#endif  // MSH_PRELUDE_HLSL
