// `eval microfacet`: D, Λ, G1 of one NDF at a direction, or the GGX directional albedo E(μ, α).
#include <fmt/format.h>
#include <microshadow/microfacet/albedo.h>
#include <microshadow/microfacet/beckmann.h>
#include <microshadow/microfacet/blinn_phong.h>
#include <microshadow/microfacet/ggx.h>
#include <microshadow/microfacet/gtr.h>

#include <optional>

#include "common.h"

namespace msh::cli {
namespace {

struct EvalMicrofacetArgs {
  std::string ndf = "ggx";
  double alpha = 0.5;
  std::optional<double> alpha_y;
  double gamma = 2.0;
  double ndotv = 1.0;
  double phi = 0.0;
  bool albedo = false;
  bool json = false;
};

template <class NDF>
nlohmann::json eval_ndf(const NDF& ndf, const Vec3d& v) {
  // D at the mirror-free pole and at m = v (the facet facing the viewer), Λ and G1 of v.
  return {
      {"D_normal", ndf.D(Vec3d(0, 0, 1))}, {"D_v", ndf.D(v)}, {"Lambda", ndf.Lambda(v)}, {"G1", ndf.G1(v)}};
}

void run(const EvalMicrofacetArgs& a) {
  require_range(a.ndotv, 0.0, 1.0, "--ndotv");
  require_range(a.alpha, 0.0, 4.0, "--alpha");
  if (a.alpha_y) require_range(*a.alpha_y, 0.0, 4.0, "--alpha-y");
  const double ay = a.alpha_y.value_or(a.alpha);
  nlohmann::json j = {{"ndf", a.ndf}, {"alpha", a.alpha}, {"ndotv", a.ndotv}};
  if (a.albedo) {
    if (a.ndf != "ggx") throw UsageError("--albedo is only available for --ndf ggx");
    if (a.alpha_y && *a.alpha_y != a.alpha)
      throw UsageError("--albedo needs an isotropic GGX (no --alpha-y)");
    j["E"] = ggx_directional_albedo(a.ndotv, a.alpha);
    j["source"] =
        "E(mu, alpha) = int D G2 / (4 mu) dl, F = 1, height-correlated Smith G2 (microfacet/albedo.h)";
  } else {
    const double s = std::sqrt(std::max(0.0, 1.0 - a.ndotv * a.ndotv));
    const Vec3d v(s * std::cos(a.phi), s * std::sin(a.phi), a.ndotv);
    j["phi"] = a.phi;
    if (a.ndf == "ggx") {
      j["alpha_y"] = ay;
      j.update(eval_ndf(GGX<double>(a.alpha, ay), v));
    } else if (a.ndf == "beckmann") {
      j["alpha_y"] = ay;
      const Beckmann<double> b(a.alpha, ay);
      j.update(eval_ndf(b, v));
      j["Lambda_approx"] = b.Lambda_approx(v);
    } else if (a.ndf == "blinn-phong") {
      if (a.alpha_y) throw UsageError("--alpha-y: Blinn-Phong is isotropic");
      // --alpha is the Beckmann-equivalent α; the exponent is αp = 2α⁻² − 2.
      const double ap = blinn_phong_exponent_from_beckmann(std::max(a.alpha, 1e-4));
      j["exponent"] = ap;
      j.update(eval_ndf(BlinnPhong<double>(ap), v));
    } else if (a.ndf == "gtr") {
      if (a.alpha_y) throw UsageError("--alpha-y: GTR is isotropic");
      require_range(a.gamma, 0.05, 20.0, "--gamma");
      j["gamma"] = a.gamma;
      j.update(eval_ndf(GTR<double>(a.alpha, a.gamma), v));
    } else {
      throw UsageError(fmt::format("--ndf must be one of ggx, beckmann, blinn-phong, gtr; got '{}'", a.ndf));
    }
  }
  if (a.json) {
    print_json(j);
    return;
  }
  for (auto it = j.begin(); it != j.end(); ++it) {
    if (it->is_number())
      fmt::print("{:<14} {:.9g}\n", it.key(), it->get<double>());
    else
      fmt::print("{:<14} {}\n", it.key(), it->is_string() ? it->get<std::string>() : it->dump());
  }
}

void add_microfacet(Groups& g) {
  const auto [c, args] = add_command<EvalMicrofacetArgs>(
      g.eval, "microfacet",
      "Evaluate an NDF's D, Smith Lambda and G1 at a view direction, or the GGX albedo E(mu, alpha)", run);
  c->add_option("--ndf", args->ndf, "ggx | beckmann | blinn-phong | gtr")->capture_default_str();
  c->add_option("--alpha", args->alpha,
                "roughness alpha (alpha_x if anisotropic; Beckmann-equivalent for blinn-phong)")
      ->check(Finite)
      ->capture_default_str();
  c->add_option("--alpha-y", args->alpha_y, "alpha_y (anisotropic ggx/beckmann)")->check(Finite);
  c->add_option("--gamma", args->gamma, "GTR tail exponent gamma (2 = GGX)")
      ->check(Finite)
      ->capture_default_str();
  c->add_option("--ndotv", args->ndotv, "cos(theta_v) in [0, 1]")->check(Finite)->capture_default_str();
  c->add_option("--phi", args->phi, "azimuth of v in radians (anisotropic NDFs)")
      ->check(Finite)
      ->capture_default_str();
  c->add_flag("--albedo", args->albedo, "print the GGX directional albedo E(ndotv, alpha) instead (F = 1)");
  add_json_flag(c, args->json);
}

}  // namespace

MSH_CLI_REGISTER(add_microfacet, 10);

}  // namespace msh::cli
