// Thin-film interference (Belcour & Barla 2017) against an independent brute-force spectral reference: the
// Airy reflectance of the film stack per wavelength (complex Fresnel amplitudes, both polarizations),
// integrated against the CIE 1931 matching functions (Wyman, Sloan & Shirley 2013 multi-lobe fits) every 1 nm
// over 360–830 nm, then the same XYZ → E-balanced Rec.709 conversion. Limits: d = 0 and η2 = 1 give the
// substrate Fresnel (checked against bsdf/fresnel.h's exact formulas).
#include <gtest/gtest.h>
#include <microshadow/bsdf/fresnel.h>
#include <microshadow/bsdf/thin_film.h>

#include <complex>

using namespace msh;
using namespace msh::bsdf;
using C = std::complex<double>;

namespace {

// Wyman et al. 2013 (JCGT 2(2)), multi-lobe piecewise Gaussian fit of the CIE 1931 2° observer.
double g(double x, double mu, double s1, double s2) {
  const double t = (x - mu) / (x < mu ? s1 : s2);
  return std::exp(-0.5 * t * t);
}
double cie_x(double l) {
  return 1.056 * g(l, 599.8, 37.9, 31.0) + 0.362 * g(l, 442.0, 16.0, 26.7) - 0.065 * g(l, 501.1, 20.4, 26.2);
}
double cie_y(double l) { return 0.821 * g(l, 568.8, 46.9, 40.5) + 0.286 * g(l, 530.9, 16.3, 31.1); }
double cie_z(double l) { return 1.217 * g(l, 437.0, 11.8, 36.0) + 0.681 * g(l, 459.0, 26.0, 13.8); }

// Airy reflectance of air | film (n2, d nm) | substrate (n3 + i k3) at wavelength λ (nm), unpolarized.
double airy(double cos1, double lambda, double n2, double d, C n3) {
  const double sin2 = 1 - cos1 * cos1;
  const C c2 = std::sqrt(C(1) - sin2 / (n2 * n2));
  const C c3 = std::sqrt(C(1) - sin2 / (n3 * n3));
  const C n2c(n2);
  // s and p amplitudes (same convention at both interfaces: r_ji = −r_ij).
  const C r12s = (cos1 - n2c * c2) / (cos1 + n2c * c2), r12p = (n2c * cos1 - c2) / (n2c * cos1 + c2);
  const C r23s = (n2c * c2 - n3 * c3) / (n2c * c2 + n3 * c3),
          r23p = (n3 * c2 - n2c * c3) / (n3 * c2 + n2c * c3);
  const C e = std::exp(C(0, 2 * kPi<double> * 2 * n2 * d * std::real(c2) / lambda));
  const C rs = (r12s + r23s * e) / (C(1) + r12s * r23s * e),
          rp = (r12p + r23p * e) / (C(1) + r12p * r23p * e);
  return 0.5 * (std::norm(rs) + std::norm(rp));
}

Rgbd spectral_reference(double cos1, double n2, double d, C n3) {
  double X = 0, Y = 0, Z = 0, Xw = 0, Yw = 0, Zw = 0;
  for (double l = 360; l <= 830; l += 1) {
    const double R = airy(cos1, l, n2, d, n3);
    X += R * cie_x(l), Y += R * cie_y(l), Z += R * cie_z(l);
    Xw += cie_x(l), Yw += cie_y(l), Zw += cie_z(l);
  }
  // Each channel relative to its own white: a flat spectrum gives (R, R, R) in XYZ, as in the B&B
  // normalization.
  return thin_film_fresnel::xyz_to_rgb_ewhite(Rgbd(X / Xw, Y / Yw, Z / Zw));
}

}  // namespace

TEST(ThinFilm, MatchesSpectralReference) {
  struct Sub {
    double n, k;
  };
  double worst = 0, sum = 0;
  int count = 0;
  for (Sub s : {Sub{1.5, 0.0}, Sub{2.0, 0.0}, Sub{2.9, 3.0}, Sub{0.2, 3.5}})
    for (double n2 : {1.33, 1.5, 2.0})
      for (double d : {50.0, 150.0, 300.0, 500.0, 800.0})
        for (double c : {1.0, 0.7, 0.35}) {
          ThinFilm<double> tf;
          tf.thickness_nm = d, tf.film_ior = n2, tf.substrate_ior = s.n, tf.substrate_k = s.k;
          const Rgbd got = tf.reflectance(c);
          Rgbd ref = spectral_reference(c, n2, d, C(s.n, s.k));
          ref = Rgbd(saturate(ref.r), saturate(ref.g), saturate(ref.b));
          for (int i = 0; i < 3; ++i) {
            const double e = std::abs(got[i] - ref[i]);
            worst = std::max(worst, e), sum += e, ++count;
            EXPECT_NEAR(got[i], ref[i], 0.04) << "substrate " << s.n << "+" << s.k << "i film " << n2 << " d "
                                              << d << " cos " << c << " channel " << i;
          }
        }
  std::printf("[thin film vs spectral] max |ΔRGB| = %.4f, mean = %.4f over %d values\n", worst, sum / count,
              count);
}

TEST(ThinFilm, ZeroThicknessIsSubstrateFresnel) {
  for (double c : {1.0, 0.8, 0.5, 0.2, 0.01}) {
    ThinFilm<double> tf;
    tf.thickness_nm = 0, tf.film_ior = 1.6, tf.substrate_ior = 2.9, tf.substrate_k = 3.0;
    const double F = fresnel_conductor(c, 2.9, 3.0);
    const Rgbd r = tf.reflectance(c);
    EXPECT_NEAR(r.r, F, 1e-9);
    EXPECT_NEAR(r.g, F, 1e-9);
    EXPECT_NEAR(r.b, F, 1e-9);
    tf.substrate_k = 0, tf.substrate_ior = 1.5;
    EXPECT_NEAR(tf.reflectance(c).g, fresnel_dielectric(c, 1.5), 1e-9);
  }
}

TEST(ThinFilm, UnitFilmIorIsSubstrateFresnel) {
  for (double d : {10.0, 250.0, 1000.0})
    for (double c : {1.0, 0.6, 0.1}) {
      ThinFilm<double> tf;
      tf.thickness_nm = d, tf.film_ior = 1.0, tf.substrate_ior = 1.8, tf.substrate_k = 0.5;
      const double F = fresnel_conductor(c, 1.8, 0.5);
      EXPECT_NEAR(tf.reflectance(c).r, F, 1e-9) << d << " " << c;
      EXPECT_NEAR(tf.reflectance(c).b, F, 1e-9) << d << " " << c;
    }
}

TEST(ThinFilm, ThickFilmTendsToIncoherentAverage) {
  // Far beyond the coherence length (~1 μm) the fringes average out: B&B's Gaussian-damped terms vanish and
  // the result is the incoherent sum C0 = R12 + T121² R23 / (1 − R12 R23), grey.
  ThinFilm<double> tf;
  tf.thickness_nm = 20000, tf.film_ior = 1.5, tf.substrate_ior = 1.5, tf.substrate_k = 0;
  const Rgbd r = tf.reflectance(1.0);
  const double R12 = sqr(0.5 / 2.5), R23 = 0.0, c0 = R12 + sqr(1 - R12) * R23 / (1 - R12 * R23);
  EXPECT_NEAR(r.r, c0, 1e-6);
  EXPECT_NEAR(r.g, c0, 1e-6);
  // Film over an index-matched substrate (η3 = η2): just the air/film interface.
  EXPECT_NEAR(r.b, fresnel_dielectric(1.0, 1.5), 1e-6);
}

TEST(ThinFilm, FiniteAndBounded) {
  for (float d : {0.0f, 1e-3f, 30.0f, 5000.0f, 1e7f})
    for (float c : {-1.0f, 0.0f, 1e-8f, 0.5f, 1.0f, 2.0f}) {
      ThinFilm<float> tf;
      tf.thickness_nm = d;
      tf.film_ior = 0.5f;  // clamped to 1
      const Rgb<float> r = tf.reflectance(c);
      EXPECT_TRUE(is_finite(r));
      EXPECT_GE(min_component(r), 0.0f);
      EXPECT_LE(max_component(r), 1.0f);
    }
}
