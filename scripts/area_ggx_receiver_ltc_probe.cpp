// Exploratory probe (docs/area-lights.md §5, "GGX receiver"): the tail weight β of the cone-clipped LTC
// (bsdf/ltc_shading.h, w = D_ltc + β (n·l)/π) for the reference step over a sphere light seen by a GGX
// receiver, against the exact GGX-weighted quadrature, at verify area-lights' Sobol points (the same inputs
// as scripts/area_ggx_receiver_probe.cpp). β constant, β = k α^1.5 and β = k α. Not part of the build:
//   g++ -std=c++20 -O2 -Iinclude scripts/area_ggx_receiver_ltc_probe.cpp build/lib/libmicroshadow.a -ltbb
//       -lfmt -lOpenEXR-3_1 -lImath-3_1 -lIex-3_1 -lpng -lz -o /tmp/ltc_probe
//   /tmp/ltc_probe ltc.dds 300 0; /tmp/ltc_probe ltc.dds 2048 300     (ltc.dds: bake ltc --out ltc.dds)
#include <microshadow/bsdf/ltc_shading.h>
#include <microshadow/bsdf/runtime/ltc_baker.h>
#include <microshadow/math/sampling.h>
#include <microshadow/occlusion/micro_shadowing_area.h>
#include <microshadow/reference/micro_shadowing_area_exact.h>

#include <cstdio>
#include <cstdlib>
#include <vector>
using namespace msh;
using namespace msh::micro_shadowing;
int main(int argc, char** argv) {
  if (argc < 2) {
    std::fprintf(stderr, "usage: probe LTC_TABLE [N [FIRST]]\n");
    return 2;
  }
  const bsdf::LtcTable tab = bsdf::load_ltc_table(argv[1]);
  const int N = argc > 2 ? std::atoi(argv[2]) : 300;
  const int first = argc > 3 ? std::atoi(argv[3]) : 0;
  std::vector<double> betas = {0, 0.001, 0.003, 0.01, 0.03, 0.1, 0.3, 1, 1e9};
  std::vector<double> ks = {0.3, 1, 1.5, 5};
  std::vector<double> ss(betas.size() + 2 * ks.size()), mx(ss.size());
  for (int i = first; i < first + N; ++i) {
    const Vec2d p = sobol_2d<double>(uint32_t(i), 0x51u), q = sobol_2d<double>(uint32_t(i), 0x9e37u),
                s = sobol_2d<double>(uint32_t(i), 0x7f4au);
    const double V = p.x, nl = p.y, rho = (1 + 39 * q.x) * kPi<double> / 180, nv = std::max(0.05, q.y);
    const double r = std::max(0.1, s.x), a = roughness_to_alpha(r);
    const Vec3d v = spherical_direction(nv, s.y * kPi<double>), n(0, 0, 1);
    const area::Cap cap{spherical_direction(nl, 0.0), rho};
    const area::Receiver rec = area::Receiver::ggx(a, v);
    const double ex = area::area_micro_shadowing_exact(cap, rec, area::reference_step_term(V), {1e-6});
    const auto k = tab.fetch(r, nv);
    const double ct = cone_cos_from_visibility(V);
    size_t j = 0;
    auto acc = [&](double beta) {
      const auto lc = bsdf::ltc_light_cone_sphere(k.inv_m(), n, v, cap.center, std::sin(rho), beta);
      const double e = bsdf::ltc_reference_step_area(lc, ct) - ex;
      ss[j] += e * e, mx[j] = std::max(mx[j], std::abs(e));
      ++j;
    };
    for (double b : betas) acc(b);
    for (double kk : ks) acc(kk * a * std::sqrt(a));
    for (double kk : ks) acc(kk * a);
  }
  size_t j = 0;
  for (double b : betas)
    std::printf("beta %-10g RMS %.2f max %.1f\n", b, 255 * std::sqrt(ss[j] / N), 255 * mx[j]), ++j;
  for (double b : ks)
    std::printf("beta %g a^1.5 RMS %.2f max %.1f\n", b, 255 * std::sqrt(ss[j] / N), 255 * mx[j]), ++j;
  for (double b : ks)
    std::printf("beta %g a     RMS %.2f max %.1f\n", b, 255 * std::sqrt(ss[j] / N), 255 * mx[j]), ++j;
}
