// The tail weight β of the cone-clipped LTC (bsdf/ltc_shading.h, w = D_ltc + β (n·l)/π) for the reference
// step over a sphere light seen by a GGX receiver (docs/area-lights.md §5, "GGX receiver: the cap forms are
// not enough"): β constant, β = k α^1.5 and β = k α, with the LTC table TABLE fetched bilinearly, against the
// exact GGX-weighted quadrature (probe_common.h):
//
//   build/bin/area_ggx_receiver_ltc_probe --ltc TABLE [--points N] [--first F] [--json]
//
// The docs' table: TABLE = `microshadow bake ltc --out ltc.dds` (64²), --points 300 (where β was chosen) and
// --points 2048 --first 300. β = 1.5 α^1.5 is ltc_tail_weight, what verify area-lights measures.
#include <microshadow/bsdf/ltc_shading.h>
#include <microshadow/bsdf/runtime/ltc_baker.h>
#include <microshadow/occlusion/micro_shadowing_area.h>

#include "probe_common.h"

int main(int argc, char** argv) {
  using namespace msh;
  using namespace msh::probes;
  CLI::App app{
      "The cone-clipped LTC's tail weight for the reference step over a sphere light, GGX receiver, "
      "against the exact GGX-weighted quadrature at verify area-lights' Sobol points "
      "(docs/area-lights.md §5).",
      "area_ggx_receiver_ltc_probe"};
  ProbeArgs a;
  std::string ltc;
  add_probe_options(app, a);
  app.add_option("--ltc", ltc, "LTC table (microshadow bake ltc)")->required();
  return run_probe(app, argc, argv, [&] {
    const bsdf::LtcTable table = bsdf::load_ltc_table(ltc);
    const std::vector<double> betas = {0, 0.001, 0.003, 0.01, 0.03, 0.1, 0.3, 1, 1e9}, ks = {0.3, 1, 1.5, 5};
    std::vector<std::string> forms;
    for (double b : betas) forms.push_back(fmt::format("beta = {:g}", b));
    for (double k : ks) forms.push_back(fmt::format("beta = {} alpha^1.5", k));
    for (double k : ks) forms.push_back(fmt::format("beta = {} alpha", k));
    print_rows(probe_rows(a, forms,
                          [&](const GgxCapInput& in) {
                            const bsdf::LtcCoeffs<double> k = table.fetch(in.roughness, in.n_dot_v);
                            const double ct = micro_shadowing::cone_cos_from_visibility(in.V);
                            std::vector<double> e;
                            auto add = [&](double beta) {
                              const auto lc = bsdf::ltc_light_cone_sphere(
                                  k.inv_m(), Vec3d(0, 0, 1), in.v, in.cap.center, std::sin(in.rho), beta);
                              e.push_back(bsdf::ltc_reference_step_area(lc, ct) - in.exact_step);
                            };
                            for (double b : betas) add(b);
                            for (double kk : ks) add(kk * in.alpha * std::sqrt(in.alpha));
                            for (double kk : ks) add(kk * in.alpha);
                            return e;
                          }),
               a, {{"ltc_table", ltc}});
  });
}
