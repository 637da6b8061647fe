// The inputs on which the directional functions of shaders/portable/directional.h are compared with the C++
// library (tests/test_shaders_directional.cpp on Vulkan, tests/test_shader_portable_cpp.cpp compiled as C++):
// channel sets (random, flat, baked from small height fields with their box mips) with lights, normals and
// views, 8-bit decodes, and the scale S of each sum that the bounds are relative to.
#pragma once

#include <microshadow/math/sampling.h>
#include <microshadow/occlusion/directional.h>
#include <microshadow/render/directional_bake.h>

#include <algorithm>
#include <array>
#include <cmath>
#include <cstddef>
#include <cstdint>
#include <initializer_list>
#include <vector>

namespace msh::test::directional_inputs {

namespace dir = msh::directional;

struct Rec {
  std::array<float, 12> c;  // c_0..c_8, then the c8 slot's padding: c[9] = origin (0 random, 1 flat, 2 baked)
  std::array<float, 4> l, n;
};
static_assert(sizeof(Rec) == 20 * sizeof(float));
struct Dec {
  std::array<float, 4> u, lo, hi, pad;
};

inline const float* channels(const Rec& r) { return r.c.data(); }
inline Vec3f light(const Rec& r) { return {r.l[0], r.l[1], r.l[2]}; }
inline Vec3f normal(const Rec& r) { return {r.n[0], r.n[1], r.n[2]}; }

// The baked channel sets' height fields, n²: 0 flat, 1 a sum of sines, 2 a deep crater field.
inline render::Texture test_field(int field, int n) {
  render::Texture h(n, n, 1);
  for (int y = 0; y < n; ++y)
    for (int x = 0; x < n; ++x) {
      const double u = 2 * kPi<double> * x / n, v = 2 * kPi<double> * y / n;
      double z = 0.5;
      if (field == 1) z = 0.5 + 0.25 * std::sin(2 * u) * std::cos(3 * v) + 0.2 * std::sin(5 * u + v);
      if (field == 2) z = 0.5 + 0.5 * std::cos(2 * u) * std::cos(2 * v) * std::sin(7 * u - 3 * v);
      h.at(x, y, 0) = float(std::clamp(z, 0.0, 1.0));
    }
  return h;
}

// Channel sets of n channels in arrays of Size floats, the last the set's origin (0 random, 1 flat, 2 baked):
// `random` random sets (signed, magnitudes 0.01–10), the flat surface's exact channels (c_3 = 1: transport =
// z) and `perturbed` perturbations of them, and every step(field, k)-th texel of bake(height, depth) of the
// 32² test fields from first_field on, at full size and box-downsampled by each k of mips.
template <std::size_t Size, class Bake, class Step>
std::vector<std::array<float, Size>> channel_sets_of(uint64_t seed, int n, int random, int perturbed,
                                                     int first_field, std::initializer_list<int> mips,
                                                     Bake&& bake, Step&& step) {
  constexpr std::size_t origin = Size - 1;
  std::vector<std::array<float, Size>> sets;
  Pcg32 rng(seed);
  for (int k = 0; k < random; ++k) {
    std::array<float, Size> c{};
    const double scale = std::pow(10.0, rng.next_double() * 3 - 2);
    for (int i = 0; i < n; ++i) c[std::size_t(i)] = float((rng.next_double() * 2 - 1) * scale);
    sets.push_back(c);
  }
  std::array<float, Size> flat{};
  flat[3] = 1, flat[origin] = 1;
  sets.push_back(flat);
  for (int k = 0; k < perturbed; ++k) {
    std::array<float, Size> c = flat;
    for (int i = 0; i < n; ++i) c[std::size_t(i)] += float((rng.next_double() * 2 - 1) * 0.05);
    sets.push_back(c);
  }
  const int size = 32;
  for (int field = first_field; field < 3; ++field) {
    const render::Texture ch = bake(test_field(field, size), field == 2 ? 6.0f : 3.0f);
    for (int k : mips) {
      const render::Texture t = k == 1 ? ch : render::box_downsample(ch, k);
      const int stride = step(field, k);
      for (int y = 0; y < t.height(); y += stride)
        for (int x = 0; x < t.width(); x += stride) {
          std::array<float, Size> c{};
          for (int i = 0; i < n; ++i) c[std::size_t(i)] = t.at(x, y, i);
          c[origin] = 2;
          sets.push_back(c);
        }
    }
  }
  return sets;
}

// The 9-channel sets: 512 random, the flat one and 64 perturbations; baked: a flat field (every 8th texel at
// full size: they are all alike) and two bumpy ones (sum of sines; a deep crater field), 32 azimuths, box
// mips by 2, 4 and 16.
inline std::vector<std::array<float, 10>> channel_sets() {
  return channel_sets_of<10>(
      2026, 9, 512, 64, 0, {1, 2, 4, 16},
      [](const render::Texture& h, float depth) {
        return render::bake_directional_channels(h, depth, 32, 0.0f);
      },
      [](int field, int k) { return field == 0 && k == 1 ? 8 : 1; });
}

// Lights for one channel set: `random` uniform on the sphere, then, at one random azimuth, one per height z
// of zs (above and below the horizon, grazing, on the tangent plane, the zenith).
inline std::vector<Vec3f> test_lights(Pcg32& rng, int random, std::initializer_list<double> zs) {
  auto rnd = [&] { return Vec2d(rng.next_double(), rng.next_double()); };
  std::vector<Vec3f> lights;
  for (int k = 0; k < random; ++k) lights.push_back(Vec3f(sample_uniform_sphere(rnd())));
  const double phi = 2 * kPi<double> * rng.next_double();
  for (double z : zs) {
    const double s = std::sqrt(std::max(0.0, 1 - z * z));
    lights.push_back(Vec3f(float(s * std::cos(phi)), float(s * std::sin(phi)), float(z)));
  }
  return lights;
}

// Lights: above and below the horizon, grazing, on the tangent plane (±0), the zenith; normals: the flat +z,
// tilted ones and some facing away; a few n · l on the 1e-4 early-out boundary.
inline std::vector<Rec> make_records() {
  std::vector<Rec> recs;
  Pcg32 rng(77);
  auto rnd = [&] { return Vec2d(rng.next_double(), rng.next_double()); };
  for (const auto& c : channel_sets()) {
    for (const Vec3f& l : test_lights(rng, 6, {1e-6, 1e-3, 0.05, 0.0, -0.0, -1e-3, 1.0})) {
      Rec r{};
      std::copy(c.begin(), c.end(), r.c.begin());
      const int kind = int(rng.next_u32() % 4);
      Vec3f n(0, 0, 1);
      if (kind == 1) n = Vec3f(sample_uniform_cone(rnd(), 0.5));
      if (kind == 2) n = Vec3f(sample_uniform_sphere(rnd()));
      if (kind == 3) n = l;
      r.l = {l.x, l.y, l.z, 0};
      r.n = {n.x, n.y, n.z, 0};
      recs.push_back(r);
    }
  }
  // n · l = 1e-4 · (1 ± small): a normal at a chosen angle to an upper light.
  for (int k = 0; k < 256; ++k) {
    Rec r = recs[std::size_t(k) * 13];
    const Vec3d l = normalize(Vec3d(0.3, -0.2, 0.5 + rng.next_double() * 0.5));
    const Framed f = Framed::from_z(l);
    const double want = 1e-4 * (1 + (rng.next_double() * 2 - 1) * 0.1);
    const double a = 2 * kPi<double> * rng.next_double();
    const Vec3d n = f.to_world(
        Vec3d(std::sqrt(1 - want * want) * std::cos(a), std::sqrt(1 - want * want) * std::sin(a), want));
    r.l = {float(l.x), float(l.y), float(l.z), 0};
    r.n = {float(n.x), float(n.y), float(n.z), 0};
    recs.push_back(r);
  }
  return recs;
}

// 8-bit decodes: every UNORM value (the first 256) and random ones, with random ranges [lo, hi].
inline std::vector<Dec> make_decodes() {
  std::vector<Dec> d;
  Pcg32 rng(9);
  for (int k = 0; k < 4096; ++k) {
    Dec x{};
    for (int i = 0; i < 4; ++i) {
      const int q = k < 256 ? (k + 64 * i) % 256 : int(rng.next_u32() % 256);
      x.u[std::size_t(i)] = float(q) / 255.0f;
      const double lo = -std::pow(10.0, rng.next_double() * 3 - 2) * rng.next_double();
      x.lo[std::size_t(i)] = float(lo);
      x.hi[std::size_t(i)] = float(lo + std::pow(10.0, rng.next_double() * 3 - 2));
    }
    d.push_back(x);
  }
  return d;
}

// |b_i(l)| of the 9 basis functions in double, x² − y² read as x² + y².
inline std::array<double, 9> abs_basis(const Vec3d& l) {
  return {1,
          std::abs(l.x),
          std::abs(l.y),
          std::abs(l.z),
          std::abs(l.x * l.z),
          std::abs(l.y * l.z),
          l.x * l.x + l.y * l.y,
          std::abs(l.x * l.y),
          l.z * l.z};
}

// S = Σ|c_i||b_i(l)| in double: the size of what the 9-term sum adds.
inline double sum_scale(const Rec& r) {
  const std::array<double, 9> b = abs_basis(Vec3d(light(r)));
  double s = 0;
  for (int i = 0; i < 9; ++i) s += std::abs(double(r.c[std::size_t(i)])) * b[std::size_t(i)];
  return s;
}
struct VRec {
  std::array<float, 24> c;
  std::array<float, 4> l, v, n;
};
static_assert(sizeof(VRec) == 36 * sizeof(float));

// Channel sets of 21: 256 random, the flat surface's (T = z, G = 0) and 32 perturbations, and every third
// texel of the one-pass bake of the two bumpy fields of channel_sets (every texel of their box mips by 4 and
// 16); origin in c[23].
inline std::vector<std::array<float, 24>> view_channel_sets() {
  return channel_sets_of<24>(
      2027, 21, 256, 32, 1, {1, 4, 16},
      [](const render::Texture& h, float depth) {
        return render::bake_directional_view_channels(h, depth, 32, 0.0f);
      },
      [](int, int k) { return k == 1 ? 3 : 1; });
}

// Lights as make_records (above, grazing, ±0, below); views: random upper, grazing (v_z below the 0.1
// clamp, 0), the zenith; normals: flat, tilted, the light itself.
inline std::vector<VRec> make_view_records() {
  std::vector<VRec> recs;
  Pcg32 rng(78);
  auto rnd = [&] { return Vec2d(rng.next_double(), rng.next_double()); };
  for (const auto& c : view_channel_sets()) {
    for (const Vec3f& l : test_lights(rng, 4, {1e-3, 0.05, 0.0, -1e-3, 1.0})) {
      VRec r{};
      r.c = c;
      const int vk = int(rng.next_u32() % 4);
      Vec3f v = Vec3f(sample_uniform_hemisphere(rnd()));
      if (vk == 1) {
        const double vz = vk == 1 ? rng.next_double() * 0.12 : 0.0, a = 2 * kPi<double> * rng.next_double();
        v = Vec3f(float(std::sqrt(1 - vz * vz) * std::cos(a)), float(std::sqrt(1 - vz * vz) * std::sin(a)),
                  float(vz));
      }
      if (vk == 2) v = Vec3f(0, 0, 1);
      const int nk = int(rng.next_u32() % 3);
      Vec3f nn(0, 0, 1);
      if (nk == 1) nn = Vec3f(sample_uniform_cone(rnd(), 0.5));
      if (nk == 2) nn = l;
      r.l = {l.x, l.y, l.z, 0};
      r.v = {v.x, v.y, v.z, 0};
      r.n = {nn.x, nn.y, nn.z, 0};
      recs.push_back(r);
    }
  }
  return recs;
}

// S_v = S_T + (S_x |v_x| + S_y |v_y|) / max(v_z, 0.5) (the bound of shaders/portable/directional.h).
inline double view_sum_scale(const VRec& r) {
  const std::array<double, 9> b = abs_basis(Vec3d(r.l[0], r.l[1], r.l[2]));
  double st = 0, sx = 0, sy = 0;
  for (int i = 0; i < 9; ++i) st += std::abs(double(r.c[std::size_t(i)])) * b[std::size_t(i)];
  for (int i = 0; i < dir::kSlopeTerms; ++i)
    sx += std::abs(double(r.c[std::size_t(9 + i)])) * b[std::size_t(i)],
        sy += std::abs(double(r.c[std::size_t(15 + i)])) * b[std::size_t(i)];
  return st + (sx * std::abs(r.v[0]) + sy * std::abs(r.v[1])) / std::max(double(r.v[2]), dir::kMinViewZ);
}

}  // namespace msh::test::directional_inputs
