// Bump-terminator terms (Conty 2019, Chiang 2019), the GGX variance metric and the Hanika 2021 offset.
// References are independent of the code under test: the literal closed forms of docs/theory.md §4 /
// Conty Estevez et al. 2019 listing 12.1 in double on unit vectors, the GGX class's Smith G1
// (microfacet/ggx.h), a numerical integral of the Beckmann slope variance, and bounds derived by hand
// (derivations in the comments and docs/bump-terminator.md).
#include <gtest/gtest.h>
#include <microshadow/math/sampling.h>
#include <microshadow/math/vec.h>
#include <microshadow/microfacet/ggx.h>
#include <microshadow/occlusion/bump_terminator.h>
#include <microshadow/occlusion/shadow_terminator_offset.h>

#include <algorithm>
#include <array>
#include <cmath>
#include <cstdio>
#include <fstream>
#include <iterator>
#include <limits>
#include <string>
#include <string_view>
#include <vector>

using namespace msh;
using namespace msh::bump;

namespace {

constexpr double kDeg = 3.14159265358979323846 / 180.0;
constexpr HemisphereTest kOff = HemisphereTest::kOff, kOn = HemisphereTest::kOn;

// Listing 12.1 verbatim (Conty Estevez et al. 2019), on unit vectors: in double the reference, in float the
// engine version our float build replaces.
template <class T>
T conty_listing(const Vec3<T>& ng, const Vec3<T>& ns, const Vec3<T>& l) {
  const T cos_d = std::min(std::abs(dot(ng, ns)), T(1));
  const T tan2_d = (1 - cos_d * cos_d) / (cos_d * cos_d);
  const T alpha2 = std::clamp(T(0.125) * tan2_d, T(0), T(1));
  const T cos_i = std::max(std::abs(dot(ng, l)), T(1e-6));
  const T tan2_i = (1 - cos_i * cos_i) / (cos_i * cos_i);
  return T(2) / (1 + std::sqrt(1 + alpha2 * tan2_i));
}

// Chiang, Li, Burley 2019 verbatim, in double, on unit vectors (callers avoid a zero denominator).
double chiang_listing(const Vec3d& ng, const Vec3d& ns, const Vec3d& l) {
  const double g = dot(ng, l) / (dot(ns, l) * dot(ng, ns));
  if (g >= 1) return 1;
  if (g < 0) return 0;
  return -g * g * g + g * g + g;
}

std::string sci(double x) {
  char b[32];
  std::snprintf(b, sizeof b, "%.3g", x);
  return b;
}

Vec3d random_unit(Pcg32& rng) { return sample_uniform_sphere(Vec2d(rng.next_double(), rng.next_double())); }

// A shading normal at angle delta from ng, azimuth phi about it.
Vec3d tilt(const Vec3d& ng, double delta, double phi) {
  return Framed::from_z(ng).to_world(spherical_direction(std::cos(delta), phi));
}

// The largest change 1 − term(N_g, N_s, L) over 200000 random frames: N_g uniform, N_s tilted from it by
// θ_d < delta_deg degrees and L at θ_i < theta_deg degrees from it, at uniform azimuths; every sample is
// checked against change ≤ bound(θ_d, θ_i) (+1e-15) first (a failure returns +inf).
template <class Term, class Bound>
double max_small_perturbation_change(uint64_t seed, double delta_deg, double theta_deg, Term term,
                                     Bound bound) {
  Pcg32 rng(seed);
  double max_change = 0;
  for (int i = 0; i < 200000; ++i) {
    const double delta = rng.next_double() * delta_deg * kDeg, theta = rng.next_double() * theta_deg * kDeg;
    const Vec3d ng = random_unit(rng);
    const Vec3d ns = tilt(ng, delta, 2 * kPi<double> * rng.next_double());
    const Vec3d l = tilt(ng, theta, 2 * kPi<double> * rng.next_double());
    const double change = 1 - term(ng, ns, l);
    if (!(change <= bound(delta, theta) + 1e-15)) {
      ADD_FAILURE() << "change " << change << " above its bound " << bound(delta, theta) << " at theta_d "
                    << delta << ", theta_i " << theta;
      return std::numeric_limits<double>::infinity();
    }
    max_change = std::max(max_change, change);
  }
  return max_change;
}

template <class T>
Vec3<T> cast(const Vec3d& v) {
  // Saturate finite values out of T's range to ±max (a double → float conversion out of range is UB);
  // ±Inf and NaN convert as they are.
  auto c = [](double x) {
    const double m = double(std::numeric_limits<T>::max());
    return std::isfinite(x) ? T(std::clamp(x, -m, m)) : T(x);
  };
  return Vec3<T>(c(v.x), c(v.y), c(v.z));
}

template <class T>
T eval(Method m, const Vec3d& ng, const Vec3d& ns, const Vec3d& l, HemisphereTest t = kOff) {
  return term<T>(m, cast<T>(ng), cast<T>(ns), cast<T>(l), t);
}

}  // namespace

// ---------------------------------------------------------------------------------------------------------
// Values against the closed forms.

TEST(BumpConty, MatchesListingInDouble) {
  Pcg32 rng(1);
  double max_err = 0;
  for (int i = 0; i < 200000; ++i) {
    const Vec3d ng = random_unit(rng);
    const Vec3d ns = tilt(ng, rng.next_double() * 89.0 * kDeg, 2 * kPi<double> * rng.next_double());
    const Vec3d l = random_unit(rng);
    const double ref = conty_listing(ng, ns, l);
    max_err = std::max(max_err, std::abs(conty2019(ng, ns, l) - ref));
  }
  EXPECT_LT(max_err, 1e-9);
}

// Independent of the listing: the term is the Smith GGX G1 (ggx.h) of l in ng's frame, α = sqrt(α²).
TEST(BumpConty, IsSmithG1OfTheGGXClass) {
  Pcg32 rng(2);
  for (int i = 0; i < 20000; ++i) {
    const double delta = (0.5 + rng.next_double() * 69.5) * kDeg;  // α² < 1 (no clamp), α > GGX's kMinAlpha
    const Vec3d ng = random_unit(rng);
    const Vec3d ns = tilt(ng, delta, 2 * kPi<double> * rng.next_double());
    Vec3d l = random_unit(rng);
    if (std::abs(dot(ng, l)) < 1e-3) continue;  // the listing's 1e-6 clamp is not part of G1
    const double alpha = std::tan(delta) / std::sqrt(8.0);
    const GGX<double> ggx(alpha);
    const Vec3d ll = Framed::from_z(ng).to_local(l);
    ASSERT_NEAR(conty2019(ng, ns, l), ggx.G1(ll), 1e-12) << "delta=" << delta;
  }
}

TEST(BumpChiang, MatchesClosedFormInDouble) {
  Pcg32 rng(3);
  double max_err = 0;
  int n = 0;
  for (int i = 0; i < 200000; ++i) {
    const Vec3d ng = random_unit(rng);
    const Vec3d ns = tilt(ng, rng.next_double() * 89.0 * kDeg, 2 * kPi<double> * rng.next_double());
    const Vec3d l = random_unit(rng);
    if (std::abs(dot(ns, l)) < 1e-9) continue;  // the literal formula divides by N_s·L
    max_err = std::max(max_err, std::abs(chiang2019(ng, ns, l) - chiang_listing(ng, ns, l)));
    ++n;
  }
  EXPECT_GT(n, 199000);
  EXPECT_LT(max_err, 1e-12);
}

TEST(BumpChiang, SmoothingCubicValues) {
  // −g³ + g² + g at a few points, computed by hand; clamps outside [0, 1].
  EXPECT_DOUBLE_EQ(chiang_smooth(0.5), 0.625);
  EXPECT_DOUBLE_EQ(chiang_smooth(0.25), 0.296875);
  EXPECT_DOUBLE_EQ(chiang_smooth(0.0), 0.0);
  EXPECT_DOUBLE_EQ(chiang_smooth(1.0), 1.0);
  EXPECT_DOUBLE_EQ(chiang_smooth(-3.0), 0.0);
  EXPECT_DOUBLE_EQ(chiang_smooth(7.0), 1.0);
  EXPECT_EQ(chiang_smooth(std::numeric_limits<double>::quiet_NaN()), 0.0);
  // In-plane case by hand: ng = z, ns tilted 30° toward x, l at 60° toward x: g = cos60/(cos30·cos30) = 2/3.
  const Vec3d ng(0, 0, 1), ns(std::sin(30 * kDeg), 0, std::cos(30 * kDeg)),
      l(std::sin(60 * kDeg), 0, std::cos(60 * kDeg));
  const double g = 2.0 / 3.0;
  EXPECT_NEAR(chiang2019(ng, ns, l), -g * g * g + g * g + g, 1e-15);
}

// float versions against the double closed forms on the same (float-rounded) inputs. Near grazing the term is
// steep in cos θ_i (dG/dcos ≈ 2/α), so the float rounding of N_g·L (~6e-8) sets the error; bins by |cos θ_i|.
TEST(BumpBoth, FloatAccuracy) {
  Pcg32 rng(4);
  double err[3] = {0, 0, 0}, err_listing[3] = {0, 0, 0}, err_chiang = 0;
  for (int i = 0; i < 300000; ++i) {
    const Vec3f ng = cast<float>(random_unit(rng));
    const Vec3f ns =
        cast<float>(tilt(Vec3d(ng), rng.next_double() * 89.0 * kDeg, 2 * kPi<double> * rng.next_double()));
    const Vec3f l = cast<float>(random_unit(rng));
    // The listing wants unit vectors: normalize the float inputs in double.
    const Vec3d ngd = normalize(Vec3d(ng)), nsd = normalize(Vec3d(ns)), ld = normalize(Vec3d(l));
    const double ref = conty_listing(ngd, nsd, ld), c = std::abs(dot(ngd, ld));
    const int bin = c < 0.01 ? 0 : (c < 0.05 ? 1 : 2);
    err[bin] = std::max(err[bin], std::abs(double(conty2019(ng, ns, l)) - ref));
    err_listing[bin] = std::max(err_listing[bin], std::abs(double(conty_listing(ng, ns, l)) - ref));
    // Chiang's g is a ratio of cosines: away from N_s·L = 0 its float error is a few ulp.
    if (std::abs(dot(nsd, ld)) > 1e-3)
      err_chiang =
          std::max(err_chiang, std::abs(double(chiang2019(ng, ns, l)) - chiang_listing(ngd, nsd, ld)));
  }
  RecordProperty("conty_float_err_cos_lt_0.01", sci(err[0]));
  RecordProperty("conty_float_err_cos_0.01_0.05", sci(err[1]));
  RecordProperty("conty_float_err_cos_ge_0.05", sci(err[2]));
  RecordProperty("listing_float_err_cos_lt_0.01", sci(err_listing[0]));
  RecordProperty("listing_float_err_cos_0.01_0.05", sci(err_listing[1]));
  RecordProperty("listing_float_err_cos_ge_0.05", sci(err_listing[2]));
  RecordProperty("chiang_float_max_abs_err", sci(err_chiang));
  EXPECT_LT(err[0], 1e-4);
  EXPECT_LT(err[1], 5e-6);
  EXPECT_LT(err[2], 1e-6);
  // The cross-product form is more accurate than the listing's 1 − cos² in float, in every bin.
  for (int b = 0; b < 3; ++b) EXPECT_LT(err[b], err_listing[b]) << "bin " << b;
  EXPECT_LT(err_chiang, 2e-5);
}

// ---------------------------------------------------------------------------------------------------------
// Properties stated by Conty Estevez et al. 2019 (§12.4) and by the formulas.

TEST(BumpBoth, NoPerturbationIsExactlyOne) {
  Pcg32 rng(5);
  for (int i = 0; i < 20000; ++i) {
    const Vec3d ng = random_unit(rng);
    Vec3d l = random_unit(rng);
    if (i == 0) l = Framed::from_z(ng).to_world(Vec3d(1, 0, 0));  // exactly grazing (up to rounding)
    for (const Vec3d& ns : {ng, -ng, 4.0 * ng, 0.25 * ng}) {
      for (Method m : {Method::kConty2019, Method::kChiang2019}) {
        ASSERT_EQ(eval<double>(m, ng, ns, l), 1.0);
        ASSERT_EQ(eval<float>(m, ng, ns, l), 1.0f);
      }
    }
  }
  // Grazing exactly: ng = z, l = x.
  for (Method m : {Method::kConty2019, Method::kChiang2019})
    EXPECT_EQ(eval<double>(m, {0, 0, 1}, {0, 0, 1}, {1, 0, 0}), 1.0);
}

TEST(BumpBoth, LightAlongGeometricNormalIsOne) {
  Pcg32 rng(6);
  for (int i = 0; i < 20000; ++i) {
    const Vec3d ng = random_unit(rng);
    const Vec3d ns = tilt(ng, rng.next_double() * 89.9 * kDeg, 2 * kPi<double> * rng.next_double());
    for (const Vec3d& l : {ng, -ng, 2.0 * ng}) {
      ASSERT_EQ(eval<double>(Method::kConty2019, ng, ns, l), 1.0);
      ASSERT_EQ(eval<float>(Method::kConty2019, ng, ns, l), 1.0f);
      // Chiang: g = |ng|²|ns|²/(ng·ns)² ≥ 1 (Cauchy-Schwarz), up to rounding of the ratio.
      ASSERT_NEAR(eval<double>(Method::kChiang2019, ng, ns, l), 1.0, 1e-14);
      ASSERT_NEAR(eval<float>(Method::kChiang2019, ng, ns, l), 1.0f, 1e-6f);
    }
  }
}

TEST(BumpBoth, BoundedAndFiniteOnEveryInput) {
  const double inf = std::numeric_limits<double>::infinity(), nan = std::numeric_limits<double>::quiet_NaN();
  std::vector<Vec3d> vs = {{0, 0, 0},     {0, 0, 1},        {0, 0, -1},     {1, 0, 0},    {1e-30, 0, 1e-30},
                           {1e30, 0, 1},  {nan, 0, 1},      {inf, 0, 0},    {0, -inf, 1}, {1e-200, 1e-200, 0},
                           {1e200, 0, 1}, {0.3, -0.4, 0.1}, {-2, 5, -0.001}};
  Pcg32 rng(7);
  for (int i = 0; i < 20; ++i) vs.push_back(random_unit(rng) * std::exp(rng.next_double() * 20 - 10));
  auto check = [](double v) { return std::isfinite(v) && v >= 0 && v <= 1; };
  for (const Vec3d& ng : vs)
    for (const Vec3d& ns : vs)
      for (const Vec3d& l : vs)
        for (Method m : {Method::kNone, Method::kConty2019, Method::kChiang2019})
          for (HemisphereTest t : {kOff, kOn}) {
            ASSERT_TRUE(check(eval<double>(m, ng, ns, l, t))) << ng.x << "," << ns.x << "," << l.x;
            ASSERT_TRUE(check(eval<float>(m, ng, ns, l, t))) << ng.x << "," << ns.x << "," << l.x;
          }
}

TEST(BumpBoth, DegenerateInputsAreDocumentedValues) {
  const double nan = std::numeric_limits<double>::quiet_NaN();
  const Vec3d z(0, 0, 1), zero(0, 0, 0), bad(nan, 0, 1), ns(0.5, 0, 1), l(1, 0, 0.1);
  for (Method m : {Method::kConty2019, Method::kChiang2019}) {
    for (const auto& [a, b, c] : std::vector<std::array<Vec3d, 3>>{
             {zero, ns, l}, {z, zero, l}, {z, ns, zero}, {bad, ns, l}, {z, bad, l}, {z, ns, bad}}) {
      EXPECT_EQ(eval<double>(m, a, b, c, kOff), 1.0) << method_name(m);
      EXPECT_EQ(eval<double>(m, a, b, c, kOn), 0.0) << method_name(m);
    }
  }
}

TEST(BumpBoth, SymmetricInEachSignConvention) {
  Pcg32 rng(8);
  for (int i = 0; i < 50000; ++i) {
    const Vec3d ng = random_unit(rng), ns = random_unit(rng), l = random_unit(rng);
    for (Method m : {Method::kConty2019, Method::kChiang2019}) {
      const double v = eval<double>(m, ng, ns, l);
      ASSERT_EQ(eval<double>(m, -ng, ns, l), v);
      ASSERT_EQ(eval<double>(m, ng, -ns, l), v);
      ASSERT_EQ(eval<double>(m, ng, ns, -l), v);
      ASSERT_EQ(eval<double>(m, -ng, -ns, -l), v);
      const float f = eval<float>(m, ng, ns, l);
      ASSERT_EQ(eval<float>(m, -ng, ns, -l), f);
    }
  }
}

TEST(BumpBoth, ScaleInvariant) {
  Pcg32 rng(9);
  for (int i = 0; i < 50000; ++i) {
    const Vec3d ng = random_unit(rng), ns = random_unit(rng), l = random_unit(rng);
    const double a = std::exp(rng.next_double() * 10 - 5), b = std::exp(rng.next_double() * 10 - 5),
                 c = std::exp(rng.next_double() * 10 - 5);
    if (std::abs(dot(ns, l)) < 1e-6) continue;  // Chiang's singular set
    for (Method m : {Method::kConty2019, Method::kChiang2019})
      ASSERT_NEAR(eval<double>(m, a * ng, b * ns, c * l), eval<double>(m, ng, ns, l), 1e-9) << method_name(m);
  }
}

// As the light moves from the geometric normal to the horizon along any azimuth, neither term increases.
// With the hemisphere test this holds for oriented normals (N_g·N_s > 0), the documented use.
TEST(BumpBoth, MonotoneTowardGrazing) {
  Pcg32 rng(10);
  for (int trial = 0; trial < 400; ++trial) {
    const Vec3d ng = random_unit(rng);
    const Framed f = Framed::from_z(ng);
    const Vec3d ns = tilt(ng, rng.next_double() * 89.0 * kDeg, 2 * kPi<double> * rng.next_double());
    const double phi = 2 * kPi<double> * rng.next_double();
    for (Method m : {Method::kConty2019, Method::kChiang2019})
      for (HemisphereTest t : {kOff, kOn}) {
        double prev_d = 2;
        float prev_f = 2;
        for (int k = 0; k <= 900; ++k) {
          const Vec3d l = f.to_world(spherical_direction(std::cos(k * 0.1 * kDeg), phi));
          const double vd = eval<double>(m, ng, ns, l, t);
          const float vf = eval<float>(m, ng, ns, l, t);
          ASSERT_LE(vd, prev_d + 1e-13) << method_name(m) << " k=" << k;
          // float: at exactly 90° the sign of the rounded N_g·L is noise, and Chiang's g ≈
          // ε/((N_s·L)(N_g·N_s)) can come out a few 1e-5 instead of 0 when N_s·L < 0: check the float sweep
          // up to 89.9°.
          if (k < 900) {
            ASSERT_LE(vf, prev_f + 1e-6f) << method_name(m) << " k=" << k;
          }
          prev_d = vd, prev_f = vf;
        }
      }
  }
}

// Conty Estevez et al. 2019 (§12.4): small perturbations get a very small α and hardly any change; only
// grazing light is affected.
// Made precise: 1 − G = x/(1 + sqrt(1 + x))² ≤ x/4 with x = α² tan²θ_i = tan²θ_d tan²θ_i / 8, so the change
// is below 1e-3 whenever tanθ_d·tanθ_i ≤ 0.179 (x ≤ 4.008e-3). "Grazing" for a perturbation θ_d therefore
// means tanθ_i > 0.179 / tanθ_d: for θ_d ≤ 2°, the light within 11.04° of the horizon (θ_i > 78.96°).
TEST(BumpConty, SmallPerturbationChangesBelow1e3ExceptGrazing) {
  // The general bound, everywhere:
  const double max_change = max_small_perturbation_change(
      11, 2.0, 78.9, [](const Vec3d& ng, const Vec3d& ns, const Vec3d& l) { return conty2019(ng, ns, l); },
      [](double delta, double theta) { return sqr(std::tan(delta) * std::tan(theta)) / 32; });
  RecordProperty("max_change", sci(max_change));
  EXPECT_LT(max_change, 1e-3);
  EXPECT_GT(max_change, 0.5e-3);  // the sampled region reaches close to the bound: the bound is not vacuous
  // Outside the region ("grazing"), the change does exceed 1e-3: the exception is real.
  const Vec3d ng(0, 0, 1);
  EXPECT_GT(1 - conty2019(ng, tilt(ng, 2 * kDeg, 0), tilt(ng, 80 * kDeg, 1.0)), 1e-3);
  EXPECT_GT(1 - conty2019(ng, tilt(ng, 2 * kDeg, 0), tilt(ng, 89 * kDeg, 1.0)), 0.1);
}

// Chiang's term changes faster: with the light at θ_i above N_g and N_s tilted by θ_d,
// g = 1/((sinθ_d tanθ_i cosφ + cosθ_d) cosθ_d) ≥ 1/(1 + sinθ_d tanθ_i), so
// 1 − p(g) = (1 − g)²(1 + g) ≤ 2 (sinθ_d tanθ_i)² (while N_s·L > 0). Below 1e-3 needs sinθ_d tanθ_i < 0.0224,
// e.g. θ_d ≤ 0.25° and θ_i ≤ 78.5°; at θ_d = 2° the change passes 1e-3 already at θ_i = 60°.
TEST(BumpChiang, SmallPerturbationBound) {
  const double max_change = max_small_perturbation_change(
      12, 0.25, 78.5, [](const Vec3d& ng, const Vec3d& ns, const Vec3d& l) { return chiang2019(ng, ns, l); },
      [](double delta, double theta) { return 2 * sqr(std::sin(delta) * std::tan(theta)); });
  EXPECT_LT(max_change, 1e-3);
  EXPECT_GT(max_change, 0.5e-3);
  const Vec3d ng(0, 0, 1);
  EXPECT_GT(1 - chiang2019(ng, tilt(ng, 2 * kDeg, 0), tilt(ng, 60 * kDeg, 0)), 1e-3);
  EXPECT_LT(1 - conty2019(ng, tilt(ng, 2 * kDeg, 0), tilt(ng, 60 * kDeg, 0)), 1e-3);
}

TEST(BumpChiang, ShadingHorizonAndBelow) {
  const Vec3d ng(0, 0, 1), ns = tilt(ng, 20 * kDeg, 0);
  // Light on the shading horizon (N_s·L = 0) with N_g·L > 0: documented value 1, no NaN.
  const Vec3d l_exact(-ns.z, 0, ns.x);  // exactly perpendicular to ns in double
  EXPECT_EQ(dot(ns, l_exact), 0.0);
  EXPECT_EQ(chiang2019(ng, ns, l_exact), 1.0);
  // Just below the shading horizon, above the geometric one: g < 0 → 0.
  const Vec3d below = tilt(ng, 75 * kDeg, kPi<double>);
  EXPECT_LT(dot(ns, below), 0);
  EXPECT_GT(dot(ng, below), 0);
  EXPECT_EQ(chiang2019(ng, ns, below), 0.0);
  EXPECT_EQ(chiang2019(ng, Vec3d(1, 0, 0), below), 1.0);  // ns ⟂ ng: denominator 0 → 1
}

TEST(BumpBoth, HemisphereTest) {
  Pcg32 rng(13);
  for (int i = 0; i < 50000; ++i) {
    const Vec3d ng = random_unit(rng);
    const Vec3d ns = tilt(ng, rng.next_double() * 80.0 * kDeg, 2 * kPi<double> * rng.next_double());
    const Vec3d l = random_unit(rng);
    const bool above = dot(ng, l) > 0 && dot(ns, l) > 0;
    for (Method m : {Method::kNone, Method::kConty2019, Method::kChiang2019}) {
      const double on = eval<double>(m, ng, ns, l, kOn), off = eval<double>(m, ng, ns, l, kOff);
      if (above)
        ASSERT_EQ(on, off);
      else
        ASSERT_EQ(on, 0.0);
    }
  }
}

// ---------------------------------------------------------------------------------------------------------
// The GGX variance metric and the perturbation → α mapping.

TEST(BumpVariance, ClosedForms) {
  for (double a : {0.0, 0.01, 0.3, 1.0, 2.5}) {
    EXPECT_DOUBLE_EQ(ggx_variance(a), 2 * a * a);
    EXPECT_NEAR(ggx_alpha_from_variance(ggx_variance(a)), a, 1e-15);
    EXPECT_DOUBLE_EQ(beckmann_alpha_from_ggx(a), std::sqrt(2.0) * a);
  }
  EXPECT_EQ(ggx_alpha_from_variance(-1.0), 0.0);
  EXPECT_EQ(ggx_variance(std::numeric_limits<double>::quiet_NaN()), 0.0);
  // tan θ_d = 2σ → α² = σ²/2 = tan²θ_d / 8, through the variance functions.
  for (double deg : {0.0, 1.0, 10.0, 45.0, 70.0}) {
    const double t = std::tan(deg * kDeg), sigma = t / 2;
    EXPECT_NEAR(alpha2_from_tan2_perturbation(t * t), sqr(ggx_alpha_from_variance(sigma * sigma)), 1e-15);
    EXPECT_NEAR(alpha2_from_cos_perturbation(std::cos(deg * kDeg)), t * t / 8, 1e-13);
    EXPECT_NEAR(alpha2_from_normals(Vec3d(0, 0, 1), tilt({0, 0, 1}, deg * kDeg, 0.7)), t * t / 8, 1e-13);
  }
  // Clamp: α² = 1 from tan²θ_d = 8, θ_d = atan(2√2) = 70.53°, up to 90°; the cosine sign does not matter.
  const double d_clamp = std::atan(2 * std::sqrt(2.0));
  EXPECT_NEAR(alpha2_from_cos_perturbation(std::cos(d_clamp - 1e-6)), 1.0, 1e-5);
  EXPECT_EQ(alpha2_from_cos_perturbation(std::cos(d_clamp + 1e-6)), 1.0);
  EXPECT_EQ(alpha2_from_cos_perturbation(0.0), 1.0);
  EXPECT_EQ(alpha2_from_cos_perturbation(-0.5), alpha2_from_cos_perturbation(0.5));
  EXPECT_EQ(alpha2_from_cos_perturbation(-1.0), 0.0);  // N_s = −N_g is no perturbation (|cos|, listing 12.1)
  EXPECT_EQ(alpha2_from_cos_perturbation(-1.5), 0.0);
  EXPECT_EQ(alpha2_from_normals(Vec3d(0, 0, 1), Vec3d(1, 0, 0)), 1.0);
  EXPECT_EQ(alpha2_from_normals(Vec3d(0, 0, 1), Vec3d(0, 0, 0)), 0.0);
  EXPECT_EQ(alpha2_from_tan2_perturbation(std::numeric_limits<double>::infinity()), 1.0);
}

// σ² = 2α² is the tangent (slope) variance of the Beckmann NDF with α_b = √2 α (the equivalence of Conty
// Estevez et al. 2019): E[tan²θ_m] = ∫ tan²θ D_b(m) cosθ dω, integrated numerically over θ (midpoint rule in
// t = tanθ).
TEST(BumpVariance, MatchesBeckmannSlopeVarianceNumerically) {
  for (double a : {0.05, 0.2, 0.5}) {
    const double ab = beckmann_alpha_from_ggx(a);
    // D_b cosθ dω = exp(−t²/α_b²)/(π α_b²) · 2π t dt in t = tanθ.
    double sum = 0;
    const int n = 200000;
    const double tmax = 12 * ab, dt = tmax / n;
    for (int i = 0; i < n; ++i) {
      const double t = (i + 0.5) * dt;
      sum += t * t * std::exp(-t * t / (ab * ab)) / (kPi<double> * ab * ab) * 2 * kPi<double> * t * dt;
    }
    EXPECT_NEAR(sum, ggx_variance(a), 1e-9 * ggx_variance(a) + 1e-12);
  }
}

// ---------------------------------------------------------------------------------------------------------
// Hanika 2021 shadow-ray origin.

namespace {
using Tri = std::array<Vec3d, 3>;

// Hanika 2021 (docs/theory.md §4) literally, unit normals: p + Σ b_i (p − p_i − min(0, (p − p_i)·n_i) n_i).
Vec3d hanika_literal(const Vec3d& p, const Tri& pos, const Tri& nrm, const std::array<double, 3>& b) {
  Vec3d out = p;
  for (int i = 0; i < 3; ++i) {
    const Vec3d n = normalize(nrm[i]);
    out += b[i] * (p - pos[i] - std::min(0.0, dot(p - pos[i], n)) * n);
  }
  return out;
}
Vec3d at(const Tri& pos, const std::array<double, 3>& b) {
  return b[0] * pos[0] + b[1] * pos[1] + b[2] * pos[2];
}
std::array<double, 3> random_bary(Pcg32& rng) {
  double u = rng.next_double(), v = rng.next_double();
  if (u + v > 1) u = 1 - u, v = 1 - v;
  return {1 - u - v, u, v};
}
}  // namespace

TEST(BumpHanika, MatchesLiteralFormula) {
  Pcg32 rng(20);
  for (int i = 0; i < 20000; ++i) {
    const Tri pos{random_unit(rng), random_unit(rng), random_unit(rng)};
    const Tri nrm{random_unit(rng) * 3.0, random_unit(rng), random_unit(rng) * 0.5};
    const auto b = random_bary(rng);
    const Vec3d p = at(pos, b);
    const Vec3d got = hanika2021_shadow_origin(p, pos, nrm, b);
    ASSERT_LT(length(got - hanika_literal(p, pos, nrm, b)), 1e-12);
  }
}

TEST(BumpHanika, FlatTriangleIsNotMoved) {
  Pcg32 rng(21);
  for (int i = 0; i < 20000; ++i) {
    const Tri pos{random_unit(rng) * 10.0, random_unit(rng) * 10.0, random_unit(rng) * 10.0};
    const Vec3d n = normalize(cross(pos[1] - pos[0], pos[2] - pos[0]));
    const auto b = random_bary(rng);
    const Vec3d p = at(pos, b);
    for (const Vec3d& nn : {n, -n}) {
      const Vec3d got = hanika2021_shadow_origin(p, pos, {nn, nn, nn}, b);
      ASSERT_LT(length(got - p), 1e-13 * 10.0);
    }
    // float too, with float rounding of the plane.
    const Vec3f pf(p);
    const Vec3f gotf =
        hanika2021_shadow_origin(pf, {Vec3f(pos[0]), Vec3f(pos[1]), Vec3f(pos[2])},
                                 {Vec3f(n), Vec3f(n), Vec3f(n)}, {float(b[0]), float(b[1]), float(b[2])});
    ASSERT_LT(length(gotf - pf), 1e-5f * 10.0f);
  }
}

// A triangle of a coarse sphere tessellation with the sphere's normals at its vertices: the origin moves
// outward (along the face normal), towards the sphere it approximates, and never when the normals say the
// surface is concave (normals flipped inward relative to the face: p is then above every tangent plane).
TEST(BumpHanika, MovesToTheCorrectSide) {
  Pcg32 rng(22);
  for (int i = 0; i < 5000; ++i) {
    const Vec3d c = random_unit(rng);
    const Framed f = Framed::from_z(c);
    const double spread = 0.2 + 0.5 * rng.next_double();  // vertices about 11°–40° from the centre
    Tri pos;
    for (int k = 0; k < 3; ++k)
      pos[k] = f.to_world(
          spherical_direction(std::cos(spread), 2 * kPi<double> * k / 3 + 0.3 * rng.next_double()));
    Vec3d nface = normalize(cross(pos[1] - pos[0], pos[2] - pos[0]));
    if (dot(nface, c) < 0) nface = -nface;
    const auto b = random_bary(rng);
    const Vec3d p = at(pos, b);
    const Vec3d q = hanika2021_shadow_origin(p, pos, pos, b);  // sphere normals = positions
    ASSERT_GE(dot(q - p, nface), 0.0);
    ASSERT_LE(std::abs(length(q) - 1), std::abs(length(p) - 1) + 1e-12);  // closer to the sphere
    if (std::min({b[0], b[1], b[2]}) > 0.05) {
      ASSERT_GT(dot(q - p, nface), 0.0);  // interior points do move
    }
    // Concave: inward normals (a spherical cavity seen from inside): no move.
    const Vec3d qc = hanika2021_shadow_origin(p, pos, {-pos[0], -pos[1], -pos[2]}, b);
    ASSERT_LT(length(qc - p), 1e-15);
  }
}

// Two triangles sharing the edge (A, B) with the same vertex normals there: the offset point is continuous.
TEST(BumpHanika, ContinuousAcrossSharedEdge) {
  Pcg32 rng(23);
  for (int i = 0; i < 5000; ++i) {
    const Vec3d A = random_unit(rng), B = random_unit(rng), C = random_unit(rng), D = random_unit(rng);
    const Vec3d nA = random_unit(rng), nB = random_unit(rng), nC = random_unit(rng), nD = random_unit(rng);
    const Tri t1{A, B, C}, n1{nA, nB, nC}, t2{B, A, D}, n2{nB, nA, nD};
    const double s = rng.next_double();
    // On the edge: the same point from both triangles' barycentrics.
    const std::array<double, 3> b1{1 - s, s, 0}, b2{s, 1 - s, 0};
    const Vec3d p1 = at(t1, b1), p2 = at(t2, b2);
    ASSERT_LT(length(hanika2021_shadow_origin(p1, t1, n1, b1) - hanika2021_shadow_origin(p2, t2, n2, b2)),
              1e-14);
    // Approaching the edge from each side: the gap shrinks linearly with the distance.
    for (double eps : {1e-3, 1e-6}) {
      const std::array<double, 3> c1{1 - s - eps / 2, s - eps / 2, eps},
          c2{s - eps / 2, 1 - s - eps / 2, eps};
      const Vec3d q1 = hanika2021_shadow_origin(at(t1, c1), t1, n1, c1);
      const Vec3d q2 = hanika2021_shadow_origin(at(t2, c2), t2, n2, c2);
      ASSERT_LT(length(q1 - q2), 50 * eps);
    }
  }
}

TEST(BumpHanika, DegenerateNormalsDoNotMoveAndStayFinite) {
  const double nan = std::numeric_limits<double>::quiet_NaN();
  const Tri pos{Vec3d(0, 0, 0), Vec3d(1, 0, 0), Vec3d(0, 1, 0)};
  const Vec3d p(0.25, 0.25, 0);
  const Vec3d q = hanika2021_shadow_origin(p, pos, {Vec3d(0, 0, 0), Vec3d(nan, 0, 1), Vec3d(0, 0, 0)},
                                           std::array<double, 3>{0.5, 0.25, 0.25});
  EXPECT_EQ(q, p);
  // Embree (u, v) overload: b = (1 − u − v, u, v).
  const Tri nrm{Vec3d(-1, -1, 1), Vec3d(1, 0, 1), Vec3d(0, 1, 1)};
  const Vec3d a = hanika2021_shadow_origin(p, pos, nrm, 0.25, 0.25);
  const Vec3d b = hanika2021_shadow_origin(p, pos, nrm, std::array<double, 3>{0.5, 0.25, 0.25});
  EXPECT_EQ(a, b);
  EXPECT_TRUE(is_finite(a));
}

// The registry (bump::kMethods): every method once, names unique and round-tripping through
// parse_method, each viewer expression calling its required function, which the GLSL port defines.
TEST(BumpTerminator, RegistryListsEveryMethodOnce) {
  std::vector<Method> seen;
  std::vector<std::string_view> names;
  for (const MethodInfo& i : kMethods) {
    EXPECT_EQ(std::count(seen.begin(), seen.end(), i.method), 0) << i.name;
    EXPECT_EQ(std::count(names.begin(), names.end(), i.name), 0) << i.name;
    seen.push_back(i.method), names.push_back(i.name);
    Method m{};
    ASSERT_TRUE(parse_method(i.name, m));
    EXPECT_EQ(m, i.method);
    EXPECT_EQ(method_name(i.method), i.name);
    EXPECT_FALSE(i.label.empty() || i.summary.empty() || i.glsl.empty()) << i.name;
    if (!i.requires_fn.empty()) {
      EXPECT_NE(i.glsl.find(i.requires_fn), std::string_view::npos) << i.name;
    }
  }
  for (Method m : {Method::kNone, Method::kConty2019, Method::kChiang2019})
    EXPECT_EQ(std::count(seen.begin(), seen.end(), m), 1);
  Method m{};
  EXPECT_FALSE(parse_method("conty2019", m));
#ifdef MSH_SOURCE_DIR
  std::ifstream in(std::string(MSH_SOURCE_DIR) + "/shaders/glsl/bump_terminator.glsl");
  std::string glsl((std::istreambuf_iterator<char>(in)), std::istreambuf_iterator<char>());
  ASSERT_FALSE(glsl.empty());
  std::ifstream pin(std::string(MSH_SOURCE_DIR) + "/shaders/portable/bump_terminator.h");
  glsl += std::string((std::istreambuf_iterator<char>(pin)), std::istreambuf_iterator<char>());
  for (const MethodInfo& i : kMethods) {
    if (!i.requires_fn.empty()) {
      EXPECT_NE(glsl.find(std::string(i.requires_fn) + "("), std::string::npos) << i.requires_fn;
    }
  }
#endif
}

// ---------------------------------------------------------------------------------------------------------
// Command line: `eval bump-terminator` and `plot bump-terminator`.
#ifdef MSH_CLI_PATH
#include <sys/wait.h>

#include <cstdio>
#include <filesystem>
#include <fstream>
#include <nlohmann/json.hpp>
#include <sstream>

namespace {
struct CliRun {
  int code = -1;
  std::string out, err;
};
CliRun run_cli(const std::string& args) {
  const std::string err_path = std::string(MSH_BINARY_DIR) + "/test_bump_cli_stderr.txt";
  const std::string cmd = std::string(MSH_CLI_PATH) + " " + args + " 2>" + err_path;
  CliRun r;
  FILE* f = popen(cmd.c_str(), "r");
  if (!f) return r;
  char buf[4096];
  size_t n;
  while ((n = fread(buf, 1, sizeof buf, f)) > 0) r.out.append(buf, n);
  const int st = pclose(f);
  r.code = WIFEXITED(st) ? WEXITSTATUS(st) : -1;
  std::ifstream e(err_path);
  std::stringstream ss;
  ss << e.rdbuf();
  r.err = ss.str();
  return r;
}
}  // namespace

std::string vec_arg(const Vec3d& v) {
  char b[128];
  std::snprintf(b, sizeof b, "%.17g,%.17g,%.17g", v.x, v.y, v.z);
  return b;
}

TEST(BumpCli, EvalPrintsTheLibraryValue) {
  struct Case {
    const char* method;
    Method m;
    Vec3d ng, ns, l;
    bool hemi;
  };
  const Case cases[] = {{"conty-2019", Method::kConty2019, {0, 0, 1}, {0.5, 0, 1}, {1, 0, 0.1}, false},
                        {"chiang-2019", Method::kChiang2019, {0, 0, 2}, {0.5, 0.2, 1}, {1, 0.3, 0.2}, false},
                        {"conty-2019", Method::kConty2019, {0.1, 0.2, 3}, {-0.4, 0.1, 1}, {-3, 1, -1}, false},
                        {"conty-2019", Method::kConty2019, {0.1, 0.2, 3}, {-0.4, 0.1, 1}, {-3, 1, -1}, true},
                        {"chiang-2019", Method::kChiang2019, {0, 0, 1}, {0.3, 0, 1}, {1, 0, 0.05}, true}};
  for (const Case& c : cases) {
    const CliRun r = run_cli("eval bump-terminator --method " + std::string(c.method) +
                             " --geometric-normal " + vec_arg(c.ng) + " --shading-normal " + vec_arg(c.ns) +
                             " --light " + vec_arg(c.l) + (c.hemi ? " --hemisphere-test" : "") + " --json");
    ASSERT_EQ(r.code, 0) << r.err;
    const auto j = nlohmann::json::parse(r.out);
    const double want = term(c.m, normalize(c.ng), normalize(c.ns), normalize(c.l), c.hemi ? kOn : kOff);
    EXPECT_NEAR(j.at("value").get<double>(), want, 1e-15) << r.out;
    EXPECT_EQ(j.at("method").get<std::string>(), c.method);
  }
  // Hand-computed: tanθ_d = 0.5 → α² = 1/32; tanθ_i = 10 → G = 2/(1 + sqrt(1 + 100/32)).
  const CliRun r = run_cli(
      "eval bump-terminator --method conty-2019 --geometric-normal 0,0,1 --shading-normal 0.5,0,1 "
      "--light 1,0,0.1 --json");
  const auto j = nlohmann::json::parse(r.out);
  EXPECT_NEAR(j.at("value").get<double>(), 2 / (1 + std::sqrt(1 + 100.0 / 32)), 1e-14);
  EXPECT_NEAR(j.at("alpha2").get<double>(), 1.0 / 32, 1e-15);
}

TEST(BumpCli, BadInputIsOneLineAndExitCode2) {
  for (const char* args :
       {"eval bump-terminator --method conty-2019 --shading-normal 0,0,0 --light 1,0,1 --json",
        "eval bump-terminator --method chiang-2019 --shading-normal nan,0,1 --light 1,0,1 --json",
        "eval bump-terminator --method conty-2019 --shading-normal 0,0,1 --light 1,0,inf --json",
        "eval bump-terminator --method conty-2019 --geometric-normal 0,0 --shading-normal 0,0,1 --light "
        "1,0,1",
        "eval bump-terminator --method conty-2019 --geometric-normal 0,0,0 --shading-normal 0,0,1 --light "
        "1,0,1",
        "eval bump-terminator --method foo-2020 --shading-normal 0,0,1 --light 1,0,1",
        "eval bump-terminator --method conty-2019 --light 1,0,1", "plot bump-terminator"}) {
    const CliRun r = run_cli(args);
    EXPECT_EQ(r.code, 2) << args;
    EXPECT_TRUE(r.out.empty()) << args;
    ASSERT_FALSE(r.err.empty()) << args;
    EXPECT_EQ(r.err.find('\n'), r.err.size() - 1) << args << ": " << r.err;
  }
}

TEST(BumpCli, PlotWritesFigureDataDeterministically) {
  namespace fs = std::filesystem;
  const fs::path d = fs::path(MSH_BINARY_DIR) / "test_bump_plot";
  fs::remove_all(d);
  const CliRun a = run_cli("plot bump-terminator --out " + d.string());
  ASSERT_EQ(a.code, 0) << a.err;
  for (const char* f : {"bump_terminator_curves.csv", "bump_terminator_shading.csv",
                        "bump_terminator_compare.csv", "bump_terminator_compare.json"})
    EXPECT_TRUE(fs::exists(d / f)) << f;
  std::ifstream in(d / "bump_terminator_curves.csv");
  std::string header;
  std::getline(in, header);
  EXPECT_EQ(header, "method,perturbation_deg,phi_deg,light_deg,value");
  // Every CSV value is the library's term at that point (spot check a few rows).
  std::string line;
  int checked = 0;
  for (int row = 0; std::getline(in, line); ++row) {
    if (row % 997 != 0) continue;
    std::stringstream ss(line);
    std::string method, f[4];
    std::getline(ss, method, ',');
    for (auto& x : f) std::getline(ss, x, ',');
    Method m{};
    ASSERT_TRUE(parse_method(method, m)) << line;
    const double d_deg = std::stod(f[0]), phi = std::stod(f[1]), th = std::stod(f[2]), v = std::stod(f[3]);
    const Vec3d ns = spherical_direction(std::cos(d_deg * kDeg), phi * kDeg);
    const Vec3d l = spherical_direction(std::cos(th * kDeg), 0.0);
    EXPECT_NEAR(v, term(m, Vec3d(0, 0, 1), ns, l), 1e-8) << line;
    ++checked;
  }
  EXPECT_GT(checked, 5);
  const CliRun b = run_cli("plot bump-terminator --out " + d.string());
  EXPECT_EQ(a.out, b.out);
}
#endif
