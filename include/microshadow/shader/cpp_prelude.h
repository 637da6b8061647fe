// The C++ prelude of the portable shader dialect (docs/shaders.md): what shaders/portable/*.h need to compile
// as C++20, the third beside shaders/glsl/msh_prelude.glsl and shaders/hlsl/msh_prelude.hlsl. The portable
// functions compiled with it are <microshadow/shader/portable.h> (namespace msh::shader); include that, not
// this. In the manner of FidelityFX's CPU path (AMD 2023, ffx_core_cpu.h): HLSL's vector and matrix types and
// the intrinsics the portable headers call, each with the GLSL/HLSL meaning, in float32.
//
// Where C++ pins what the shading languages leave open (stated so that CPU and GPU results can be compared):
//  - min, max and clamp return the non-NaN operand (IEEE 754-2008 minNum/maxNum, as Direct3D requires), so a
//    NaN input clamps to the lower bound instead of propagating;
//  - msh_mad is a fused multiply-add (std::fma), GLSL's fma(); `precise` (MSH_PRECISE) is empty: on a target
//    with FMA instructions (e.g. -march=x86-64-v3) GCC contracts a * b + c under -ffp-contract=fast (its
//    default in the GNU modes, -std=gnu++20, not in -std=c++20) and clang within an expression by default
//    (-ffp-contract=on); compile with -ffp-contract=off where the bodies' `precise` matters (the bump
//    terminator's exact 1 at an unperturbed normal). Baseline x86-64 has no FMA: nothing is contracted;
//  - textures are filtered exactly (float weights; GPUs quantize them, lavapipe to 8 bits): see Texture2D.
// Header-only, no I/O, no threads, C++ standard library only.
#pragma once

#include <bit>
#include <cmath>
#include <cstdint>

namespace msh::shader {

using uint = std::uint32_t;

// ---- Vectors ----------------------------------------------------------------------------------------------
// HLSL's floatN / intN / uintN (GLSL's vecN / ivecN / uvecN): components x, y, z, w and operator[].
template <class T, int N>
struct Vec;

template <class T>
struct Vec<T, 2> {
  T x{}, y{};
  constexpr Vec() = default;
  constexpr explicit Vec(T s) : x(s), y(s) {}
  constexpr Vec(T x_, T y_) : x(x_), y(y_) {}
  template <class U>
  constexpr explicit Vec(const Vec<U, 2>& o) : x(T(o.x)), y(T(o.y)) {}
  constexpr T& operator[](int i) { return i == 0 ? x : y; }
  constexpr T operator[](int i) const { return i == 0 ? x : y; }
};

template <class T>
struct Vec<T, 3> {
  T x{}, y{}, z{};
  constexpr Vec() = default;
  constexpr explicit Vec(T s) : x(s), y(s), z(s) {}
  constexpr Vec(T x_, T y_, T z_) : x(x_), y(y_), z(z_) {}
  constexpr Vec(Vec<T, 2> xy, T z_) : x(xy.x), y(xy.y), z(z_) {}
  template <class U>
  constexpr explicit Vec(const Vec<U, 3>& o) : x(T(o.x)), y(T(o.y)), z(T(o.z)) {}
  constexpr T& operator[](int i) { return i == 0 ? x : (i == 1 ? y : z); }
  constexpr T operator[](int i) const { return i == 0 ? x : (i == 1 ? y : z); }
};

template <class T>
struct Vec<T, 4> {
  T x{}, y{}, z{}, w{};
  constexpr Vec() = default;
  constexpr explicit Vec(T s) : x(s), y(s), z(s), w(s) {}
  constexpr Vec(T x_, T y_, T z_, T w_) : x(x_), y(y_), z(z_), w(w_) {}
  constexpr Vec(Vec<T, 3> xyz, T w_) : x(xyz.x), y(xyz.y), z(xyz.z), w(w_) {}
  constexpr Vec(T x_, Vec<T, 3> yzw) : x(x_), y(yzw.x), z(yzw.y), w(yzw.z) {}
  constexpr Vec(Vec<T, 2> xy, T z_, T w_) : x(xy.x), y(xy.y), z(z_), w(w_) {}
  constexpr Vec(Vec<T, 2> xy, Vec<T, 2> zw) : x(xy.x), y(xy.y), z(zw.x), w(zw.y) {}
  template <class U>
  constexpr explicit Vec(const Vec<U, 4>& o) : x(T(o.x)), y(T(o.y)), z(T(o.z)), w(T(o.w)) {}
  constexpr T& operator[](int i) { return i == 0 ? x : (i == 1 ? y : (i == 2 ? z : w)); }
  constexpr T operator[](int i) const { return i == 0 ? x : (i == 1 ? y : (i == 2 ? z : w)); }
};

using float2 = Vec<float, 2>;
using float3 = Vec<float, 3>;
using float4 = Vec<float, 4>;
using int2 = Vec<int, 2>;
using int3 = Vec<int, 3>;
using int4 = Vec<int, 4>;
using uint2 = Vec<uint, 2>;
using uint3 = Vec<uint, 3>;
using uint4 = Vec<uint, 4>;

// f applied per component.
template <class T, int N, class F>
constexpr Vec<T, N> msh_cpp_map(Vec<T, N> a, F f) {
  Vec<T, N> r;
  for (int i = 0; i < N; ++i) r[i] = f(a[i]);
  return r;
}
template <class T, int N, class F>
constexpr Vec<T, N> msh_cpp_map(Vec<T, N> a, Vec<T, N> b, F f) {
  Vec<T, N> r;
  for (int i = 0; i < N; ++i) r[i] = f(a[i], b[i]);
  return r;
}

// Component-wise arithmetic, vector with vector and with a scalar on either side.
#define MSH_CPP_BINARY_OP(op)                                      \
  template <class T, int N>                                        \
  constexpr Vec<T, N> operator op(Vec<T, N> a, Vec<T, N> b) {      \
    return msh_cpp_map(a, b, [](T p, T q) { return p op q; });     \
  }                                                                \
  template <class T, int N>                                        \
  constexpr Vec<T, N> operator op(Vec<T, N> a, T s) {              \
    return a op Vec<T, N>(s);                                      \
  }                                                                \
  template <class T, int N>                                        \
  constexpr Vec<T, N> operator op(T s, Vec<T, N> b) {              \
    return Vec<T, N>(s) op b;                                      \
  }                                                                \
  template <class T, int N>                                        \
  constexpr Vec<T, N>& operator op##=(Vec<T, N>& a, Vec<T, N> b) { \
    return a = a op b;                                             \
  }                                                                \
  template <class T, int N>                                        \
  constexpr Vec<T, N>& operator op##=(Vec<T, N>& a, T s) {         \
    return a = a op Vec<T, N>(s);                                  \
  }
MSH_CPP_BINARY_OP(+)
MSH_CPP_BINARY_OP(-)
MSH_CPP_BINARY_OP(*)
MSH_CPP_BINARY_OP(/)
#undef MSH_CPP_BINARY_OP

template <class T, int N>
constexpr Vec<T, N> operator-(Vec<T, N> a) {
  return msh_cpp_map(a, [](T p) { return -p; });
}

// ---- Intrinsics -------------------------------------------------------------------------------------------
// Scalar float and int forms, and the component-wise forms of vectors (with a scalar operand where GLSL and
// HLSL both allow one).
inline float min(float a, float b) { return std::fmin(a, b); }
inline float max(float a, float b) { return std::fmax(a, b); }
inline int min(int a, int b) { return a < b ? a : b; }
inline int max(int a, int b) { return a > b ? a : b; }
inline uint min(uint a, uint b) { return a < b ? a : b; }
inline uint max(uint a, uint b) { return a > b ? a : b; }
inline float clamp(float x, float lo, float hi) { return min(max(x, lo), hi); }
inline int clamp(int x, int lo, int hi) { return min(max(x, lo), hi); }
inline float abs(float x) { return std::fabs(x); }
inline int abs(int x) { return x < 0 ? -x : x; }
inline float sign(float x) { return x > 0.0f ? 1.0f : (x < 0.0f ? -1.0f : 0.0f); }
inline float step(float edge, float x) { return x < edge ? 0.0f : 1.0f; }
inline float smoothstep(float e0, float e1, float x) {
  const float t = clamp((x - e0) / (e1 - e0), 0.0f, 1.0f);
  return t * t * (3.0f - 2.0f * t);
}
inline float sqrt(float x) { return std::sqrt(x); }
inline float sin(float x) { return std::sin(x); }
inline float cos(float x) { return std::cos(x); }
inline float tan(float x) { return std::tan(x); }
inline float acos(float x) { return std::acos(x); }
inline float asin(float x) { return std::asin(x); }
inline float atan(float x) { return std::atan(x); }
inline float exp(float x) { return std::exp(x); }
inline float exp2(float x) { return std::exp2(x); }
inline float log(float x) { return std::log(x); }
inline float log2(float x) { return std::log2(x); }
inline float pow(float x, float y) { return std::pow(x, y); }
inline float floor(float x) { return std::floor(x); }
inline float ceil(float x) { return std::ceil(x); }

#define MSH_CPP_UNARY_FN(fn)                              \
  template <int N>                                        \
  Vec<float, N> fn(Vec<float, N> a) {                     \
    return msh_cpp_map(a, [](float p) { return fn(p); }); \
  }
MSH_CPP_UNARY_FN(abs)
MSH_CPP_UNARY_FN(sign)
MSH_CPP_UNARY_FN(sqrt)
MSH_CPP_UNARY_FN(sin)
MSH_CPP_UNARY_FN(cos)
MSH_CPP_UNARY_FN(exp2)
MSH_CPP_UNARY_FN(log2)
MSH_CPP_UNARY_FN(floor)
#undef MSH_CPP_UNARY_FN

#define MSH_CPP_BINARY_FN(fn)                                    \
  template <class T, int N>                                      \
  Vec<T, N> fn(Vec<T, N> a, Vec<T, N> b) {                       \
    return msh_cpp_map(a, b, [](T p, T q) { return fn(p, q); }); \
  }                                                              \
  template <class T, int N>                                      \
  Vec<T, N> fn(Vec<T, N> a, T s) {                               \
    return fn(a, Vec<T, N>(s));                                  \
  }
MSH_CPP_BINARY_FN(min)
MSH_CPP_BINARY_FN(max)
MSH_CPP_BINARY_FN(pow)
MSH_CPP_BINARY_FN(step)
#undef MSH_CPP_BINARY_FN

template <class T, int N>
Vec<T, N> clamp(Vec<T, N> x, Vec<T, N> lo, Vec<T, N> hi) {
  return min(max(x, lo), hi);
}
template <class T, int N>
Vec<T, N> clamp(Vec<T, N> x, T lo, T hi) {
  return min(max(x, lo), hi);
}

template <int N>
float dot(Vec<float, N> a, Vec<float, N> b) {
  float s = a[0] * b[0];
  for (int i = 1; i < N; ++i) s += a[i] * b[i];
  return s;
}
template <int N>
float length(Vec<float, N> a) {
  return sqrt(dot(a, a));
}
template <int N>
Vec<float, N> normalize(Vec<float, N> a) {
  return a / length(a);
}
inline float3 cross(float3 a, float3 b) {
  return float3(a.y * b.z - a.z * b.y, a.z * b.x - a.x * b.z, a.x * b.y - a.y * b.x);
}

// The portable spellings (msh_-prefixed where GLSL and HLSL name an intrinsic differently).
inline float msh_saturate(float x) { return clamp(x, 0.0f, 1.0f); }
template <int N>
Vec<float, N> msh_saturate(Vec<float, N> x) {
  return clamp(x, 0.0f, 1.0f);
}
inline float msh_rsqrt(float x) { return 1.0f / std::sqrt(x); }
inline float msh_atan2(float y, float x) { return std::atan2(y, x); }
inline float msh_lerp(float a, float b, float t) { return a + t * (b - a); }
template <int N>
Vec<float, N> msh_lerp(Vec<float, N> a, Vec<float, N> b, float t) {
  return a + t * (b - a);
}
inline float msh_frac(float x) { return x - std::floor(x); }
inline float msh_mad(float a, float b, float c) { return std::fma(a, b, c); }
inline float msh_asfloat(uint x) { return std::bit_cast<float>(x); }
inline uint msh_asuint(float x) { return std::bit_cast<uint>(x); }
// Bit reversal of a 32-bit word (HLSL reversebits, GLSL bitfieldReverse). Exact.
inline uint msh_reverse_bits(uint x) {
  x = ((x >> 1) & 0x55555555u) | ((x & 0x55555555u) << 1);
  x = ((x >> 2) & 0x33333333u) | ((x & 0x33333333u) << 2);
  x = ((x >> 4) & 0x0f0f0f0fu) | ((x & 0x0f0f0f0fu) << 4);
  x = ((x >> 8) & 0x00ff00ffu) | ((x & 0x00ff00ffu) << 8);
  return (x >> 16) | (x << 16);
}

// ---- float3x3 ---------------------------------------------------------------------------------------------
// Built by rows (msh_float3x3_rows); msh_mul(m, v) is the matrix times a column vector, msh_mul(v, m) the row
// vector times the matrix, as in HLSL's mul and GLSL's * on the transposed mat3 the GLSL prelude builds.
struct float3x3 {
  float3 r[3];
};
inline float3x3 msh_float3x3_rows(float3 a, float3 b, float3 c) { return float3x3{{a, b, c}}; }
inline float3 msh_mul(const float3x3& m, float3 v) {
  return float3(dot(m.r[0], v), dot(m.r[1], v), dot(m.r[2], v));
}
inline float3 msh_mul(float3 v, const float3x3& m) {
  return float3(v.x * m.r[0].x + v.y * m.r[1].x + v.z * m.r[2].x,
                v.x * m.r[0].y + v.y * m.r[1].y + v.z * m.r[2].y,
                v.x * m.r[0].z + v.y * m.r[1].z + v.z * m.r[2].z);
}
inline float determinant(const float3x3& m) { return dot(m.r[0], cross(m.r[1], m.r[2])); }

// ---- Textures ---------------------------------------------------------------------------------------------
// A table on the CPU: RGBA float texels, x fastest, then y, then z; sampled like the shaders' sampler
// (linear filtering, clamp-to-edge addressing, normalized coordinates with texel centres at (i + 0.5) /
// size), at mip 0. The texels are not owned.
struct Texture2D {
  const float4* texels = nullptr;
  int width = 0, height = 0;
};
struct Texture3D {
  const float4* texels = nullptr;
  int width = 0, height = 0, depth = 0;
};

// The two texels around normalized coordinate u on an axis of n texels and the weight of the second.
struct MshCppTexelPair {
  int i0, i1;
  float f;
};
inline MshCppTexelPair msh_cpp_texel_pair(float u, int n) {
  const float x = u * float(n) - 0.5f;
  const float fl = std::floor(x);
  const int i = int(fl);
  const auto at = [n](int k) { return k < 0 ? 0 : (k >= n ? n - 1 : k); };
  return {at(i), at(i + 1), x - fl};
}
inline float4 msh_cpp_sample(const Texture2D& t, float2 uv) {
  const MshCppTexelPair a = msh_cpp_texel_pair(uv.x, t.width), b = msh_cpp_texel_pair(uv.y, t.height);
  const auto at = [&](int i, int j) {
    return t.texels[std::size_t(j) * std::size_t(t.width) + std::size_t(i)];
  };
  const float4 lo = at(a.i0, b.i0) + a.f * (at(a.i1, b.i0) - at(a.i0, b.i0));
  const float4 hi = at(a.i0, b.i1) + a.f * (at(a.i1, b.i1) - at(a.i0, b.i1));
  return lo + b.f * (hi - lo);
}
inline float4 msh_cpp_sample(const Texture3D& t, float3 uvw) {
  const MshCppTexelPair c = msh_cpp_texel_pair(uvw.z, t.depth);
  const std::size_t slab = std::size_t(t.width) * std::size_t(t.height);
  const Texture2D s0{t.texels + slab * std::size_t(c.i0), t.width, t.height};
  const Texture2D s1{t.texels + slab * std::size_t(c.i1), t.width, t.height};
  const float2 uv(uvw.x, uvw.y);
  const float4 lo = msh_cpp_sample(s0, uv);
  return lo + c.f * (msh_cpp_sample(s1, uv) - lo);
}

}  // namespace msh::shader

// The dialect's macros (docs/shaders.md has the table of all three preludes).
#define MSH_FN inline
#define MSH_GLOBAL_CONST inline constexpr
#define MSH_STATIC_CONST static const
#define MSH_ARRAY(T, N) {
#define MSH_ARRAY_END }
#define MSH_PRECISE
#define MSH_OUT(T) T&
#define MSH_INOUT(T) T&
#define MSH_OUT_ARRAY(T, name, n) T(&name)[n]
#define MSH_TEXTURE2D(t, s) const ::msh::shader::Texture2D& t
#define MSH_TEXTURE3D(t, s) const ::msh::shader::Texture3D& t
#define MSH_TEXTURE_ARGS(t, s) t
#define msh_sample_level0(t, s, uv) ::msh::shader::msh_cpp_sample(t, uv)
#define msh_texture_size2(t) ::msh::shader::int2((t).width, (t).height)
#define msh_texture_size3(t) ::msh::shader::int3((t).width, (t).height, (t).depth)
