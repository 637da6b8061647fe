// Evaluates a few micro-shadowing terms through the header-only core and samples the installed default
// table through the library's loader, against the exact term. Prints one line per value; exits 1 if the
// table disagrees with the exact term by more than its documented accuracy allows (docs/lut.md).
#include <microshadow/io/error.h>  // microshadow::microshadow
#include <microshadow/lut/runtime/micro_shadowing_loader.h>
#include <microshadow/microshadow.h>  // microshadow::core

#include <cmath>
#include <cstdio>
#include <string>

int main(int argc, char** argv) {
  const double V = 0.6, n_dot_l = 0.4, n_dot_v = 0.8, roughness = 0.5;
  std::printf("chan_2018 %.6f\n", msh::micro_shadowing::chan_2018(V, n_dot_l));
  std::printf("brinck_maximov_2016 %.6f\n", msh::micro_shadowing::brinck_maximov_2016(V, n_dot_l));
  const double exact =
      msh::micro_shadowing::generic_vndf_exact_azimuth_mean(V, roughness * roughness, n_dot_l, n_dot_v);
  std::printf("exact %.6f\n", exact);

  const std::string table = argc > 1 ? argv[1] : MSH_TABLE_DIR "/micro_shadowing.ktx2";
  try {
    const msh::lut::MicroShadowingLut lut = msh::lut::load_micro_shadowing_lut(table);
    const double s = msh::lut::sample_micro_shadowing(lut.view(), V, n_dot_l, n_dot_v, roughness);
    std::printf("lut %.6f\n", s);
    // Half-precision table, interpolated between texels: a few 1e-3 is the documented scale of its error.
    if (!(std::abs(s - exact) < 0.01)) {
      std::printf("FAIL: lut - exact = %.6f\n", s - exact);
      return 1;
    }
  } catch (const msh::InputError& e) {
    std::fprintf(stderr, "consumer: %s\n", e.what());
    return 2;
  }
  std::printf("consumer: ok\n");
  return 0;
}
