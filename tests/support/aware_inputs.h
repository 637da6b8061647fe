// The inputs on which the micro-BRDF-aware functions of shaders/portable/micro_shadowing_aware.h are compared
// with the C++ library (tests/test_shaders_micro_shadowing_aware.cpp on Vulkan,
// tests/test_shader_portable_cpp.cpp compiled as C++).
#pragma once

#include <microshadow/math/sampling.h>
#include <microshadow/math/vec.h>

#include <algorithm>
#include <cmath>
#include <vector>

#include "random_records.h"

namespace msh::test::aware_inputs {

struct Rec {
  float vis, alpha, nl, nv;
  Vec3f v;
  float cos_m;
  Vec3f l;
  float c;
};

inline Vec3f unit(double ct, double phi) {
  const double st = std::sqrt(std::max(0.0, 1 - ct * ct));
  return Vec3f(Vec3d(st * std::cos(phi), st * std::sin(phi), ct));
}

// 4096 random inputs (alpha in [0.01, 1], N.L and N.V in (0, 1], relative azimuth in [0, pi], cap fraction
// arguments over their domain) and the 6^3 grid of degenerate values (0, 1, outside [0, 1], tiny).
inline std::vector<Rec> make_records() {
  std::vector<Rec> r = random_records<Rec>(4096, 77, [](auto& u, int) {
    Rec x{};
    x.vis = float(u());
    x.alpha = float(sqr(0.1 + 0.9 * u()));
    x.nl = float(1 - u()), x.nv = float(1 - u());
    x.v = unit(x.nv, 0.0), x.l = unit(x.nl, kPi<double> * u());
    x.cos_m = float(2 * u() - 1), x.c = float(u());
    return x;
  });
  const float vals[] = {0.0f, 1.0f, -0.5f, 1.5f, 1e-7f, 0.5f};
  for (float a : vals)
    for (float b : vals)
      for (float c : vals) {
        Rec x{};
        x.vis = a, x.alpha = std::clamp(c, 0.0f, 1.0f), x.nl = b, x.nv = c;
        x.v = Vec3f(0, 0, 1), x.l = unit(std::clamp(b, -1.0f, 1.0f), 0.3);
        x.cos_m = b, x.c = c;
        r.push_back(x);
      }
  return r;
}

}  // namespace msh::test::aware_inputs
