// The inputs on which the bump-terminator functions of shaders/portable/bump_terminator.h are compared with
// the C++ library (tests/test_shaders_bump.cpp on Vulkan, tests/test_shader_portable_cpp.cpp compiled as
// C++), and the double-precision closed forms they are also compared with.
#pragma once

#include <microshadow/math/sampling.h>
#include <microshadow/math/vec.h>

#include <algorithm>
#include <cmath>
#include <vector>

namespace msh::test::bump_inputs {

struct Record {
  Vec3f ng, ns, l;
};
struct TriRecord {
  Vec3f p, p0, p1, p2, n0, n1, n2, b;
};

// Inputs: random configurations plus the exact cases (no perturbation, light along N_g, zero vectors).
inline std::vector<Record> make_records() {
  std::vector<Record> r;
  Pcg32 rng(77);
  for (int i = 0; i < 8192; ++i) {
    const Vec3d ng = sample_uniform_sphere(Vec2d(rng.next_double(), rng.next_double()));
    const Framed f = Framed::from_z(ng);
    const Vec3d ns = f.to_world(sample_uniform_cone(Vec2d(rng.next_double(), rng.next_double()), 0.05));
    const Vec3d l = sample_uniform_sphere(Vec2d(rng.next_double(), rng.next_double()));
    const double scale = std::exp(rng.next_double() * 4 - 2);  // not unit length
    r.push_back({Vec3f(ng), Vec3f(ns * scale), Vec3f(l)});
  }
  for (int i = 0; i < 256; ++i) {
    const Vec3f ng = Vec3f(sample_uniform_sphere(Vec2d(rng.next_double(), rng.next_double())));
    const Vec3f l = Vec3f(sample_uniform_sphere(Vec2d(rng.next_double(), rng.next_double())));
    const Vec3f ns = Vec3f(sample_uniform_sphere(Vec2d(rng.next_double(), rng.next_double())));
    r.push_back({ng, ng, l});       // no perturbation → exactly 1
    r.push_back({ng, ns, ng});      // light along N_g → Conty exactly 1
    r.push_back({ng, Vec3f(), l});  // zero shading normal → 1 (0 with the hemisphere test)
  }
  return r;
}

// Hanika offsets: random triangles, a point inside (its barycentrics b) and vertex normals of any length.
inline std::vector<TriRecord> make_tris() {
  std::vector<TriRecord> t;
  Pcg32 rng(78);
  for (int i = 0; i < 2048; ++i) {
    auto u = [&] { return Vec3f(sample_uniform_sphere(Vec2d(rng.next_double(), rng.next_double()))); };
    float a = float(rng.next_double()), b = float(rng.next_double());
    if (a + b > 1) a = 1 - a, b = 1 - b;
    const Vec3f p0 = u(), p1 = u(), p2 = u();
    const Vec3f bary(1 - a - b, a, b);
    const Vec3f p = p0 * bary.x + p1 * bary.y + p2 * bary.z;
    t.push_back({p, p0, p1, p2, u(), u() * 2.0f, u(), bary});
  }
  return t;
}

// Conty reference (listing 12.1) and Chiang closed form in double, on unit vectors.
inline double conty_ref(const Vec3d& ng, const Vec3d& ns, const Vec3d& l) {
  const double cos_d = std::min(std::abs(dot(ng, ns)), 1.0);
  const double alpha2 = std::clamp(0.125 * (1 - cos_d * cos_d) / (cos_d * cos_d), 0.0, 1.0);
  const double cos_i = std::max(std::abs(dot(ng, l)), 1e-6);
  return 2.0 / (1 + std::sqrt(1 + alpha2 * (1 - cos_i * cos_i) / (cos_i * cos_i)));
}
inline double chiang_ref(const Vec3d& ng, const Vec3d& ns, const Vec3d& l) {
  const double g = dot(ng, l) / (dot(ns, l) * dot(ng, ns));
  return g >= 1 ? 1 : (g < 0 ? 0 : -g * g * g + g * g + g);
}

}  // namespace msh::test::bump_inputs
