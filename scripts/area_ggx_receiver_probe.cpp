// Exploratory probe (docs/area-lights.md §5, "GGX receiver"): candidate fast forms for the reference step
// over a sphere light seen by a GGX receiver, against the exact GGX-weighted quadrature, at the first N
// points of verify area-lights' Sobol set (V, centre N·L ∈ [0, 1], ρ ∈ [1°, 40°], N·V ∈ [0.05, 1], roughness
// ∈ [0.1, 1], view azimuth ∈ [0, π]). Not part of the build:
//   g++ -std=c++20 -O2 -Iinclude scripts/area_ggx_receiver_probe.cpp -o /tmp/probe && /tmp/probe N [FIRST]
#include <microshadow/math/sampling.h>
#include <microshadow/occlusion/micro_shadowing_area.h>
#include <microshadow/reference/micro_shadowing_area_exact.h>

#include <cstdio>
#include <cstdlib>
#include <vector>

using namespace msh;
using namespace msh::micro_shadowing;

namespace {
// The point of the cap closest to r (Karis 2013, "Real Shading in Unreal Engine 4").
Vec3d closest(const Vec3d& c, double rho, const Vec3d& r) {
  if (std::acos(std::clamp(dot(c, r), -1.0, 1.0)) <= rho) return r;
  const Vec3d t = normalize(r - dot(r, c) * c, Vec3d(1, 0, 0));
  return std::cos(rho) * c + std::sin(rho) * t;
}
Vec3d toward(const Vec3d& c, const Vec3d& r, double ang) {
  const Vec3d t = normalize(r - dot(r, c) * c, Vec3d(1, 0, 0));
  return std::cos(ang) * c + std::sin(ang) * t;
}
}  // namespace

int main(int argc, char** argv) {
  const int N = argc > 1 ? std::atoi(argv[1]) : 300;
  const int first = argc > 2 ? std::atoi(argv[2]) : 0;  // first Sobol index (out-of-sample checks)
  struct Acc {
    const char* name;
    double k, ss = 0, mx = 0;
  };
  std::vector<Acc> acc = {{"Lambert closed form", 0}, {"representative point (Karis closest point)", 0}};
  for (double k : {0.5, 1.0, 2.0, 3.0}) acc.push_back({"cap ∩ lobe cone, beta = k·2 atan(0.64 α)", k});
  for (double k : {0.5, 2.0, 8.0}) acc.push_back({"Gaussian-product cap, lobe width k·α", k});
  for (double k : {-0.25, 0.1, 0.25, 1.0}) acc.push_back({"centroid shift k·ρ²/4·∇log w", k});
  // The lens of the cap and the lobe cone (beta = kk·2 atan(0.64 α)) along the great circle toward the mirror
  // direction, at least m·ρ wide (so a lobe that misses the light still weighs its near part); k = 10 kk + m.
  for (double kk : {2.0, 4.0})
    for (double m : {1.0, 1.25, 1.5, 1.75}) acc.push_back({"lens >= m rho wide, k = 10 kk + m", 10 * kk + m});
  for (int i = first; i < first + N; ++i) {
    const Vec2d p = sobol_2d<double>(uint32_t(i), 0x51u), q = sobol_2d<double>(uint32_t(i), 0x9e37u),
                s = sobol_2d<double>(uint32_t(i), 0x7f4au);
    const double V = p.x, nl = p.y, rho = (1 + 39 * q.x) * kPi<double> / 180, nv = std::max(0.05, q.y);
    const double a = roughness_to_alpha(std::max(0.1, s.x));
    const Vec3d v = spherical_direction(nv, s.y * kPi<double>), refl(-v.x, -v.y, v.z);
    const area::Cap cap{spherical_direction(nl, 0.0), rho};
    const area::Receiver rec = area::Receiver::ggx(a, v);
    const double ex = area::area_micro_shadowing_exact(cap, rec, area::reference_step_term(V), {1e-6});
    const double g = std::acos(std::clamp(dot(cap.center, refl), -1.0, 1.0));
    const Frame<double> fr = Frame<double>::from_z(cap.center);
    const double h = 1e-4;
    auto lw = [&](double x, double y) {
      return std::log(std::max(rec.weight(normalize(cap.center + x * fr.s + y * fr.t)), 1e-300));
    };
    const double gx = (lw(h, 0) - lw(-h, 0)) / (2 * h), gy = (lw(0, h) - lw(0, -h)) / (2 * h);
    for (Acc& A : acc) {
      double val;
      if (A.name[0] == 'L') {
        val = reference_step_area_cap(V, nl, rho);
      } else if (A.name[0] == 'r') {
        val = reference_step(V, closest(cap.center, rho, refl).z);
      } else if (A.name[0] == 'c' && A.name[1] == 'a') {
        const double beta = A.k * 2 * std::atan(0.64 * a);
        const double lo = std::max(-rho, g - beta), hi = std::min(rho, g + beta);
        if (!(hi > lo))
          val = reference_step(V, closest(cap.center, rho, refl).z);
        else
          val = reference_step_area_cap(V, toward(cap.center, refl, 0.5 * (lo + hi)).z,
                                        std::min(0.5 * (hi - lo), std::min(rho, beta)));
      } else if (A.name[0] == 'G') {
        const double sc = rho / std::sqrt(2.0), beta = A.k * a;
        const double sh = std::min(g * sc * sc / (sc * sc + beta * beta), rho);
        val = reference_step_area_cap(V, toward(cap.center, refl, sh).z,
                                      std::min(rho, std::sqrt(2.0) * sc * beta / std::hypot(sc, beta)));
      } else if (A.name[0] == 'l') {
        const double kk = std::floor(A.k / 10), m = A.k - 10 * kk;
        const double beta = kk * 2 * std::atan(0.64 * a);
        const double hi = std::min(rho, g + beta), lo = std::max(-rho, std::min(g - beta, hi - m * rho));
        val = reference_step_area_cap(V, toward(cap.center, refl, 0.5 * (lo + hi)).z,
                                      std::min(0.5 * (hi - lo), rho));
      } else {
        const double gl = std::hypot(gx, gy), sh = std::clamp(A.k * rho * rho / 4 * gl, -rho, rho);
        const Vec3d t = gl > 0 ? normalize(fr.s * gx + fr.t * gy) : fr.s;
        val = reference_step_area_cap(V, (std::cos(sh) * cap.center + std::sin(sh) * t).z, rho);
      }
      const double e = val - ex;
      A.ss += e * e, A.mx = std::max(A.mx, std::abs(e));
    }
  }
  for (const Acc& A : acc)
    std::printf("%-45s k = %5.2f: RMS %6.2f/255, max %6.1f/255\n", A.name, A.k, 255 * std::sqrt(A.ss / N),
                255 * A.mx);
}
