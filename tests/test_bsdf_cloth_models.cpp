// Every model of extra_brdf_models() (cloth, thin film, clear coat) through the runtime interface: white
// furnace (directional albedo ≤ 1 wherever energy_conserving() is claimed, over a grid of parameters),
// Helmholtz reciprocity where claimed, non-negativity and finiteness, and the importance sampler against its
// own pdf (chi-square).
#include <gtest/gtest.h>
#include <microshadow/bsdf/runtime/brdf_model.h>
#include <microshadow/math/sampling.h>

#include "support/brdf_checks.h"
#include "support/chi2.h"

using namespace msh;
using namespace msh::bsdf;

namespace {

// Parameter grid: defaults, each parameter alone at lo and at hi, and 6 random combinations.
std::vector<BrdfParams> param_grid(const ModelInfo& info) {
  std::vector<BrdfParams> out;
  out.push_back(complete_params(info, {}));
  for (const auto& p : info.params)
    for (double v : {p.lo, p.hi}) {
      BrdfParams g;
      g.values[p.name] = std::vector<double>(size_t(p.components), v);
      out.push_back(complete_params(info, g));
    }
  Pcg32 rng(1234);
  for (int k = 0; k < 6; ++k) {
    BrdfParams g;
    for (const auto& p : info.params) {
      std::vector<double> v;
      for (int c = 0; c < p.components; ++c) v.push_back(p.lo + (p.hi - p.lo) * rng.next_double());
      if (p.name == "coat-normal") v = {v[0] * 0.5, v[1] * 0.5, 1.0};  // mostly upward coat normals
      g.values[p.name] = v;
    }
    out.push_back(complete_params(info, g));
  }
  return out;
}

std::string describe(const BrdfParams& p) {
  std::string s;
  for (const auto& [k, v] : p.values) {
    s += k + "=";
    for (double x : v) s += std::to_string(x) + ",";
    s += " ";
  }
  return s;
}

struct Albedo {
  Rgbd mean;
  double se;  // standard error of the max-channel estimate
};

// E(wo) = ∫ f cos dω by the model's own importance sampler (validated separately by chi-square).
Albedo albedo(const BrdfModel& m, const Vec3d& wo, int n) {
  Rgbd s(0);
  double s2 = 0;
  for (int i = 0; i < n; ++i) {
    const auto smp = m.sample(wo, sobol_2d<double>(uint32_t(i), 77));
    if (!smp) continue;
    const Rgbd w = smp->f * (smp->wi.z / smp->pdf);
    s += w;
    s2 += sqr(max_component(w));
  }
  const Rgbd mean = s / double(n);
  const double mm = max_component(mean);
  return {mean, std::sqrt(std::max(0.0, s2 / n - mm * mm) / n)};
}

}  // namespace

TEST(ExtraModels, Registered) {
  const auto models = extra_brdf_models();
  EXPECT_EQ(models.size(), 8u);
  for (const auto& m : models) {
    EXPECT_FALSE(m.source.empty()) << m.name;
    EXPECT_NO_THROW(find_brdf_model(m.name));
  }
}

TEST(ExtraModels, WhiteFurnaceAlbedoAtMostOne) {
  for (const auto& info : extra_brdf_models()) {
    double worst = 0;
    for (const auto& params : param_grid(info)) {
      const auto model = info.make(params);
      for (double mu : {1.0, 0.6, 0.2, 0.05}) {
        const Vec3d wo = spherical_direction(mu, 0.3);
        const Albedo a = albedo(*model, wo, 8192);
        ASSERT_TRUE(is_finite(a.mean)) << info.name << " " << describe(params);
        EXPECT_GE(min_component(a.mean), 0.0) << info.name;
        worst = std::max(worst, max_component(a.mean));
        if (model->energy_conserving()) {
          EXPECT_LE(max_component(a.mean), 1.0 + 4 * a.se + 2e-3)
              << info.name << " mu " << mu << " se " << a.se << " " << describe(params);
        }
      }
    }
    std::printf("[furnace] %-18s max albedo over grid %.4f (%s)\n", info.name.c_str(), worst,
                info.make(complete_params(info, {}))->energy_conserving() ? "claims <= 1" : "no claim");
  }
}

TEST(ExtraModels, ReciprocityNonNegativityFinite) {
  Pcg32 rng(99);
  for (const auto& info : extra_brdf_models()) {
    for (const auto& params : param_grid(info)) {
      const auto model = info.make(params);
      for (int i = 0; i < 200; ++i) {
        const Vec3d a = sample_uniform_sphere(Vec2d(rng.next_double(), rng.next_double()));
        const Vec3d b = sample_uniform_sphere(Vec2d(rng.next_double(), rng.next_double()));
        const Rgbd fab = test::expect_sane_pair(*model, a, b, info.name + " " + describe(params));
        if (!(a.z > 0 && b.z > 0)) {
          EXPECT_EQ(max_component(fab), 0.0) << info.name << " below the horizon";
        }
      }
      // Degenerate directions.
      for (const Vec3d& d : {Vec3d(0, 0, 1), Vec3d(1, 0, 0), Vec3d(0, 0, 0), Vec3d(0, 1e-9, 1)}) {
        EXPECT_TRUE(is_finite(model->f(d, Vec3d(0, 0, 1)))) << info.name;
        EXPECT_TRUE(is_finite(model->f(Vec3d(0, 0, 1), d))) << info.name;
        EXPECT_TRUE(std::isfinite(model->pdf(d, Vec3d(0, 0, 1))));
      }
    }
  }
}

TEST(ExtraModels, SamplersChiSquare) {
  // Moderately rough settings: the (cos θ, φ) grid must resolve the lobes.
  std::vector<std::pair<std::string, BrdfParams>> cases;
  for (const auto& info : extra_brdf_models()) cases.push_back({info.name, {}});
  BrdfParams cc;
  cc.values = {{"coat-roughness", {0.6}},
               {"metallic", {0.5}},
               {"base-roughness", {0.5}},
               {"coat-normal", {0.3, 0.1, 1}}};
  cases.push_back({"clearcoat", cc});
  BrdfParams tf;
  tf.values = {{"roughness", {0.6}}};
  cases.push_back({"thin-film", tf});
  BrdfParams sh;
  sh.values = {{"roughness", {0.3}}};
  cases.push_back({"imageworks-sheen", sh});
  const int runs = int(cases.size()) * 3;
  for (const auto& [name, given] : cases) {
    const ModelInfo& info = find_brdf_model(name);
    auto params = given;
    if (name == "clearcoat" && given.values.empty()) params.values["coat-roughness"] = {0.5};
    if (name == "thin-film" && given.values.empty()) params.values["roughness"] = {0.5};
    const auto model = info.make(complete_params(info, params));
    for (double mu : {0.9, 0.5, 0.15}) {
      const Vec3d wo = spherical_direction(mu, 0.7);
      const auto r = test::chi2_test_directions(
          [&](uint32_t i) -> std::optional<Vec3d> {
            Pcg32 rng(i, 0xc0ffee);
            const double u0 = rng.next_double();
            const auto s = model->sample(wo, Vec2d(u0, rng.next_double()));
            if (!s) return std::nullopt;
            return s->wi;
          },
          [&](const Vec3d& wi) { return model->pdf(wo, wi); }, 200000, 40, 80, 0.01, runs);
      EXPECT_TRUE(r.pass) << name << " mu " << mu << " p " << r.p_value << " " << describe(params) << "\n"
                          << r.table;
    }
  }
}
