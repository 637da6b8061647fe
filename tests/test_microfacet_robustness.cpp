// Sweep of ≥ 1e6 random and degenerate inputs per public microfacet function (grazing, α = 0, n·v = 0,
// backfacing, the pole, zero vectors): every result must be finite, in float and double.
#include <gtest/gtest.h>
#include <microshadow/microfacet/beckmann.h>
#include <microshadow/microfacet/blinn_phong.h>
#include <microshadow/microfacet/bounded_vndf.h>
#include <microshadow/microfacet/ggx.h>
#include <microshadow/microfacet/gtr.h>
#include <microshadow/microfacet/masking.h>
#include <microshadow/microfacet/roughness.h>

using namespace msh;

namespace {

template <class T>
struct Inputs {
  Pcg32 rng{0x5eed};
  T u() { return rng.next<T>(); }
  // Random unit vector, or a degenerate one 1 time in 4: grazing, pole, backfacing, zero, axis-aligned.
  Vec3<T> dir() {
    const uint32_t k = rng.next_u32() % 16;
    const T phi = T(2) * kPi<T> * u();
    switch (k) {
      case 0:
        return {std::cos(phi), std::sin(phi), T(0)};
      case 1:
        return {T(0), T(0), T(1)};
      case 2:
        return {T(0), T(0), T(-1)};
      case 3:
        return {T(0), T(0), T(0)};
      default:
        return sample_uniform_sphere(Vec2<T>(u(), u()));
    }
  }
  T alpha() {
    const uint32_t k = rng.next_u32() % 8;
    if (k == 0) return T(0);
    if (k == 1) return T(1);
    if (k == 2) return T(1e-7);
    return u() * T(1.2);
  }
  Vec2<T> uv() {
    const uint32_t k = rng.next_u32() % 8;
    if (k == 0) return {T(0), T(0)};
    if (k == 1) return {kOneMinusEpsilon<T>, kOneMinusEpsilon<T>};
    return {u(), u()};
  }
};

template <class T>
bool fin(T x) {
  return std::isfinite(x);
}
template <class T>
bool fin(const Vec3<T>& v) {
  return is_finite(v);
}

constexpr int kN = 1000000;

template <class T, class NDF, class Make>
void sweep_ndf(Make&& make, bool has_vndf_sampler) {
  Inputs<T> in;
  long bad = 0;
  NDF ndf = make(in);
  for (int i = 0; i < kN; ++i) {
    if (i % 1000 == 0) ndf = make(in);
    const Vec3<T> w = in.dir(), l = in.dir(), m = in.dir();
    const Vec2<T> u = in.uv();
    bad += !fin(ndf.D(m)) + !fin(ndf.Lambda(w)) + !fin(ndf.G1(w)) + !fin(ndf.G1(w, m)) + !fin(ndf.G2(w, l)) +
           !fin(ndf.D(w, m)) + !fin(ndf.sample_ndf(u)) + !fin(ndf.pdf_ndf(m)) + !fin(ndf.G1_over_cos(w));
    bad += !fin(G2_separable(ndf, w, l, m)) + !fin(G2_height_correlated(ndf, w, l, m)) +
           !fin(G2_direction_correlated(ndf, w, l, m, lambda_ashikhmin<T>)) +
           !fin(G2_height_direction_correlated(ndf, w, l, m, lambda_van_ginneken<T>));
    if constexpr (requires { ndf.Sample_wm(w, u); }) {
      if (has_vndf_sampler) bad += !fin(ndf.Sample_wm(w, u)) + !fin(ndf.PDF(w, m));
    }
  }
  EXPECT_EQ(bad, 0);
}

// The count of non-finite results that check(in, i) reports over kN draws of fresh inputs.
template <class T, class Check>
long count_non_finite(Check&& check) {
  Inputs<T> in;
  long bad = 0;
  for (int i = 0; i < kN; ++i) bad += check(in, i);
  return bad;
}

}  // namespace

template <class T>
class MicrofacetRobustness : public ::testing::Test {};
using Scalars = ::testing::Types<float, double>;
TYPED_TEST_SUITE(MicrofacetRobustness, Scalars);

TYPED_TEST(MicrofacetRobustness, Ggx) {
  using T = TypeParam;
  sweep_ndf<T, GGX<T>>([](Inputs<T>& in) { return GGX<T>(in.alpha(), in.alpha()); }, true);
  EXPECT_EQ(count_non_finite<T>([](Inputs<T>& in, int i) {
              const GGX<T> g(in.alpha(), in.alpha());
              const Vec3<T> w = in.dir(), m = in.dir();
              const Vec2<T> u = in.uv();
              long bad = !fin(g.sample_vndf_heitz2018(w, u)) + !fin(g.sample_vndf_spherical_caps(w, u)) +
                         !fin(sample_bounded_vndf(g, w, u)) + !fin(pdf_bounded_vndf(g, w, m)) +
                         !fin(pdf_bounded_vndf_reflection(g, w, m)) + !fin(pdf_vndf_reflection(g, w, m));
              const T mo = in.u() * (i % 7 == 0 ? T(0) : T(1)), mi = in.u(), a = in.alpha();
              bad += !fin(ggx_visibility_height_correlated(mo, mi, a)) + !fin(karis_G1(mo, a)) +
                     !fin(hammon_visibility(mo, mi, a)) + !fin(relative_azimuth(w, m));
              T ax, ay;
              alpha_disney_anisotropic(in.u(), in.u(), ax, ay);
              bad += !fin(ax) + !fin(ay);
              alpha_imageworks_anisotropic(in.u(), T(2) * in.u() - T(1), ax, ay);
              return bad + !fin(ax) + !fin(ay);
            }),
            0);
}
TYPED_TEST(MicrofacetRobustness, Beckmann) {
  using T = TypeParam;
  sweep_ndf<T, Beckmann<T>>([](Inputs<T>& in) { return Beckmann<T>(in.alpha(), in.alpha()); }, true);
  EXPECT_EQ(count_non_finite<T>([](Inputs<T>& in, int) {
              const Beckmann<T> b(in.alpha());
              const Vec3<T> w = in.dir();
              return !fin(b.Lambda_approx(w)) + !fin(erf_inv(T(2) * in.u() - T(1)));
            }),
            0);
  EXPECT_EQ(!fin(erf_inv(T(1))) + !fin(erf_inv(T(-1))) + !fin(erf_inv(T(0))), 0);
}
TYPED_TEST(MicrofacetRobustness, BlinnPhong) {
  using T = TypeParam;
  sweep_ndf<T, BlinnPhong<T>>(
      [](Inputs<T>& in) {
        const uint32_t k = in.rng.next_u32() % 4;
        return BlinnPhong<T>(k == 0 ? T(0) : (k == 1 ? T(1e9) : in.u() * T(1000)));
      },
      false);
}
TYPED_TEST(MicrofacetRobustness, Gtr) {
  using T = TypeParam;
  // Few distinct GTRs (each builds its Λ table): α and γ from the extremes of the domain.
  const T as[] = {T(0), T(0.05), T(0.5), T(1)}, gs[] = {T(0.05), T(1), T(2), T(20)};
  std::vector<GTR<T>> gtrs;
  for (T g : gs)
    for (T a : as) gtrs.emplace_back(a, g);
  size_t idx = 0;
  sweep_ndf<T, GTR<T>>([&](Inputs<T>&) { return gtrs[idx++ % gtrs.size()]; }, false);
}

// A NaN α is a precondition violation: the constructors do not turn it into a mirror (kMinAlpha) silently;
// it propagates, so a caller that passes one sees NaN. Finite values below the minimum (and −∞) are clamped.
TYPED_TEST(MicrofacetRobustness, NanAlphaIsNotClampedFiniteAlphaIs) {
  using T = TypeParam;
  const T nan = std::numeric_limits<T>::quiet_NaN(), inf = std::numeric_limits<T>::infinity();
  EXPECT_TRUE(std::isnan(GGX<T>(nan).alpha_x()));
  EXPECT_TRUE(std::isnan(GGX<T>(T(0.3), nan).alpha_y()));
  EXPECT_EQ(GGX<T>(T(0.3), nan).alpha_x(), T(0.3));
  EXPECT_TRUE(std::isnan(Beckmann<T>(nan).alpha_x()));
  EXPECT_TRUE(std::isnan(BlinnPhong<T>(nan).exponent()));
  EXPECT_TRUE(std::isnan(GTR<T>(nan, T(2)).alpha()));
  EXPECT_TRUE(std::isnan(GTR<T>(T(0.5), nan).gamma()));
  EXPECT_TRUE(std::isnan(GGX<T>(nan).D(Vec3<T>(0, 0, 1))));
  for (T a : {T(0), T(-1), -inf, T(1e-30)}) {
    EXPECT_EQ(GGX<T>(a).alpha_x(), GGX<T>::kMinAlpha) << a;
    EXPECT_EQ(Beckmann<T>(a).alpha_y(), Beckmann<T>::kMinAlpha) << a;
    if (!(a > T(0))) {  // αp ≥ 0 is the domain: non-positive values clamp to 0
      EXPECT_EQ(BlinnPhong<T>(a).exponent(), T(0)) << a;
    }
    EXPECT_EQ(GTR<T>(a, T(2)).alpha(), GTR<T>::kMinAlpha) << a;
  }
}
