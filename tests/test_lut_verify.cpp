// The as-used accuracy measurement (lut/runtime/micro_shadowing_verify.h) and `microshadow verify`:
// statistics on hand-computable cases, the inputs (domain, stratification, off texels and off channel
// roughness, determinism), the reference against the independent semi-analytic term, hardware weight
// quantisation through the real sampler, and the CLI (finite, reproducible, thread-independent, bad input →
// exit 2).
#include <gtest/gtest.h>
#include <microshadow/io/error.h>
#include <microshadow/lut/micro_shadowing_lut.h>
#include <microshadow/lut/runtime/micro_shadowing_verify.h>
#include <microshadow/math/vec.h>
#include <microshadow/occlusion/micro_shadowing.h>
#include <microshadow/occlusion/micro_shadowing_fit.h>
#include <microshadow/occlusion/runtime/micro_shadowing_methods.h>
#include <microshadow/reference/micro_shadowing_ring.h>
#include <support/cli_test_util.h>
#include <sys/wait.h>
#include <unistd.h>

#include <algorithm>
#include <cmath>
#include <cstdlib>
#include <cstring>
#include <filesystem>
#include <fstream>
#include <iterator>
#include <nlohmann/json.hpp>
#include <sstream>
#include <string>
#include <vector>

namespace fs = std::filesystem;
using namespace msh;
using namespace msh::lut;

namespace {

VerifyOptions small(int n, VerifyReference against = VerifyReference::AzimuthMean) {
  VerifyOptions o;
  o.samples = n;
  o.against = against;
  o.threads = 2;
  return o;
}

TEST(VerifyStats, HandComputed) {
  std::vector<double> e;
  for (int i = 1; i <= 100; ++i) e.push_back((i % 2 ? -1.0 : 1.0) * i / 1000.0);
  const ErrorStats s = error_stats(e);
  EXPECT_EQ(s.count, 100u);
  EXPECT_EQ(s.nonfinite, 0u);
  EXPECT_DOUBLE_EQ(s.max_abs, 0.1);
  EXPECT_DOUBLE_EQ(s.p99, 0.099);  // nearest rank: the 99th of 100 sorted |e|
  EXPECT_NEAR(s.rms, std::sqrt(338350.0 / 100.0) / 1000.0, 1e-15);  // Σ i² = 100·101·201/6
  EXPECT_NEAR(s.mean, 50.0 / 100.0 / 1000.0, 1e-15);                // pairs (−odd, +even) give +1/1000 each
  const ErrorStats one = error_stats({0.25});
  EXPECT_EQ(one.p99, 0.25);
  EXPECT_EQ(one.rms, 0.25);
  const ErrorStats bad = error_stats({0.0, std::nan(""), 0.0, 0.0});
  EXPECT_EQ(bad.nonfinite, 1u);
  EXPECT_EQ(bad.max_abs, 1.0);
  EXPECT_EQ(bad.rms, 0.5);
  EXPECT_EQ(error_stats({}).count, 0u);
}

// A callable equal to the exact term plus a constant c has RMS = p99 = max = |mean| = c in every row; the
// exact term itself measures ~0 (float rounding of its result).
TEST(Verify, ConstantErrorAndExactCallable) {
  for (VerifyReference ref : {VerifyReference::AzimuthMean, VerifyReference::Azimuth}) {
    const VerifyOptions o = small(96, ref);
    const std::vector<VerifyInput> in = make_verify_inputs(o);
    auto exact = [ref](float V, float nl, float nv, float r, float c) {
      return verify_reference_value(ref, V, nl, nv, r, c);
    };
    const double c = 0.01;
    const VerifyResult shifted = measure(
        in,
        [&](float V, float nl, float nv, float r, float cp) { return float(exact(V, nl, nv, r, cp) + c); },
        o);
    for (const ErrorStats& s : {shifted.all, shifted.early_out, shifted.rest}) {
      EXPECT_NEAR(s.rms, c, 1e-7);
      EXPECT_NEAR(s.max_abs, c, 1e-7);
      EXPECT_NEAR(s.p99, c, 1e-7);
      EXPECT_NEAR(s.mean, c, 1e-7);
    }
    std::size_t nr = 0, nn = 0;
    for (const VerifyBand& b : shifted.by_roughness) {
      nr += b.stats.count;
      EXPECT_NEAR(b.stats.rms, c, 1e-7);
    }
    for (const VerifyBand& b : shifted.by_n_dot_v) {
      nn += b.stats.count;
      EXPECT_NEAR(b.stats.max_abs, c, 1e-7);
    }
    EXPECT_EQ(nr, in.size());
    EXPECT_EQ(nn, in.size());
    EXPECT_EQ(shifted.early_out.count + shifted.rest.count, in.size());
    ASSERT_EQ(shifted.worst.size(), 10u);
    const VerifyResult zero = measure(
        in, [&](float V, float nl, float nv, float r, float cp) { return float(exact(V, nl, nv, r, cp)); },
        o);
    EXPECT_LT(zero.all.max_abs, 1e-7);
    EXPECT_EQ(zero.early_out.max_abs, 0.0);
  }
}

// The azimuth mean measured against the term at the azimuth is not zero (the modes differ), and a callable
// that ignores its inputs has the error the reference's own statistics predict.
TEST(Verify, ReferenceModesDiffer) {
  const VerifyOptions o = small(128, VerifyReference::Azimuth);
  const std::vector<VerifyInput> in = make_verify_inputs(o);
  const VerifyResult r = measure(
      in,
      [](float V, float nl, float nv, float rr, float) {
        return float(verify_reference_value(VerifyReference::AzimuthMean, V, nl, nv, rr, 1.0));
      },
      o);
  EXPECT_GT(r.all.rms, 0.01);
  const VerifyResult zero = measure(
      in, [](float, float, float, float, float) { return 0.0f; }, o);
  double sum2 = 0;
  for (const VerifyInput& p : in) sum2 += p.exact * p.exact;
  EXPECT_NEAR(zero.all.rms, std::sqrt(sum2 / double(in.size())), 1e-12);
}

// The stored reference equals the independent semi-analytic evaluation (ring integration, another
// quadrature of the same definition): < 1e-5 for the azimuth mean, < 5e-5 at one azimuth.
TEST(Verify, ReferenceMatchesSemiAnalytic) {
  for (VerifyReference ref : {VerifyReference::AzimuthMean, VerifyReference::Azimuth}) {
    VerifyOptions o = small(48, ref);
    o.seed = 7;
    int nonzero = 0;
    for (const VerifyInput& p : make_verify_inputs(o)) {
      const double alpha = double(p.roughness) * double(p.roughness);
      const double s = ref == VerifyReference::AzimuthMean
                           ? micro_shadowing::micro_shadowing_semi_analytic_azimuth_mean(
                                 alpha, p.visibility, p.n_dot_l, p.n_dot_v, 8)
                           : micro_shadowing::micro_shadowing_semi_analytic(
                                 alpha, p.visibility, p.n_dot_l, p.n_dot_v, std::acos(double(p.cos_phi)));
      EXPECT_NEAR(p.exact, s, ref == VerifyReference::AzimuthMean ? 1e-5 : 5e-5)
          << p.visibility << " " << p.n_dot_l << " " << p.n_dot_v << " " << p.roughness << " " << p.cos_phi;
      nonzero += p.exact > 0.01 && p.exact < 0.99;
    }
    EXPECT_GT(nonzero, 15);  // the check is not all early-outs and ones
  }
}

// Inputs cover the documented domain, stratified, off the texels and off the channel roughness values, the
// early-out region with its area (1/4 of the (V, N·L) square), bit-identical for 1 and 2 threads.
TEST(Verify, InputsDomainStratifiedOffTexelsDeterministic) {
  VerifyOptions o = small(1024);
  o.roughness_min = 0.1, o.roughness_max = 1.0;
  o.threads = 1;
  const std::vector<VerifyInput> a = make_verify_inputs(o);
  o.threads = 2;
  const std::vector<VerifyInput> b = make_verify_inputs(o);
  ASSERT_EQ(a.size(), 1024u);
  ASSERT_EQ(b.size(), a.size());
  std::vector<int> vbin(64), nlbin(64), nvbin(64), rbin(64), pbin(64);
  int early = 0, on_texel = 0, on_channel = 0;
  for (std::size_t i = 0; i < a.size(); ++i) {
    const VerifyInput& p = a[i];
    ASSERT_EQ(std::memcmp(&p, &b[i], sizeof(VerifyInput)), 0) << i;
    ASSERT_TRUE(p.visibility >= 0 && p.visibility < 1);
    ASSERT_TRUE(p.n_dot_l > 0 && p.n_dot_l <= 1);
    ASSERT_TRUE(p.n_dot_v > 0 && p.n_dot_v <= 1);
    ASSERT_TRUE(p.roughness >= 0.1f && p.roughness <= 1.0f);
    ASSERT_TRUE(p.cos_phi >= -1 && p.cos_phi <= 1);
    ASSERT_TRUE(std::isfinite(p.exact) && p.exact >= 0 && p.exact <= 1);
    ++vbin[std::min(63, int(p.visibility * 64))];
    ++nlbin[std::min(63, int((1 - p.n_dot_l) * 64))];
    ++nvbin[std::min(63, int((1 - p.n_dot_v) * 64))];
    ++rbin[std::min(63, int((p.roughness - 0.1) / 0.9 * 64))];
    ++pbin[std::min(63, int(std::acos(double(p.cos_phi)) / kPi<double> * 64))];
    early += 2 * p.visibility + p.n_dot_l < 1;
    for (int n : {16, 64})
      for (float x : {p.visibility, p.n_dot_l, p.n_dot_v}) on_texel += x * (n - 1) == std::floor(x * (n - 1));
    for (float r : kDefaultRoughness) on_channel += p.roughness == r;
  }
  for (int k = 0; k < 64; ++k)
    for (const auto* bins : {&vbin, &nlbin, &nvbin, &rbin, &pbin}) EXPECT_NEAR((*bins)[k], 16, 1) << k;
  EXPECT_EQ(on_texel, 0);
  EXPECT_EQ(on_channel, 0);
  EXPECT_NEAR(early / 1024.0, 0.25, 0.01);
  VerifyOptions other = o;
  other.seed = 2;
  EXPECT_NE(make_verify_inputs(other)[3].visibility, a[3].visibility);
}

TEST(Verify, ResultsIndependentOfThreads) {
  VerifyOptions o = small(200);
  auto f = [](float V, float nl, float, float r, float) { return V * nl * r; };
  o.threads = 1;
  const VerifyResult a = verify_micro_shadowing(f, o);
  o.threads = 2;
  const VerifyResult b = verify_micro_shadowing(f, o);
  EXPECT_EQ(a.all.rms, b.all.rms);
  EXPECT_EQ(a.all.p99, b.all.p99);
  EXPECT_EQ(a.by_roughness[1].stats.rms, b.by_roughness[1].stats.rms);
  ASSERT_EQ(a.worst.size(), b.worst.size());
  for (std::size_t i = 0; i < a.worst.size(); ++i) EXPECT_EQ(a.worst[i].index, b.worst[i].index);
  for (std::size_t i = 1; i < a.worst.size(); ++i)
    EXPECT_GE(std::abs(a.worst[i - 1].error), std::abs(a.worst[i].error));
}

TEST(Verify, BadOptionsThrow) {
  const auto bad = [](auto change) {
    VerifyOptions o = small(10);
    change(o);
    EXPECT_THROW(validate(o), InputError);
  };
  bad([](VerifyOptions& o) { o.samples = 0; });
  bad([](VerifyOptions& o) { o.samples = 20000000; });
  bad([](VerifyOptions& o) { o.roughness_min = -0.1; });
  bad([](VerifyOptions& o) { o.roughness_max = 1.5; });
  bad([](VerifyOptions& o) { o.roughness_min = 0.8, o.roughness_max = 0.2; });
  bad([](VerifyOptions& o) { o.roughness_max = std::nan(""); });
  bad([](VerifyOptions& o) { o.threads = -1; });
  bad([](VerifyOptions& o) { o.roughness_bands = {0.5}; });
  bad([](VerifyOptions& o) { o.n_dot_v_bands = {0, 0.5, 0.5}; });
  EXPECT_THROW(verify_reference_from_name("median"), InputError);
  // One roughness value: a zero-width range and its single band.
  VerifyOptions one = small(16, VerifyReference::Azimuth);
  one.roughness_min = one.roughness_max = 0.4;
  one.roughness_bands = {0.4, 0.4};
  EXPECT_NO_THROW(validate(one));
  const std::vector<VerifyInput> in = make_verify_inputs(one);
  for (const VerifyInput& p : in) EXPECT_EQ(p.roughness, 0.4f);
  EXPECT_EQ(measure(
                in, [](float, float, float, float, float) { return 0.0f; }, one)
                .by_roughness[0]
                .stats.count,
            16u);
}

// What --gpu-weights relies on: the sampler's filter_weight_bits puts the weights on the 1/256 grid, rounded
// down. On a table whose single channel holds the V texel coordinate, the sampled value is the weight itself.
TEST(Verify, SamplerWeightBitsGiveHardwareWeights) {
  const int n = 5;
  std::vector<float> data(n * 2 * 2);
  for (int z = 0; z < 2; ++z)
    for (int y = 0; y < 2; ++y)
      for (int x = 0; x < n; ++x) data[(z * 2 + y) * n + x] = float(x) / float(n - 1);
  MicroShadowingLutView v;
  v.data = data.data();
  v.n_vis = n, v.n_nl = 2, v.n_nv = 2, v.channels = 1;
  v.filter_weight_bits = 8;
  for (int i = 0; i < 2000; ++i) {
    const double u = 0.5 + 0.5 * (i + 0.37) / 2000.0;  // V ≥ 0.5 with N·L = 1: never the early-out
    const double x = u * (n - 1), f = x - std::floor(x);
    const double value = sample_micro_shadowing<double>(v, u, 1.0, 0.3, 0.5) * (n - 1);
    EXPECT_NEAR(value, std::floor(x) + std::floor(f * 256.0) / 256.0, 1e-6) << u;
  }
}

// ----------------------------------------------------------------------------------------------------------
// CLI

fs::path scratch() { return msh::test::scratch_dir("lut_verify_tmp"); }
using msh::test::CliResult;
using msh::test::slurp;
CliResult run(const std::string& args, const fs::path& dir) { return msh::test::run_cli(args, dir); }

nlohmann::json without_seconds(const std::string& text) {
  nlohmann::json j = nlohmann::json::parse(text);
  j.erase("seconds");
  return j;
}

void expect_finite_stats(const nlohmann::json& s, std::size_t count) {
  EXPECT_EQ(s["count"].get<std::size_t>(), count);
  EXPECT_EQ(s["nonfinite"].get<int>(), 0);
  for (const char* k : {"rms", "p99", "max", "mean", "rms_255", "max_255"}) {
    ASSERT_TRUE(s[k].is_number()) << k;
    EXPECT_TRUE(std::isfinite(s[k].get<double>())) << k;
  }
  // The 1/255 fields are the absolute ones scaled (rms ≤ max and p99 ≤ max hold for any data: not checked).
  EXPECT_NEAR(s["rms_255"].get<double>(), 255 * s["rms"].get<double>(),
              1e-9 * (1 + s["rms_255"].get<double>()));
  EXPECT_NEAR(s["max_255"].get<double>(), 255 * s["max"].get<double>(),
              1e-9 * (1 + s["max_255"].get<double>()));
}

// Small tables of both layouts (Zurita 2026b's seed layout and the cone layout), through the CLI.
const char* const kSmallBakes[][2] = {
    {"seed", "--layout seed --size 16 --samples 1024 --phi-nodes 4"},
    {"cone",
     "--layout cone --size-t 16 --size-nl 8 --size-nv 4 --roughness-slabs 4 --samples 1024 --phi-nodes 4"},
};

// Bakes each small table (with the extra bake flags `extra`) into d/<layout>.npy through the CLI and calls
// f(layout, path) on it.
template <class F>
void for_each_small_table(const fs::path& d, const std::string& extra, F&& f) {
  for (const auto& [layout, bake] : kSmallBakes) {
    SCOPED_TRACE(layout);
    const std::string t = (d / (std::string(layout) + ".npy")).string();
    ASSERT_EQ(run("bake micro-shadowing --quiet " + extra + bake + " --out " + t, d).code, 0);
    f(std::string(layout), t);
  }
}

TEST(VerifyCli, SmallTableFiniteReproducibleThreadIndependent) {
  const fs::path d = scratch();
  for_each_small_table(d, "", [&](const std::string& layout, const std::string& t) {
    const std::string cmd = "verify micro-shadowing-lut " + t + " --samples 300 --json";
    const CliResult a = run(cmd + " --threads 1", d);
    ASSERT_EQ(a.code, 0) << a.err;
    const CliResult b = run(cmd + " --threads 2", d);
    ASSERT_EQ(b.code, 0) << b.err;
    EXPECT_EQ(without_seconds(a.out), without_seconds(b.out));
    const nlohmann::json j = nlohmann::json::parse(a.out);
    EXPECT_EQ(j["layout"], layout);
    expect_finite_stats(j["all"], 300);
    std::size_t sum = 0;
    for (const auto& band : j["by_roughness"]) sum += band["count"].get<std::size_t>();
    EXPECT_EQ(sum, 300u);
    EXPECT_EQ(j["roughness_range"][0].get<double>(), 0.1);
    EXPECT_EQ(j["roughness_range"][1].get<double>(), 1.0);
    EXPECT_EQ(j["sampler"], "plain");
    EXPECT_EQ(j["early_out"]["max"].get<double>(), 0.0);  // the sampler's early-out is exact
    EXPECT_GT(j["all"]["max"].get<double>(), 0.0);
    EXPECT_LT(j["all"]["rms"].get<double>(), 0.1);  // a small table is coarse, not wrong
    EXPECT_EQ(j["worst"].size(), 10u);
    // Another seed: other inputs.
    const CliResult c = run(cmd + " --seed 5", d);
    ASSERT_EQ(c.code, 0);
    EXPECT_NE(nlohmann::json::parse(c.out)["all"]["rms"], j["all"]["rms"]);
    // 8-bit filter weights move each weight by < 1/256: the RMS moves by less than 3/256 (three filtered
    // axes).
    const CliResult g = run(cmd + " --gpu-weights 8", d);
    ASSERT_EQ(g.code, 0) << g.err;
    const nlohmann::json jg = nlohmann::json::parse(g.out);
    expect_finite_stats(jg["all"], 300);
    EXPECT_EQ(jg["gpu_weights"], 8);
    EXPECT_NE(jg["all"]["rms"], j["all"]["rms"]);
    EXPECT_LT(std::abs(jg["all"]["rms"].get<double>() - j["all"]["rms"].get<double>()), 3.0 / 256.0);
    // --csv: every input, consistent with the statistics.
    const std::string csv = (d / (std::string(layout) + ".csv")).string();
    ASSERT_EQ(run(cmd + " --csv " + csv, d).code, 0);
    std::ifstream in(csv);
    std::string line;
    std::getline(in, line);
    EXPECT_EQ(line, "index,visibility,n_dot_l,n_dot_v,roughness,cos_phi,exact,approx,error");
    int rows = 0;
    double max_abs = 0;
    while (std::getline(in, line)) {
      ++rows;
      max_abs = std::max(max_abs, std::abs(std::stod(line.substr(line.rfind(',') + 1))));
    }
    EXPECT_EQ(rows, 300);
    EXPECT_NEAR(max_abs, j["all"]["max"].get<double>(), 1e-12);
    // The human table.
    const CliResult h = run("verify micro-shadowing-lut " + t + " --samples 64", d);
    ASSERT_EQ(h.code, 0);
    EXPECT_NE(h.out.find("RMS/255"), std::string::npos);
    EXPECT_NE(h.out.find("worst inputs"), std::string::npos);
  });
}

TEST(VerifyCli, AzimuthAwareTableUsesTheAzimuthSampler) {
  const fs::path d = scratch();
  for_each_small_table(d, "--azimuth ", [&](const std::string&, const std::string& t) {
    const CliResult az =
        run("verify micro-shadowing-lut " + t + " --samples 200 --against azimuth --json", d);
    ASSERT_EQ(az.code, 0) << az.err;
    const CliResult plain =
        run("verify micro-shadowing-lut " + t + " --samples 200 --against azimuth --sampler plain --json", d);
    ASSERT_EQ(plain.code, 0) << plain.err;
    const nlohmann::json ja = nlohmann::json::parse(az.out), jp = nlohmann::json::parse(plain.out);
    EXPECT_EQ(ja["sampler"], "azimuth");
    EXPECT_EQ(jp["sampler"], "plain");
    EXPECT_GT(ja["harmonics"].get<int>(), 0);
    expect_finite_stats(ja["all"], 200);
    EXPECT_LT(ja["all"]["rms"].get<double>(), jp["all"]["rms"].get<double>());  // the harmonics help
  });
}

TEST(VerifyCli, ClosedFormTerms) {
  const fs::path d = scratch();
  const CliResult r = run("verify micro-shadowing-term --samples 128 --json", d);
  ASSERT_EQ(r.code, 0) << r.err;
  const nlohmann::json j = nlohmann::json::parse(r.out);
  // The registry's ids (the two-stage fit under its GLSL form's id, as the viewer names it).
  std::vector<std::string> names;
  for (const auto& x : j["results"]) names.push_back(x["method"]);
  // The registry's closed forms that depend on N.L, then the generic term's.
  std::vector<std::string> want = msh::occlusion::micro_shadowing_closed_form_terms();
  EXPECT_GE(want.size(), 4u);  // reference, brinck-maximov-2016, chan-2018, part1-analytic at least
  for (const char* s : {"generic-vndf-alu", "generic-vndf-alu-two-stage", "generic-vndf"}) want.push_back(s);
  EXPECT_EQ(names, want);
  for (const auto& x : j["results"]) {
    expect_finite_stats(x["all"], 128);
    if (x["method"] == "generic-vndf")
      EXPECT_LT(x["all"]["max"].get<double>(), 1e-7);  // the reference itself, rounded to float
    else
      EXPECT_GT(x["all"]["rms"].get<double>(), 1e-3);
  }
  const CliResult one =
      run("verify micro-shadowing-term --method chan-2018 --samples 64 --against azimuth", d);
  ASSERT_EQ(one.code, 0) << one.err;
  EXPECT_NE(one.out.find("chan-2018"), std::string::npos);
  // Each term in float, as a shader runs it: --csv's approx is the float function at the row's inputs.
  const std::pair<const char*, float (*)(float, float, float, float)> forms[] = {
      {"chan-2018", [](float V, float nl, float, float) { return micro_shadowing::chan_2018(V, nl); }},
      {"generic-vndf-alu",
       [](float V, float nl, float nv, float r) { return micro_shadowing::generic_vndf_alu(V, nl, nv, r); }},
      {"generic-vndf-alu-two-stage", [](float V, float nl, float nv, float r) {
         return micro_shadowing::generic_vndf_alu_two_stage(V, nl, nv, r);
       }}};
  for (const auto& [name, f] : forms) {
    const std::string csv = (d / (std::string(name) + ".csv")).string();
    ASSERT_EQ(
        run("verify micro-shadowing-term --samples 64 --method " + std::string(name) + " --csv " + csv, d)
            .code,
        0);
    std::ifstream in(csv);
    std::string line;
    std::getline(in, line);
    int rows = 0;
    while (std::getline(in, line)) {
      std::vector<double> c;
      std::stringstream ss(line);
      for (std::string cell; std::getline(ss, cell, ',');) c.push_back(std::stod(cell));
      ASSERT_EQ(c.size(), 9u);
      EXPECT_EQ(c[7], double(f(float(c[1]), float(c[2]), float(c[3]), float(c[4])))) << name << ": " << line;
      ++rows;
    }
    EXPECT_EQ(rows, 64) << name;
  }
}

// verify micro-shadowing-aware names the run-time forms by registry id (the specular mean's float and double
// closed forms: specular-aware-alu, specular-aware), not by the names it had (specular-aware-mean...).
TEST(VerifyCli, AwareFormsByRegistryId) {
  const fs::path d = scratch();
  for (const char* m : {"specular-aware-alu", "specular-aware"}) {
    const CliResult r = run("verify micro-shadowing-aware --samples 32 --json --method " + std::string(m), d);
    ASSERT_EQ(r.code, 0) << r.err;
    EXPECT_TRUE(nlohmann::json::parse(r.out).contains(m)) << r.out;
  }
  EXPECT_EQ(run("verify micro-shadowing-aware --samples 32 --method specular-aware-mean", d).code, 2);
}

TEST(VerifyCli, BadInputIsOneLineExitTwo) {
  const fs::path d = scratch();
  const std::string t = (d / "t.npy").string();
  ASSERT_EQ(
      run("bake micro-shadowing --layout seed --size 6 --samples 256 --phi-nodes 2 --quiet --out " + t, d)
          .code,
      0);
  const std::string tc = (d / "c.npy").string();
  ASSERT_EQ(run("bake micro-shadowing --size-t 6 --size-nl 4 --size-nv 3 --roughness-slabs 2 --samples 256 "
                "--phi-nodes 2 --quiet --out " +
                    tc,
                d)
                .code,
            0);
  const std::string bytes = slurp(t), side = slurp(t + ".json");
  auto write = [](const fs::path& p, const std::string& s) { std::ofstream(p, std::ios::binary) << s; };
  write(d / "trunc.npy", bytes.substr(0, bytes.size() / 2));
  write(d / "trunc.npy.json", side);
  write(d / "garbage.npy", "not a table at all");
  write(d / "garbage.npy.json", side);
  write(d / "noside.npy", bytes);
  write(d / "badjson.npy", bytes);
  write(d / "badjson.npy.json", "{ roughness: ");
  write(d / "size.npy", bytes);
  {
    nlohmann::json j = nlohmann::json::parse(side);
    j["size_visibility"] = 7;
    write(d / "size.npy.json", j.dump());
    j = nlohmann::json::parse(side);
    j["roughness"] = {0.2, 0.8};
    write(d / "rough.npy", bytes);
    write(d / "rough.npy.json", j.dump());
    j = nlohmann::json::parse(side);
    j["layout"] = "hexagonal";
    write(d / "layout.npy", bytes);
    write(d / "layout.npy.json", j.dump());
    nlohmann::json jc = nlohmann::json::parse(slurp(tc + ".json"));
    jc.erase("roughness_slabs");
    write(d / "cone.npy", slurp(tc));
    write(d / "cone.npy.json", jc.dump());
  }
  const std::string p = "verify micro-shadowing-lut ";
  const std::string cases[] = {
      p + (d / "missing.npy").string(),
      p + (d / "trunc.npy").string(),
      p + (d / "garbage.npy").string(),
      p + (d / "noside.npy").string(),
      p + (d / "badjson.npy").string(),
      p + (d / "size.npy").string(),
      p + (d / "rough.npy").string(),
      p + (d / "layout.npy").string(),
      p + (d / "cone.npy").string(),
      p + tc + " --roughness 0.1,0.4,0.7,1",
      p + t + " --against median",
      p + t + " --samples 0",
      p + t + " --gpu-weights 20",
      p + t + " --sampler azimuth",
      p + t + " --sampler bilinear",
      p + t + " --roughness-range 0.5",
      p + t + " --roughness-range 0.9,0.2",
      p + t + " --roughness 0.1,0.5",
      "verify micro-shadowing-term --method unknown",
      "verify micro-shadowing-term --nv-bands 0.5",
      "verify micro-shadowing-term --csv " + (d / "x.csv").string(),
      p + t + " --csv " + (d / "missing" / "x.csv").string(),
  };
  for (const std::string& c : cases) {
    const CliResult r = run(c + (c.find("--samples") == std::string::npos ? " --samples 8" : ""), d);
    EXPECT_EQ(r.code, 2) << c << "\n" << r.err;
    EXPECT_EQ(std::count(r.err.begin(), r.err.end(), '\n'), 1) << c << "\n" << r.err;
  }
  // Without a sidecar, explicit metadata is accepted.
  EXPECT_EQ(run(p + (d / "noside.npy").string() + " --roughness 0.1,0.4,0.7,1 --samples 8", d).code, 0);
}

}  // namespace
