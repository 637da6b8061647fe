// The method table (occlusion/runtime/micro_shadowing_methods.h): every entry evaluates the function it names
// (compared with a direct call of the core header at random inputs), options that do not apply are refused,
// inputs outside the domain throw InputError, and eval is deterministic across threads.
#include <gtest/gtest.h>
#include <microshadow/io/error.h>
#include <microshadow/lut/runtime/micro_shadowing_analysis.h>
#include <microshadow/lut/runtime/micro_shadowing_loader.h>
#include <microshadow/math/sampling.h>
#include <microshadow/occlusion/directional.h>
#include <microshadow/occlusion/micro_shadowing_fit.h>
#include <microshadow/occlusion/runtime/micro_shadowing_methods.h>
#include <microshadow/reference/micro_shadowing_exact.h>

#include <algorithm>
#include <cmath>
#include <set>
#include <thread>

namespace msh::occlusion {
namespace {

TEST(MicroShadowingMethods, NamesAreUniqueAndFindable) {
  std::set<std::string> seen;
  for (const auto& m : micro_shadowing_methods()) {
    EXPECT_TRUE(seen.insert(m.name).second) << m.name;
    EXPECT_EQ(find_micro_shadowing_method(m.name), &m);
    EXPECT_FALSE(m.summary.empty()) << m.name;
  }
  EXPECT_GE(seen.size(), 9u);
  EXPECT_EQ(find_micro_shadowing_method("nope"), nullptr);
}

// What docs/choosing.md derives from the registry (scripts/guide.py): every study method says when to use it;
// a method reads V unless it is none or a per-texel term (which names the command that bakes its channels);
// a pair reads what its terms read.
TEST(MicroShadowingMethods, GuideFactsAreInTheRegistry) {
  for (const auto& m : micro_shadowing_methods()) {
    if (m.in_study) {
      EXPECT_FALSE(m.use.empty()) << m.name;
    }
    if (m.is_pair()) {
      const auto *d = find_micro_shadowing_method(m.diffuse), *s = find_micro_shadowing_method(m.specular);
      EXPECT_EQ(m.uses_visibility, d->uses_visibility || s->uses_visibility) << m.name;
      EXPECT_EQ(m.texel_bake, d->needs_texel ? d->texel_bake : s->texel_bake) << m.name;
      continue;
    }
    EXPECT_EQ(m.uses_visibility, m.name != "none" && !m.needs_texel) << m.name;
    EXPECT_EQ(m.texel_bake.empty(), !m.needs_texel) << m.name;
  }
  EXPECT_EQ(find_micro_shadowing_method("directional")->texel_bake, "gen-material");
  EXPECT_EQ(find_micro_shadowing_method("directional-view")->texel_bake, "gen-material --directional-view");
}

TEST(MicroShadowingMethods, EachEntryEvaluatesItsFunction) {
  const MicroShadowingEvaluator ao("ao"), step("reference"), bm("brinck-maximov-2016"), chan("chan-2018"),
      p1("part1-analytic"), gen("generic-vndf"), alu("generic-vndf-alu"), l3("lut3d"), l2("lut2d");
  const auto table = lut::default_micro_shadowing_lut(false);
  const auto table2 = lut::default_micro_shadowing_lut(true);
  Pcg32 rng(7);
  for (int i = 0; i < 40; ++i) {
    const double V = rng.next_double(), nl = rng.next_double(), nv = 0.05 + 0.95 * rng.next_double(),
                 r = 0.1 + 0.9 * rng.next_double(), phi = kPi<double> * rng.next_double();
    MicroShadowingQuery q{V, nl, nv, r, std::nullopt, std::nullopt};
    EXPECT_EQ(ao.eval(q), V);
    EXPECT_EQ(step.eval(q), micro_shadowing::reference_step(V, nl));
    EXPECT_EQ(bm.eval(q), micro_shadowing::brinck_maximov_2016(V, nl));
    EXPECT_EQ(chan.eval(q), micro_shadowing::chan_2018(V, nl));
    EXPECT_EQ(p1.eval(q), micro_shadowing::part1_analytic(V, nl));
    EXPECT_EQ(alu.eval(q),
              double(micro_shadowing::generic_vndf_alu(float(V), float(nl), float(nv), float(r))));
    const double a = r * r;
    EXPECT_EQ(gen.eval(q), micro_shadowing::generic_vndf_exact_azimuth_mean(V, a, nl, nv));
    EXPECT_EQ(l3.eval(q), lut::sample_micro_shadowing(table->view(), V, nl, nv, r));
    EXPECT_EQ(l2.eval(q), lut::sample_micro_shadowing(table2->view(), V, nl, 1.0, r));
    q.phi = phi;
    EXPECT_EQ(gen.eval(q), micro_shadowing::generic_vndf_exact(V, a, a, lut::study_view_dir(nv),
                                                               lut::study_light_dir(nl, phi)));
    q.roughness_y = 0.3;
    EXPECT_EQ(gen.eval(q), micro_shadowing::generic_vndf_exact(V, a, 0.09, lut::study_view_dir(nv),
                                                               lut::study_light_dir(nl, phi)));
  }
}

TEST(MicroShadowingMethods, EstimatorConvergesToExact) {
  const MicroShadowingEvaluator est("generic-vndf", {4096, 3, micro_shadowing::G2Form::HeightCorrelated, ""});
  const MicroShadowingEvaluator exact("generic-vndf");
  for (double V : {0.3, 0.7}) {
    MicroShadowingQuery q{V, 0.5, 0.6, 0.5, 1.0, std::nullopt};
    // 4096 Owen-scrambled Sobol samples: the measured spread of such estimates is < 0.01.
    EXPECT_NEAR(est.eval(q), exact.eval(q), 0.02) << V;
  }
}

TEST(MicroShadowingMethods, RefusesWhatDoesNotApply) {
  EXPECT_THROW(MicroShadowingEvaluator("unknown"), InputError);
  EXPECT_THROW(MicroShadowingEvaluator("chan-2018", {16, 1, micro_shadowing::G2Form::HeightCorrelated, ""}),
               InputError);
  EXPECT_THROW(
      MicroShadowingEvaluator("chan-2018", {0, 1, micro_shadowing::G2Form::HeightCorrelated, "x.dds"}),
      InputError);
  EXPECT_THROW(
      MicroShadowingEvaluator("lut3d", {0, 1, micro_shadowing::G2Form::HeightCorrelated, "/nonexistent.dds"}),
      InputError);
  const MicroShadowingEvaluator chan("chan-2018"), l3("lut3d"), gen("generic-vndf");
  EXPECT_THROW(chan.eval({0.5, 0.5, 1, 0.5, 1.0, std::nullopt}), InputError);  // φ
  EXPECT_THROW(l3.eval({0.5, 0.5, 1, 0.5, std::nullopt, 0.3}), InputError);    // anisotropic
  EXPECT_THROW(gen.eval({0.5, 0.5, 1, 0.5, 4.0, std::nullopt}), InputError);   // φ > π
  for (double bad : {-0.1, 1.1, std::nan("")}) {
    EXPECT_THROW(chan.eval({bad, 0.5, 1, 0.5, std::nullopt, std::nullopt}), InputError);
    EXPECT_THROW(chan.eval({0.5, bad, 1, 0.5, std::nullopt, std::nullopt}), InputError);
    EXPECT_THROW(gen.eval({0.5, 0.5, bad, 0.5, std::nullopt, std::nullopt}), InputError);
    EXPECT_THROW(gen.eval({0.5, 0.5, 1, bad, std::nullopt, std::nullopt}), InputError);
  }
}

// A pair is its two terms, one per lobe; eval() refuses it (it has no single value), eval_lobes() gives the
// parts' own values, and the options reach only the part that takes them.
TEST(MicroShadowingMethods, PairsAreTheirTwoTerms) {
  int pairs = 0;
  for (const auto& m : micro_shadowing_methods()) {
    if (!m.is_pair()) continue;
    ++pairs;
    if (m.needs_texel) continue;  // evaluated by the renderer only (MicroShadowingTexelTerms below)
    EXPECT_EQ(m.name, m.diffuse + "+" + m.specular);
    const MicroShadowingMethodInfo *d = find_micro_shadowing_method(m.diffuse),
                                   *s = find_micro_shadowing_method(m.specular);
    ASSERT_TRUE(d && s) << m.name;
    EXPECT_FALSE(d->is_pair() || s->is_pair()) << m.name;
    EXPECT_EQ(m.accepts_samples, d->accepts_samples || s->accepts_samples) << m.name;
    const MicroShadowingEvaluator pe(m.name), de(m.diffuse), se(m.specular);
    const MicroShadowingQuery q{0.7, 0.6, 0.8, 0.5, std::nullopt, std::nullopt};
    EXPECT_THROW(pe.eval(q), InputError) << m.name;
    const auto [vd, vs] = pe.eval_lobes(q);
    EXPECT_EQ(vd, de.eval(q)) << m.name;
    EXPECT_EQ(vs, se.eval(q)) << m.name;
    if (m.accepts_samples) {
      MicroShadowingOptions o;
      o.samples = 64;
      EXPECT_NO_THROW(MicroShadowingEvaluator(m.name, o)) << m.name;
    }
  }
  EXPECT_GE(pairs, 5);
  // The recommended pair (docs/micro-shadowing-aware.md) is in the study.
  EXPECT_TRUE(find_micro_shadowing_method("diffuse-aware-alu+lut3d")->in_study);
  EXPECT_TRUE(find_micro_shadowing_method("diffuse-aware-alu+generic-vndf-alu")->in_study);
}

// The renderer's per-light form (shade, float, at full vectors) against eval (double): equal for the terms of
// (V, N·L, N·V) at any azimuth; the estimators converge to the exact term at the azimuth; the
// azimuth-dependent indicators at their direction; every method finite at degenerate inputs.
TEST(MicroShadowingMethods, ShadeAgreesWithEval) {
  Pcg32 rng(11);
  for (const auto& m : micro_shadowing_methods()) {
    if (m.needs_texel) continue;  // MicroShadowingTexelTerms
    MicroShadowingOptions o;
    if (m.accepts_samples) o.samples = 4096;
    const MicroShadowingEvaluator e(m.name, o);
    MicroShadowingOptions exact_o;
    const MicroShadowingEvaluator exact(m.name, exact_o);
    if (m.is_pair()) {
      // Each lobe is its term's own per-light value (the terms are checked below, on their own).
      const auto part = [&](const std::string& name) {
        MicroShadowingOptions po;
        if (find_micro_shadowing_method(name)->accepts_samples) po.samples = o.samples;
        return MicroShadowingEvaluator(name, po);
      };
      const MicroShadowingEvaluator d = part(m.diffuse), sp = part(m.specular);
      MicroShadowingShadeInput in;
      in.visibility = 0.8f, in.roughness = 0.4f, in.v = Vec3f(0.6f, 0, 0.8f), in.l = Vec3f(0, 0.6f, 0.8f);
      EXPECT_EQ(e.shade(in).diffuse, d.shade(in).diffuse) << m.name;
      EXPECT_EQ(e.shade(in).specular, sp.shade(in).specular) << m.name;
      continue;
    }
    double worst = 0;
    for (int i = 0; i < 12; ++i) {
      const double V = rng.next_double(), nl = 0.02 + 0.97 * rng.next_double(),
                   nv = 0.05 + 0.94 * rng.next_double(), r = 0.15 + 0.85 * rng.next_double(),
                   phi = kPi<double> * rng.next_double();
      MicroShadowingShadeInput in;
      in.visibility = float(V), in.roughness = float(r);
      in.v = Vec3f(lut::study_view_dir(nv));
      in.l = Vec3f(lut::study_light_dir(nl, phi));
      in.seed = 2 * uint32_t(i) + 1;
      const MicroShadowingLobes t = e.shade(in);
      MicroShadowingQuery q{V, nl, nv, r, std::nullopt, std::nullopt};
      // Methods whose shade reads the full vectors: compare at the azimuth (an estimator: with its noise).
      const bool at_phi = m.accepts_phi && m.name.rfind("lut", 0) != 0;
      if (at_phi) q.phi = phi;
      const auto [d, s] = exact.eval_lobes(q);
      worst = std::max({worst, std::abs(t.diffuse - d), std::abs(t.specular - s)});
    }
    // Closed forms, fits and tables: float rounding; estimators (4096 samples): Monte Carlo noise.
    EXPECT_LT(worst, m.accepts_samples ? 0.05 : 2e-5) << m.name;
    for (const Vec3f& l : {Vec3f(1, 0, 0), Vec3f(0, 0, 1), Vec3f(0.6f, 0.8f, 0.0f)}) {
      MicroShadowingShadeInput in;
      in.visibility = 0.5f, in.roughness = 0.0f, in.v = Vec3f(0, 0, 1), in.l = l;
      const MicroShadowingLobes t = e.shade(in);
      EXPECT_TRUE(std::isfinite(t.diffuse) && std::isfinite(t.specular)) << m.name;
      EXPECT_TRUE(t.diffuse >= 0 && t.diffuse <= 1 && t.specular >= 0 && t.specular <= 1) << m.name;
    }
  }
}

// The methods that read per-texel channels: eval at one point refuses them (there is no texel), shade reads
// the channels: the flat surface's channels (transport = l.z) give 1 for the directional term, the pair
// puts it on the diffuse lobe only.
TEST(MicroShadowingTexelTerms, DirectionalReadsItsChannels) {
  const MicroShadowingEvaluator d("directional"), p("directional+generic-vndf-alu"), g("generic-vndf-alu");
  EXPECT_TRUE(d.info().needs_texel && p.info().needs_texel);
  EXPECT_EQ(d.info().texel_channels, 9);
  EXPECT_THROW(d.eval(MicroShadowingQuery{0.5, 0.5, 1, 0.5, std::nullopt, std::nullopt}), InputError);
  // Flat: f(l) = l.z, i.e. the channel of z is 1 and every other 0.
  const float flat[9] = {0, 0, 0, 1, 0, 0, 0, 0, 0};
  MicroShadowingShadeInput in;
  in.visibility = 0.6f, in.roughness = 0.5f, in.texel = flat, in.texel_channels = 9;
  for (float e : {0.1f, 0.5f, 1.2f}) {
    in.l = in.l_tangent = Vec3f(std::cos(e), 0, std::sin(e));
    in.v = Vec3f(0, 0.6f, 0.8f);
    EXPECT_NEAR(d.shade(in).diffuse, 1.0f, 1e-6f) << e;
    EXPECT_NEAR(p.shade(in).diffuse, 1.0f, 1e-6f) << e;
    EXPECT_EQ(p.shade(in).specular, g.shade(in).specular) << e;
  }
  // Below the horizon: no light.
  in.l = in.l_tangent = Vec3f(1, 0, -0.1f);
  EXPECT_EQ(d.shade(in).diffuse, 0.0f);
}

// directional-view: 21 channels; the flat surface's channels give 1 whatever the view, and any channels give
// the core directional_view_term (v in tangent space); fewer channels than it reads: no term (1), as the
// renderer refuses such a material before shading.
TEST(MicroShadowingTexelTerms, DirectionalViewReadsItsChannelsAndTheView) {
  const MicroShadowingEvaluator d("directional-view"), p("directional-view+generic-vndf-alu");
  EXPECT_TRUE(d.info().needs_texel && p.info().needs_texel);
  EXPECT_EQ(d.info().texel_channels, 21);
  EXPECT_EQ(p.info().texel_channels, 21);
  EXPECT_THROW(d.eval(MicroShadowingQuery{0.5, 0.5, 1, 0.5, std::nullopt, std::nullopt}), InputError);
  float c[21] = {};
  c[3] = 1;
  MicroShadowingShadeInput in;
  in.texel = c, in.texel_channels = 21;
  in.l = in.l_tangent = normalize(Vec3f(0.6f, 0.2f, 0.5f));
  in.v_tangent = normalize(Vec3f(-0.7f, 0.3f, 0.4f));
  EXPECT_NEAR(d.shade(in).diffuse, 1.0f, 1e-6f);
  Pcg32 rng(5);
  const auto u = [&] { return rng.next_float() - 0.5f; };
  for (int t = 0; t < 50; ++t) {
    for (float& x : c) x = u();
    c[0] += 0.5f;
    in.l_tangent = normalize(Vec3f(u(), u(), u() + 0.5f));
    in.v_tangent = normalize(Vec3f(u(), u(), u() + 0.5f));
    in.n_tangent = normalize(Vec3f(0.4f * u(), 0.4f * u(), 1));
    EXPECT_EQ(d.shade(in).diffuse,
              directional::directional_view_term(c, in.l_tangent, in.v_tangent, in.n_tangent));
    EXPECT_EQ(p.shade(in).diffuse, d.shade(in).diffuse);
  }
  in.texel_channels = 9;
  EXPECT_EQ(d.shade(in).diffuse, 1.0f);
}

TEST(MicroShadowingMethods, SameValuesFromManyThreads) {
  const MicroShadowingEvaluator l3("lut3d");
  std::vector<double> a(200), b(200);
  auto fill = [&](std::vector<double>& out, int begin, int end) {
    for (int i = begin; i < end; ++i)
      out[size_t(i)] = l3.eval({(i % 17) / 16.0, (i % 13) / 12.0, 0.5, 0.6, std::nullopt, std::nullopt});
  };
  fill(a, 0, 200);
  std::thread t1(fill, std::ref(b), 0, 100), t2(fill, std::ref(b), 100, 200);
  t1.join();
  t2.join();
  EXPECT_EQ(a, b);
}

}  // namespace
}  // namespace msh::occlusion
