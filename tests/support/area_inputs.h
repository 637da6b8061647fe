// The inputs on which the area-light functions of shaders/portable/micro_shadowing_area.h are compared with
// the C++ library (tests/test_shaders_micro_shadowing_area*.cpp on Vulkan, tests/test_shader_portable_cpp.cpp
// compiled as C++): cap lights (with the ten cap forms evaluated by the C++ templates in a scalar T), and
// disk and rectangle lights.
#pragma once

#include <microshadow/math/sampling.h>
#include <microshadow/occlusion/micro_shadowing.h>
#include <microshadow/occlusion/micro_shadowing_area.h>
#include <microshadow/occlusion/micro_shadowing_fit.h>
#include <microshadow/reference/micro_shadowing_area_exact.h>

#include <array>
#include <cmath>
#include <vector>

namespace msh::test::area_inputs {

namespace cap {

struct Rec {
  float vis, nl, nv, r, rho, pad[3];
};

// 2^13 random inputs (ρ over [0°, 90°], most in [1°, 40°]), lights straddling the cone boundary, and
// degenerate values (ρ = 0, N.L = 0 or 1, vis = 0 or 1).
inline std::vector<Rec> make_records() {
  std::vector<Rec> recs;
  Pcg32 rng(2024);
  auto u = [&] { return rng.next_float(); };
  const float deg = 3.14159265f / 180;
  for (int i = 0; i < (1 << 13); ++i) {
    const float rho = i % 8 == 0 ? 90 * deg * u() : (1 + 39 * u()) * deg;
    recs.push_back({u(), u(), u(), u(), rho, {0, 0, 0}});
  }
  for (int i = 0; i < 512; ++i) {  // centre near the cone boundary
    const float vis = u(), rho = (1 + 39 * u()) * deg;
    const float nl = std::cos(std::acos(std::sqrt(1 - vis)) + (2 * u() - 1) * rho);
    recs.push_back({vis, nl, u(), u(), rho, {0, 0, 0}});
  }
  for (float vis : {0.0f, 0.3f, 1.0f})
    for (float nl : {0.0f, 0.5f, 1.0f})
      for (float rho : {0.0f, 1e-4f, 10 * deg, 90 * deg})
        recs.push_back({vis, nl, 0.7f, 0.5f, rho, {0, 0, 0}});
  return recs;
}

// The ten outputs of the kernels, evaluated in C++ in scalar T at the same (float) inputs.
template <class T>
std::array<T, 10> cpu_outputs(const Rec& x) {
  const T vis = x.vis, nl = x.nl, nv = x.nv, r = x.r, rho = x.rho;
  const T th = micro_shadowing::cap_theta(nl), t = micro_shadowing::cone_angle(vis);
  return {micro_shadowing::reference_step_area_cap(vis, nl, rho),
          micro_shadowing::reference_step_area_cap_solid_angle(vis, nl, rho),
          micro_shadowing::reference_step_area_cap_oat_sander(vis, nl, rho),
          micro_shadowing::cap_cone_projected_solid_angle(rho, th, t),
          micro_shadowing::brinck_maximov_2016_area_cap(vis, nl, rho),
          micro_shadowing::chan_2018_area_cap(vis, nl, rho),
          micro_shadowing::part1_analytic_area_cap(vis, nl, rho),
          // The ALU fit is float code: in T = double only the area rule runs in double.
          micro_shadowing::area_cap_lambert(
              [&](T z) {
                return T(micro_shadowing::generic_vndf_alu(float(vis), float(z), float(nv), float(r)));
              },
              nl, rho, micro_shadowing::generic_vndf_kinks(vis, r)),
          micro_shadowing::cap_intersection_solid_angle(rho, t, th),
          micro_shadowing::cap_intersection_solid_angle_oat_sander(rho, t, th)};
}

}  // namespace cap

namespace shapes {

struct Rec {
  float q[4][4];
  float c[3], R, nd[3], vis;
};

inline Vec3d v3(const float* p) { return Vec3d(p[0], p[1], p[2]); }

inline std::vector<Rec> make_records() {
  std::vector<Rec> recs;
  Pcg32 rng(4242);
  auto u = [&] { return rng.next_double(); };
  const double deg = kPi<double> / 180;
  auto add = [&](const area::Quad& q, const area::Disk& d, double vis) {
    Rec r{};
    for (int k = 0; k < 4; ++k)
      for (int j = 0; j < 3; ++j) r.q[k][j] = float((&q.corners[size_t(k)].x)[j]);
    for (int j = 0; j < 3; ++j) r.c[j] = float((&d.center.x)[j]), r.nd[j] = float((&d.normal.x)[j]);
    r.R = float(d.radius), r.vis = float(vis);
    recs.push_back(r);
  };
  for (int i = 0; i < 4096; ++i) {
    const Vec3d c = spherical_direction(u(), 2 * kPi<double> * u());
    const double rho = (1 + 39 * u()) * deg, tilt = (120 * u() - 60) * deg, roll = 2 * kPi<double> * u();
    add(area::rect_tilted(c, rho, rho * (0.25 + 0.75 * u()), tilt, roll),
        area::disk_tilted(c, rho, tilt, roll), u());
  }
  // Degenerate: zero size (F = 0: the point value at the centre), a disk seen edge-on, the pole.
  const Vec3d c = spherical_direction(0.6, 0.3);
  add(area::Quad{{c, c, c, c}}, area::Disk{c, -1.0 * c, 0.0}, 0.5);
  add(area::rect_tilted(Vec3d(0, 0, 1), 0.2, 0.1), area::Disk{c, normalize(cross(c, Vec3d(0, 1, 0))), 0.5},
      0.3);
  return recs;
}

}  // namespace shapes

}  // namespace msh::test::area_inputs
