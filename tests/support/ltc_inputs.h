// The inputs on which the LTC functions of shaders/portable/ltc.h are compared with the C++ library
// (tests/test_shaders_ltc*.cpp on Vulkan, tests/test_shader_portable_cpp.cpp compiled as C++): the small LTC
// tables fitted by the library, the records of the sphere and rectangle integrals, and those of the
// cone-clipped micro-shadowing with their C++ double evaluation.
#pragma once

#include <microshadow/bsdf/ltc.h>
#include <microshadow/bsdf/ltc_shading.h>
#include <microshadow/bsdf/runtime/ltc_baker.h>
#include <microshadow/math/sampling.h>
#include <microshadow/occlusion/micro_shadowing.h>
#include <microshadow/occlusion/micro_shadowing_area.h>

#include <cmath>
#include <vector>

#include "ltc_test_table.h"
#include "random_records.h"
#include "shader_kernel.h"

namespace msh::test::ltc_inputs {

using namespace msh::bsdf;

namespace integrals {

struct Record {
  float a[4];  // roughness, N.V, and a, b of the matrix of the D check (c = w[3], d = 1)
  float n[4], v[4], l[4], w[4], c[4], ex[4], ey[4];
};

inline const LtcTable& table() {
  static const LtcTable t = test::small_ltc_table(8, 16, 60, 512);
  return t;
}

using vk::get;
using vk::put;

// 2048 random frames, views (N.V down to 0.02, and 1), roughness (and 0), sphere and rectangle lights of 1
// to 40 degrees from 10 degrees below the horizon to the zenith, 8- or 16-gons; directions for the D check.
inline std::vector<Record> make_records() {
  return random_records<Record>(2048, 77, [](auto& u, int i) {
    Record r{};
    const Vec3d n = sample_uniform_sphere(Vec2d(u(), u()));
    const Frame<double> f = Frame<double>::from_z(n);
    double mu = i % 64 == 0 ? 1.0 : 0.02 + 0.98 * u();
    const Vec3d v = f.to_world(spherical_direction(mu, 2 * kPi<double> * u()));
    r.a[0] = float(i % 50 == 0 ? 0.0 : u()), r.a[1] = float(mu), r.a[2] = float(0.3 + u()),
    r.a[3] = float(0.2 + u());
    if (i % 2) r.a[3] = -r.a[3];  // also selects the 8-gon
    put(r.n, n), put(r.v, v);
    const double el = (u() * 100 - 10) * kPi<double> / 180, sig = (1 + 39 * u()) * kPi<double> / 180;
    const Vec3d l = f.to_world(
        Vec3d(std::cos(el) * std::cos(6.3 * u()), std::cos(el) * std::sin(6.3 * u()), std::sin(el)));
    put(r.l, normalize(l), std::sin(sig));
    put(r.w, sample_uniform_sphere(Vec2d(u(), u())), u() - 0.5);
    const double d = 0.5 + 3 * u();
    const Frame<double> lf = Frame<double>::from_z(normalize(l));
    put(r.c, normalize(l) * d), put(r.ex, lf.s, d * std::tan(sig) * (0.5 + u())),
        put(r.ey, lf.t, d * std::tan(sig) * (0.5 + u()));
    return r;
  });
}

}  // namespace integrals

namespace cone {

struct Record {
  float t[4];   // (a, b, c, d) of M⁻¹; (1, 0, 0, 1) for Lambert
  float n[4];   // n, tail
  float v[4];   // v, cos t of the step
  float l[4];   // sphere: unit centre direction, sin σ
  float c[4];   // rect centre, visibility V of Brinck–Maximov
  float ex[4];  // rect half-axis x (unit), half-size
  float ey[4];  // rect half-axis y (unit), half-size
  float k[4];   // sphere polygon sides, product-rule nodes, α for the tail-weight check, degenerate flag
};

inline const LtcTable& table() {
  static const LtcTable t = test::small_ltc_table(4, 12, 40, 256);
  return t;
}

using vk::get;
using vk::put;

constexpr int kRandom = 1536;

// Records [0, kRandom): random; then the degenerate ones (k[3] = 1).
inline std::vector<Record> make_records() {
  const LtcTable& tab = table();
  return random_records<Record>(kRandom + 512, 2016, [&](auto& u, int i) {
    const bool degenerate = i >= kRandom;
    const int kind = i % 8;  // degenerate kind
    Record r{};
    const Vec3d n = sample_uniform_sphere(Vec2d(u(), u()));
    const Frame<double> f = Frame<double>::from_z(n);
    const double mu = (degenerate && kind == 5) ? 1.0 : 0.05 + 0.95 * u();
    const Vec3d v = f.to_world(spherical_direction(mu, 2 * kPi<double> * u()));
    const double rough = 0.1 + 0.9 * u(), alpha = rough * rough;
    const bool ggx = i % 2 == 1;
    if (ggx) {
      const LtcCoeffs<double> k = tab.fetch(rough, mu);
      r.t[0] = float(k.a), r.t[1] = float(k.b), r.t[2] = float(k.c), r.t[3] = float(k.d);
    } else {
      r.t[0] = 1, r.t[1] = 0, r.t[2] = 0, r.t[3] = 1;
    }
    put(r.n, n, ggx ? ltc_tail_weight(alpha) : 0.0);
    double cos_t = u(), vis = u();
    if (degenerate && kind == 0) cos_t = 1, vis = 0;                                 // V = 0
    if (degenerate && kind == 1) cos_t = 0, vis = 1;                                 // V = 1
    if (degenerate && kind == 2) cos_t = (i / 8) % 2 ? 1e-4 : 1 - 1e-6, vis = 1e-3;  // cos t near 0 / 1
    put(r.v, v, cos_t);
    double el = (u() * 105 - 15) * kPi<double> / 180, sig = (0.5 + 39.5 * u()) * kPi<double> / 180;
    if (degenerate && kind == 3) el = -(sig + 0.2 + 0.5 * u());   // the whole sphere light below the horizon
    if (degenerate && kind == 4) sig = 1e-3 * kPi<double> / 180;  // tiny light
    const double az = 2 * kPi<double> * u();
    const Vec3d l = f.to_world(Vec3d(std::cos(el) * std::cos(az), std::cos(el) * std::sin(az), std::sin(el)));
    put(r.l, l, std::sin(sig));
    const double d = 0.5 + 3 * u();
    const Frame<double> lf = Frame<double>::from_z(l);
    put(r.c, l * d, vis);
    put(r.ex, lf.s, d * std::tan(sig) * (0.5 + u())), put(r.ey, lf.t, d * std::tan(sig) * (0.5 + u()));
    if (degenerate && kind == 3) {  // the rectangle below the horizon too: lift it off its centre's side
      const Vec3d c = n * (-(d * std::tan(sig) * 3.5 + 0.1)) + l * (0.3 * d);
      put(r.c, c, vis);
    }
    r.k[0] = float(i % 3 == 0 ? 8 : 16), r.k[1] = float(2 + i % 3), r.k[2] = float(u()),
    r.k[3] = degenerate ? 1.f : 0.f;
    if (degenerate && kind == 6) r.k[2] = float(i % 16 < 8 ? 0.0 : 1.0);  // tail weight at α = 0, 1
    return r;
  });
}

struct Cpu {
  double step_s, step_r, bm_s, bm_r;
  LtcLightCone<double> sphere, rect;
};

inline Cpu cpu(const Record& r) {
  LtcCoeffs<double> k;
  k.a = r.t[0], k.b = r.t[1], k.c = r.t[2], k.d = r.t[3];
  const Mat3<double> minv = k.inv_m();
  const Vec3d n = get(r.n), v = get(r.v);
  const double tail = r.n[3], cos_t = r.v[3], V = r.c[3];
  const int sides = int(r.k[0]), nodes = int(r.k[1]);
  const Vec3d c = get(r.c), ex = get(r.ex) * double(r.ex[3]), ey = get(r.ey) * double(r.ey[3]);
  const Vec3d p[4] = {c - ex - ey, c + ex - ey, c + ex + ey, c - ex + ey};
  Cpu o;
  o.sphere = ltc_light_cone_sphere(minv, n, v, get(r.l), double(r.l[3]), tail, sides, 16);
  o.rect = ltc_light_cone_polygon(minv, n, v, p, 4, tail, 16);
  const auto& rect = o.rect;
  auto bm = [V](double z) { return micro_shadowing::brinck_maximov_2016(V, z); };
  const auto kinks = micro_shadowing::brinck_maximov_2016_kinks(V);
  o.step_s = ltc_reference_step_area(o.sphere, cos_t), o.step_r = ltc_reference_step_area(rect, cos_t);
  o.bm_s = ltc_micro_shadowing_area(bm, o.sphere, kinks, nodes);
  o.bm_r = ltc_micro_shadowing_area(bm, rect, kinks, nodes);
  return o;
}

}  // namespace cone

}  // namespace msh::test::ltc_inputs
