// The inputs on which the micro-shadowing functions of shaders/portable/micro_shadowing.h are compared with
// the C++ library (tests/test_shaders_micro_shadowing.cpp on Vulkan, tests/test_shader_portable_cpp.cpp
// compiled as C++): the records, the small seed and cone-layout tables baked by the library, and the
// double-precision references written from the closed forms.
#pragma once

#include <microshadow/io/texture.h>
#include <microshadow/lut/micro_shadowing_lut.h>
#include <microshadow/lut/runtime/micro_shadowing_baker.h>
#include <microshadow/math/sampling.h>
#include <microshadow/math/vec.h>

#include <algorithm>
#include <cmath>
#include <cstdint>
#include <vector>

namespace msh::test::ms_inputs {

constexpr int kHarmonics = 2;  // azimuth-aware test table

// One record: a = (vis, N.L, alpha_x, alpha_y), v = (view, cos_phi), l = (light, sobol index),
// u = (u1, u2, perceptual roughness, N.V).
struct Record {
  float vis, nl, ax, ay;
  Vec3f v;
  float cos_phi;
  Vec3f l;
  uint32_t index;
  float u1, u2, roughness, nv;
};

inline Vec3f unit(double theta, double phi) {
  return Vec3f(Vec3d(std::sin(theta) * std::cos(phi), std::sin(theta) * std::sin(phi), std::cos(theta)));
}

// Random configurations over the whole domain plus degenerate ones: vis and N.L at and outside [0, 1],
// grazing, normal and backfacing v and l, alpha 0 / tiny / 1, u at the corners of [0,1)^2, the exact-zero
// boundary.
inline std::vector<Record> make_records() {
  std::vector<Record> r;
  Pcg32 rng(2026);
  auto uni = [&] { return rng.next_double(); };
  const float one_minus = kOneMinusEpsilon<float>;
  const int n_random = 4096;
  for (int i = 0; i < n_random; ++i) {
    Record x{};
    x.vis = float(uni());
    const Vec3f l = unit(std::acos(uni()), 2 * kPi<double> * uni());  // upper hemisphere
    const Vec3f v = unit(std::acos(uni()), 2 * kPi<double> * uni());
    x.nl = l.z;
    x.ax = float(sqr(0.05 + 0.95 * uni()));
    x.ay = i % 2 ? float(sqr(0.05 + 0.95 * uni())) : x.ax;
    x.v = v, x.l = l;
    x.u1 = float(uni()), x.u2 = float(uni());
    x.roughness = float(uni() * 1.2 - 0.1);  // also outside the channel range [0.1, 1]
    x.nv = float(uni());
    x.cos_phi = float(uni() * 2 - 1);
    x.index = uint32_t(rng.next_u32() >> (8 + i % 24));  // < 2^24: exact in the float record
    r.push_back(x);
  }
  const float vis_d[] = {0.0f, 1.0f, -0.25f, 1.5f, 1e-6f, 0.5f, 0.999999f, 0.05f};
  const float nl_d[] = {0.0f, 1.0f, -0.5f, 2.0f, 1e-7f, 0.5f};
  const float alpha_d[] = {0.0f, 1e-5f, 1.0f, 0.25f};
  const Vec3f dirs[] = {Vec3f(0, 0, 1), Vec3f(1, 0, 0), Vec3f(0, -1, 0), Vec3f(0.6f, 0, -0.8f),
                        Vec3f(0, 0, 0), unit(1.2, 0.3), Vec3f(0, 0, -1)};
  const float us[][2] = {{0, 0}, {one_minus, one_minus}, {0.5f, 0}, {0.25f, one_minus}};
  uint32_t k = 0;
  for (float vis : vis_d)
    for (float nl : nl_d)
      for (float a : alpha_d) {
        Record x{};
        x.vis = vis, x.nl = nl, x.ax = a, x.ay = (k % 3 == 0) ? 1.0f : a;
        x.v = dirs[k % 7];
        x.l = dirs[(k / 7 + 2) % 7];
        x.u1 = us[k % 4][0], x.u2 = us[k % 4][1];
        x.roughness = float(k % 5) * 0.25f;
        x.nv = float(k % 3) * 0.5f;
        x.cos_phi = float(int(k % 3) - 1);
        x.index = k;
        ++k;
        r.push_back(x);
      }
  // The early-out boundary 2 vis + N.L = 1 and the cone boundary N.L = cos_t.
  for (int i = 0; i < 256; ++i) {
    Record x = r[size_t(i)];
    x.vis = float(uni());
    x.nl = i % 2 ? 1.0f - 2.0f * x.vis : std::sqrt(1.0f - x.vis);
    x.l = Vec3f(std::sqrt(std::max(0.0f, 1 - x.nl * x.nl)), 0.0f, x.nl);
    r.push_back(x);
  }
  return r;
}

struct Luts {
  io::Volume plain, azimuth, two_d;
  lut::MicroShadowingLutView plain_v, azimuth_v, two_d_v;
};

// Small tables baked by the library: plain 3D (slab 0 of the azimuth-aware one), azimuth-aware (H = 2), 2D.
inline const Luts& luts() {
  static Luts* L = [] {
    auto* x = new Luts;
    lut::BakeOptions o;
    o.n_vis = 12, o.n_nl = 10, o.n_nv = 6;
    o.samples = 512, o.phi_nodes = 6, o.harmonics = kHarmonics;
    x->azimuth = lut::bake_micro_shadowing_lut(o);
    x->plain = io::Volume(o.n_vis, o.n_nl, o.n_nv, 4);
    std::copy_n(x->azimuth.data.begin(), x->plain.data.size(), x->plain.data.begin());
    o.two_d = true, o.harmonics = 0;
    x->two_d = lut::bake_micro_shadowing_lut(o);
    const std::vector<double> rough = {0.1, 0.4, 0.7, 1.0};
    x->azimuth_v = lut::make_view(x->azimuth, rough, kHarmonics);
    x->plain_v = lut::make_view(x->plain, rough, 0);
    x->two_d_v = lut::make_view(x->two_d, rough, 0);
    return x;
  }();
  return *L;
}

struct ConeLuts {
  io::Volume plain, azimuth, plain_rgba;
  lut::MicroShadowingLutView plain_v, azimuth_v;
  int n_rough = 5;
};

// Small cone-layout tables baked by the library with the default warps: plain (1 channel, uploaded as RGBA
// with a_0 in R) and azimuth-aware (H = 3, RGBA = a_0..a_3).
inline const ConeLuts& cone_luts() {
  static ConeLuts* L = [] {
    auto* x = new ConeLuts;
    lut::BakeOptions o = lut::default_bake_options();
    o.n_vis = 14, o.n_nl = 9, o.n_nv = 6, o.n_rough = x->n_rough;
    o.samples = 256, o.phi_nodes = 6, o.harmonics = 3;
    x->azimuth = lut::bake_micro_shadowing_lut(o);
    o.harmonics = 0;
    x->plain = lut::bake_micro_shadowing_lut(o);
    x->plain_rgba = io::Volume(x->plain.width, x->plain.height, x->plain.depth, 4);
    for (std::size_t i = 0; i < x->plain.data.size(); ++i) x->plain_rgba.data[4 * i] = x->plain.data[i];
    x->azimuth_v = lut::make_cone_view(x->azimuth, x->n_rough, 3, o.cone);
    x->plain_v = lut::make_cone_view(x->plain, x->n_rough, 0, o.cone);
    return x;
  }();
  return *L;
}

struct ConeRecord {
  float vis, nl, nv, roughness, cos_phi;
};

// ≥ 10⁴ random inputs over the domain (roughness also outside [0.1, 1]), the early-out boundary, and
// degenerate values (0, 1, outside [0, 1]).
inline std::vector<ConeRecord> make_cone_records() {
  std::vector<ConeRecord> r;
  Pcg32 rng(909);
  auto uni = [&] { return float(rng.next_double()); };
  for (int i = 0; i < 12000; ++i) r.push_back({uni(), uni(), uni(), uni() * 1.2f - 0.1f, uni() * 2 - 1});
  for (int i = 0; i < 1000; ++i) {  // 2 vis + N.L = 1 (float-rounded both ways)
    const float vis = uni() * 0.5f;
    r.push_back({vis, 1.0f - 2.0f * vis, uni(), uni(), uni() * 2 - 1});
    r.push_back({vis, std::nextafter(1.0f - 2.0f * vis, 2.0f), uni(), uni(), uni() * 2 - 1});
  }
  const float d[] = {0.0f, 1.0f, -0.5f, 1.5f, 1e-7f, 0.5f, 0.999999f};
  for (float a : d)
    for (float b : d)
      for (float c : d) r.push_back({a, b, c, c * 0.7f + 0.2f, b});
  return r;
}

// ---- Double references, written from the closed forms (docs/micro-shadowing.md, RTR4), not from the C++
// code. ----
inline double sat(double x) { return std::clamp(x, 0.0, 1.0); }
inline double ref_chan(double vis, double nl) {
  const double c = std::sqrt(1 - sat(vis));
  if (c == 0) return sat(nl) > 0 ? 1 : 0;
  return sqr(sat(sat(nl) / c));
}
inline double ref_brinck(double vis, double nl) { return sat(sat(nl) + 2 * sqr(sat(vis)) - 1); }
inline double ref_part1(double vis, double nl) {
  const double v = sat(vis);
  if (v == 0 || v == 1) return v;
  return std::pow(sat(sat(nl) / std::sqrt(1 - std::pow(v, 5))), 0.75 / v);
}
// RTR4 9.51 with the azimuth of w: alpha(phi) = sqrt(ax^2 cos^2 phi + ay^2 sin^2 phi).
inline double ref_projected_alpha(const Vec3d& w, double ax, double ay) {
  ax = std::max(ax, 1e-4), ay = std::max(ay, 1e-4);
  if (w.x == 0 && w.y == 0) return std::sqrt(0.5 * (ax * ax + ay * ay));
  const double phi = std::atan2(w.y, w.x);
  return std::sqrt(sqr(ax * std::cos(phi)) + sqr(ay * std::sin(phi)));
}
// RTR4 9.24 + 9.37: G1 = 1/(1 + Lambda), Lambda = (-1 + sqrt(1 + 1/a^2))/2, a = cos/(alpha sin).
inline double ref_g1(const Vec3d& w, double alpha) {
  const double z = std::abs(w.z) / length(w), s = std::sqrt(std::max(0.0, 1 - z * z));
  if (s == 0) return 1;
  if (z == 0) return 0;
  const double a = z / (alpha * s);
  return 1 / (1 + 0.5 * (-1 + std::sqrt(1 + 1 / (a * a))));
}

}  // namespace msh::test::ms_inputs
