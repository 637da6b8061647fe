// The umbrella header alone, compiled with -Wall -Wextra -Werror and linked against nothing but
// microshadow::core (tests/package, built by cmake/install.cmake). It also evaluates a few core functions
// against independent facts, so that a header that compiles but is broken in this context fails too.
#include <microshadow/microshadow.h>

#include <cmath>
#include <cstdio>

int main() {
  int failures = 0;
  const auto check = [&](bool ok, const char* what) {
    if (!ok) std::printf("FAIL: %s\n", what), ++failures;
  };
  // GGX is normalized: ∫ D(m) cos θm dω = 1 (Walter et al. 2007, "Microfacet Models for Refraction"), by
  // Gauss–Legendre over μ = cos θm (isotropic: the azimuth integral is 2π).
  const msh::GGX<double> ggx(0.3);
  const double norm = msh::gauss_legendre_01<double>(64, [&](double mu) {
    const double s = std::sqrt(1 - mu * mu);
    return 2 * msh::kPi<double> * ggx.D(msh::Vec3d(s, 0, mu)) * mu;
  });
  check(std::abs(norm - 1) < 1e-6, "GGX normalization");
  // The closed-form micro-shadowing terms at their documented limits: Chan 2018 is 1 for a fully visible
  // hemisphere, Brinck & Maximov 2016 is N·L + 2V² − 1 inside [0, 1].
  check(msh::micro_shadowing::chan_2018(1.0, 0.3) == 1.0, "chan_2018 at V = 1");
  check(std::abs(msh::micro_shadowing::brinck_maximov_2016(0.75, 0.5) - 0.625) < 1e-15,
        "brinck_maximov_2016");
  // The exact term is 1 at V = 1 and 0 where 2V + N·L < 1.
  check(msh::micro_shadowing::generic_vndf_exact_azimuth_mean(1.0, 0.25, 0.5, 0.7) == 1.0,
        "exact term at V = 1");
  check(msh::micro_shadowing::generic_vndf_exact_azimuth_mean(0.2, 0.25, 0.5, 0.7) == 0.0,
        "exact term below the cone");
  if (failures == 0) std::printf("core umbrella: ok\n");
  return failures == 0 ? 0 : 1;
}
