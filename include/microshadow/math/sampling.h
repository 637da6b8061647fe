// Deterministic random and low-discrepancy sequences, and the basic warps built on them.
// Everything here is a pure function of its inputs (index, seed): results never depend on threads or time.
#pragma once

#include <microshadow/math/vec.h>
#include <microshadow/shader/cpp_prelude.h>

#include <cstdint>

// The seed hashes, written once for the shaders and this library (shaders/portable/hash.h).
namespace msh::shader {
#include <shaders/portable/hash.h>
}  // namespace msh::shader

namespace msh {

// Largest float/double below 1: uniform samples live in [0, 1).
template <class T>
inline constexpr T kOneMinusEpsilon = T(1) - std::numeric_limits<T>::epsilon() / T(2);

// PCG32 (O'Neill 2014, pcg-random.org, "XSH RR" output): small state, good statistics, reproducible streams.
class Pcg32 {
 public:
  explicit Pcg32(uint64_t seed = 0x853c49e6748fea9bULL, uint64_t stream = 0xda3e39cb94b95bdbULL) {
    state_ = 0u;
    inc_ = (stream << 1u) | 1u;
    next_u32();
    state_ += seed;
    next_u32();
  }
  uint32_t next_u32() {
    const uint64_t old = state_;
    state_ = old * 0x5851f42d4c957f2dULL + inc_;
    const uint32_t xorshifted = uint32_t(((old >> 18u) ^ old) >> 27u);
    const uint32_t rot = uint32_t(old >> 59u);
    return (xorshifted >> rot) | (xorshifted << ((~rot + 1u) & 31u));
  }
  // Uniform in [0, 1).
  float next_float() { return std::min(float(next_u32()) * 0x1p-32f, kOneMinusEpsilon<float>); }
  double next_double() {
    const uint64_t hi = next_u32(), lo = next_u32();
    return double((hi << 21) ^ lo) * 0x1p-53;  // 53 random bits
  }
  template <class T>
  T next() {
    if constexpr (sizeof(T) == sizeof(float))
      return next_float();
    else
      return T(next_double());
  }

 private:
  uint64_t state_, inc_;
};

// 32-bit mixing hash and seed combination, for deriving seeds (shaders/portable/hash.h: the shaders' own).
inline uint32_t hash_u32(uint32_t x) { return shader::msh_hash_u32(x); }
inline uint32_t hash_combine(uint32_t seed, uint32_t v) { return shader::msh_hash_combine(seed, v); }

constexpr uint32_t reverse_bits(uint32_t x) {
  x = ((x >> 1) & 0x55555555u) | ((x & 0x55555555u) << 1);
  x = ((x >> 2) & 0x33333333u) | ((x & 0x33333333u) << 2);
  x = ((x >> 4) & 0x0f0f0f0fu) | ((x & 0x0f0f0f0fu) << 4);
  return (x >> 24) | ((x >> 8) & 0xff00u) | ((x << 8) & 0xff0000u) | (x << 24);  // the bytes (one bswap)
}

// First two dimensions of the Sobol sequence as 32-bit fixed point. Dimension 0 is the van der Corput
// sequence; dimension 1 uses the direction numbers v_0 = 2^31, v_k = v_{k-1} ^ (v_{k-1} >> 1) (Pascal's
// triangle mod 2). Any 2^k-point prefix is a (0, k, 2)-net.
constexpr uint32_t sobol_dim0(uint32_t index) { return reverse_bits(index); }
// The sum (xor) is linear in the index bits, so it is read from four tables of 256 (one per index byte):
// scrambled indices use all 32 bits, where a loop over the bits costs ~32 unpredictable branches.
namespace sobol_tables {
struct Dim1ByteTables {
  uint32_t t[4][256];
};
constexpr Dim1ByteTables make_dim1_byte_tables() {
  Dim1ByteTables d{};
  uint32_t v[32] = {};
  v[0] = 0x80000000u;
  for (int k = 1; k < 32; ++k) v[k] = v[k - 1] ^ (v[k - 1] >> 1);
  for (int b = 0; b < 4; ++b)
    for (uint32_t x = 0; x < 256; ++x)
      for (int k = 0; k < 8; ++k)
        if ((x >> k) & 1u) d.t[b][x] ^= v[8 * b + k];
  return d;
}
inline constexpr Dim1ByteTables kDim1ByteTables = make_dim1_byte_tables();
}  // namespace sobol_tables
constexpr uint32_t sobol_dim1(uint32_t index) {
  const auto& t = sobol_tables::kDim1ByteTables.t;
  return t[0][index & 0xffu] ^ t[1][(index >> 8) & 0xffu] ^ t[2][(index >> 16) & 0xffu] ^ t[3][index >> 24];
}

// Owen scrambling by hashing (Burley 2020, "Practical Hash-based Owen Scrambling", JCGT 9(4)), with the
// Laine-Karras style permutation in reversed-bit order. Keeps the net property; makes the estimate unbiased.
constexpr uint32_t laine_karras_permutation(uint32_t x, uint32_t seed) {
  x += seed;
  x ^= x * 0x6c50b47cu;
  x ^= x * 0xb82f1e52u;
  x ^= x * 0xc7afe638u;
  x ^= x * 0x8d22f6e6u;
  return x;
}
constexpr uint32_t nested_uniform_scramble(uint32_t x, uint32_t seed) {
  return reverse_bits(laine_karras_permutation(reverse_bits(x), seed));
}

template <class T>
constexpr T u32_to_unit(uint32_t x) {
  const T v = T(x) * T(0x1p-32);
  return v < kOneMinusEpsilon<T> ? v : kOneMinusEpsilon<T>;
}

// Point `index` of a 2D Sobol sequence; seed = 0 gives the plain (unscrambled) sequence, any other seed an
// Owen-scrambled and index-shuffled one (Burley 2020, §4), independent per seed.
template <class T>
Vec2<T> sobol_2d(uint32_t index, uint32_t seed = 0) {
  if (seed == 0) return {u32_to_unit<T>(sobol_dim0(index)), u32_to_unit<T>(sobol_dim1(index))};
  const uint32_t i = nested_uniform_scramble(index, seed);
  // nested_uniform_scramble(sobol_dim0(i), s) with reverse_bits(reverse_bits(i)) = i.
  return {u32_to_unit<T>(reverse_bits(laine_karras_permutation(i, hash_combine(seed, 0)))),
          u32_to_unit<T>(nested_uniform_scramble(sobol_dim1(i), hash_combine(seed, 1)))};
}

// Sobol sequence in up to kSobolMaxDims dimensions, 32-bit fixed point. Direction numbers of Joe & Kuo 2008,
// "Constructing Sobol sequences with better two-dimensional projections" (SIAM J. Sci. Comput. 30(5)),
// dimensions 1–5 of their table (s, a, m_i): dim 0 is van der Corput, then (1, 0, {1}), (2, 1, {1, 3}),
// (3, 1, {1, 3, 1}), (3, 2, {1, 1, 1}). Dims 0 and 1 equal sobol_dim0/sobol_dim1. Each dimension of any
// 2^k-point prefix is stratified into 2^k equal intervals.
inline constexpr int kSobolMaxDims = 5;
namespace sobol_tables {
struct SobolDirections {
  uint32_t v[kSobolMaxDims][32];
};
constexpr SobolDirections make_sobol_directions() {
  SobolDirections d{};
  for (int k = 0; k < 32; ++k) d.v[0][k] = 1u << (31 - k);
  struct Poly {
    int s;
    uint32_t a, m[3];
  };
  constexpr Poly polys[kSobolMaxDims - 1] = {
      {1, 0, {1, 0, 0}}, {2, 1, {1, 3, 0}}, {3, 1, {1, 3, 1}}, {3, 2, {1, 1, 1}}};
  for (int j = 1; j < kSobolMaxDims; ++j) {
    const Poly& p = polys[j - 1];
    uint32_t m[32] = {};
    for (int i = 0; i < p.s; ++i) m[i] = p.m[i];
    // m_i = 2 a_1 m_{i-1} ^ 4 a_2 m_{i-2} ^ ... ^ 2^{s-1} a_{s-1} m_{i-s+1} ^ 2^s m_{i-s} ^ m_{i-s}
    for (int i = p.s; i < 32; ++i) {
      uint32_t x = m[i - p.s] ^ (m[i - p.s] << p.s);
      for (int k = 1; k < p.s; ++k)
        if ((p.a >> (p.s - 1 - k)) & 1u) x ^= m[i - k] << k;
      m[i] = x;
    }
    for (int i = 0; i < 32; ++i) d.v[j][i] = m[i] << (31 - i);
  }
  return d;
}
inline constexpr SobolDirections kSobolDirections = make_sobol_directions();
}  // namespace sobol_tables

// Coordinate `dim` (0 ≤ dim < kSobolMaxDims) of Sobol point `index`, unscrambled.
constexpr uint32_t sobol_u32(uint32_t index, int dim) {
  uint32_t r = 0;
  for (int k = 0; index; index >>= 1, ++k)
    if (index & 1u) r ^= sobol_tables::kSobolDirections.v[dim][k];
  return r;
}

// Coordinate `dim` of point `index` of the Owen-scrambled, index-shuffled Sobol sequence for `seed` (Burley
// 2020, §4: one index shuffle shared by all dimensions, an independent scramble per dimension), in [0, 1).
// The first 2^k points are an aligned block of the sequence, so they keep its stratification.
template <class T>
T sobol_scrambled(uint32_t index, int dim, uint32_t seed) {
  const uint32_t i = nested_uniform_scramble(index, seed);
  return u32_to_unit<T>(nested_uniform_scramble(sobol_u32(i, dim), hash_combine(seed, uint32_t(dim))));
}

// Hammersley point i of n: (i/n, radical inverse of i). A (0, m, 2)-net when n = 2^m.
template <class T>
Vec2<T> hammersley_2d(uint32_t i, uint32_t n) {
  return {T(i) / T(n), u32_to_unit<T>(reverse_bits(i))};
}

// ---- Warps from the unit square. Each states its pdf (solid angle or area) next to it.

// Concentric map to the unit disk (Shirley & Chiu 1997): area-preserving, low distortion. pdf = 1/π.
template <class T>
Vec2<T> sample_uniform_disk_concentric(Vec2<T> u) {
  const T ox = T(2) * u.x - T(1), oy = T(2) * u.y - T(1);
  if (ox == T(0) && oy == T(0)) return {T(0), T(0)};
  T r, theta;
  if (std::abs(ox) > std::abs(oy)) {
    r = ox;
    theta = kPi<T> / T(4) * (oy / ox);
  } else {
    r = oy;
    theta = kPi<T> / T(2) - kPi<T> / T(4) * (ox / oy);
  }
  return {r * std::cos(theta), r * std::sin(theta)};
}

// Cosine-weighted hemisphere about +z (Malley's method). pdf = cos θ / π.
template <class T>
Vec3<T> sample_cosine_hemisphere(Vec2<T> u) {
  const Vec2<T> d = sample_uniform_disk_concentric(u);
  return {d.x, d.y, safe_sqrt(T(1) - d.x * d.x - d.y * d.y)};
}
template <class T>
T cosine_hemisphere_pdf(T cos_t) {
  return cos_t > T(0) ? cos_t * kInvPi<T> : T(0);
}

// Uniform over the hemisphere about +z. pdf = 1/(2π).
template <class T>
Vec3<T> sample_uniform_hemisphere(Vec2<T> u) {
  const T z = u.x;
  return spherical_direction(z, T(2) * kPi<T> * u.y);
}

// Uniform over the sphere. pdf = 1/(4π).
template <class T>
Vec3<T> sample_uniform_sphere(Vec2<T> u) {
  const T z = T(1) - T(2) * u.x;
  return spherical_direction(z, T(2) * kPi<T> * u.y);
}

// Uniform over the cone of directions with cos θ ≥ cos_max about +z. pdf = 1/(2π(1 − cos_max)).
template <class T>
Vec3<T> sample_uniform_cone(Vec2<T> u, T cos_max) {
  const T c = (T(1) - u.x) + u.x * cos_max;
  return spherical_direction(c, T(2) * kPi<T> * u.y);
}

}  // namespace msh
