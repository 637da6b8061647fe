// Candidate cap forms for the reference step over a sphere light seen by a GGX receiver (docs/area-lights.md
// §5, "GGX receiver: the cap forms are not enough"): each candidate evaluates a Lambertian cap form of
// occlusion/micro_shadowing_area.h at a cap (or a point) derived from the light and the receiver's lobe about
// the mirror direction, against the exact GGX-weighted quadrature (probe_common.h):
//
//   build/bin/area_ggx_receiver_probe [--points N] [--first F] [--json]
//
// The docs' table: --points 300 (where the parameters were chosen) and --points 2048 --first 300.
#include <microshadow/occlusion/micro_shadowing_area.h>

#include <functional>
#include <string>
#include <vector>

#include "probe_common.h"

namespace msh::probes {
namespace {

using micro_shadowing::reference_step;
using micro_shadowing::reference_step_area_cap;

// The point of the cap closest to r (Karis 2013, "Real Shading in Unreal Engine 4").
Vec3d closest(const Vec3d& c, double rho, const Vec3d& r) {
  if (std::acos(std::clamp(dot(c, r), -1.0, 1.0)) <= rho) return r;
  const Vec3d t = normalize(r - dot(r, c) * c, Vec3d(1, 0, 0));
  return std::cos(rho) * c + std::sin(rho) * t;
}

// The direction at angle `ang` from c on the great circle toward r.
Vec3d toward(const Vec3d& c, const Vec3d& r, double ang) {
  const Vec3d t = normalize(r - dot(r, c) * c, Vec3d(1, 0, 0));
  return std::cos(ang) * c + std::sin(ang) * t;
}

// What the candidates use of a point: the mirror direction, its angle g from the light's centre, and the
// gradient (gx, gy) of log f(v, l) at the centre in the frame fr of the centre (central differences).
struct Lobe {
  Vec3d refl;
  double g, gx, gy;
  Frame<double> fr;
};
Lobe lobe_at(const GgxCapInput& in) {
  Lobe b;
  const Vec3d& c = in.cap.center;
  b.refl = Vec3d(-in.v.x, -in.v.y, in.v.z);
  b.g = std::acos(std::clamp(dot(c, b.refl), -1.0, 1.0));
  b.fr = Frame<double>::from_z(c);
  const double h = 1e-4;
  auto lw = [&](double x, double y) {
    return std::log(std::max(in.receiver.weight(normalize(c + x * b.fr.s + y * b.fr.t)), 1e-300));
  };
  b.gx = (lw(h, 0) - lw(-h, 0)) / (2 * h), b.gy = (lw(0, h) - lw(0, -h)) / (2 * h);
  return b;
}

// The lobe's cone about the mirror direction: half-angle k·2 atan(0.64 α).
double lobe_cone(double k, double alpha) { return k * 2 * std::atan(0.64 * alpha); }

struct Candidate {
  std::string form;
  std::function<double(const GgxCapInput&, const Lobe&)> value;
};

std::vector<Candidate> candidates() {
  std::vector<Candidate> cs;
  cs.push_back({"Lambert closed form", [](const GgxCapInput& in, const Lobe&) {
                  return reference_step_area_cap(in.V, in.n_dot_l, in.rho);
                }});
  cs.push_back({"representative point (Karis 2013 closest point to the mirror ray)",
                [](const GgxCapInput& in, const Lobe& b) {
                  return reference_step(in.V, closest(in.cap.center, in.rho, b.refl).z);
                }});
  // The cap ∩ the lobe's cone along the great circle toward the mirror direction, as a cap; the closest point
  // when they do not meet.
  for (double k : {0.5, 1.0, 2.0, 3.0})
    cs.push_back({fmt::format("cap ∩ lobe cone beta = k 2 atan(0.64 alpha), as a cap, k = {}", k),
                  [k](const GgxCapInput& in, const Lobe& b) {
                    const double beta = lobe_cone(k, in.alpha);
                    const double lo = std::max(-in.rho, b.g - beta), hi = std::min(in.rho, b.g + beta);
                    if (!(hi > lo)) return reference_step(in.V, closest(in.cap.center, in.rho, b.refl).z);
                    return reference_step_area_cap(in.V, toward(in.cap.center, b.refl, 0.5 * (lo + hi)).z,
                                                   std::min(0.5 * (hi - lo), std::min(in.rho, beta)));
                  }});
  // The product of two Gaussians about the centre (width ρ/√2) and the mirror direction (width k·α), as a
  // cap.
  for (double k : {0.5, 2.0, 8.0})
    cs.push_back({fmt::format("Gaussian product of cap and lobe, lobe width k alpha, k = {}", k),
                  [k](const GgxCapInput& in, const Lobe& b) {
                    const double sc = in.rho / std::sqrt(2.0), beta = k * in.alpha;
                    const double sh = std::min(b.g * sc * sc / (sc * sc + beta * beta), in.rho);
                    return reference_step_area_cap(
                        in.V, toward(in.cap.center, b.refl, sh).z,
                        std::min(in.rho, std::sqrt(2.0) * sc * beta / std::hypot(sc, beta)));
                  }});
  // The cap's centroid under the weight, to first order: shifted by k ρ²/4 ∇log f.
  for (double k : {-0.25, 0.1, 0.25, 1.0})
    cs.push_back({fmt::format("cap centroid shifted by k rho^2/4 grad log f, k = {}", k),
                  [k](const GgxCapInput& in, const Lobe& b) {
                    const double gl = std::hypot(b.gx, b.gy),
                                 sh = std::clamp(k * in.rho * in.rho / 4 * gl, -in.rho, in.rho);
                    const Vec3d t = gl > 0 ? normalize(b.fr.s * b.gx + b.fr.t * b.gy) : b.fr.s;
                    return reference_step_area_cap(in.V, (std::cos(sh) * in.cap.center + std::sin(sh) * t).z,
                                                   in.rho);
                  }});
  // The lens of the cap and the lobe cone along the great circle toward the mirror direction, kept at least
  // m·ρ wide (so a lobe that misses the light still weighs its near part).
  for (double k : {2.0, 4.0})
    for (double m : {1.0, 1.25, 1.5, 1.75})
      cs.push_back({fmt::format("lens of cap and lobe cone (k = {}), at least m rho wide, m = {}", k, m),
                    [k, m](const GgxCapInput& in, const Lobe& b) {
                      const double beta = lobe_cone(k, in.alpha);
                      const double hi = std::min(in.rho, b.g + beta),
                                   lo = std::max(-in.rho, std::min(b.g - beta, hi - m * in.rho));
                      return reference_step_area_cap(in.V, toward(in.cap.center, b.refl, 0.5 * (lo + hi)).z,
                                                     std::min(0.5 * (hi - lo), in.rho));
                    }});
  return cs;
}

}  // namespace
}  // namespace msh::probes

int main(int argc, char** argv) {
  using namespace msh::probes;
  CLI::App app{
      "Candidate cap forms for the reference step over a sphere light, GGX receiver, against the exact "
      "GGX-weighted quadrature at verify area-lights' Sobol points (docs/area-lights.md §5).",
      "area_ggx_receiver_probe"};
  ProbeArgs a;
  add_probe_options(app, a);
  return run_probe(app, argc, argv, [&] {
    const std::vector<Candidate> cs = candidates();
    std::vector<std::string> forms;
    for (const Candidate& c : cs) forms.push_back(c.form);
    print_rows(probe_rows(a, forms,
                          [&](const GgxCapInput& in) {
                            const Lobe b = lobe_at(in);
                            std::vector<double> e;
                            for (const Candidate& c : cs) e.push_back(c.value(in, b) - in.exact_step);
                            return e;
                          }),
               a);
  });
}
