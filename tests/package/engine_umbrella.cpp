// The engine surface (<microshadow/engine.h>) alone, compiled with -Wall -Wextra -Werror and linked against
// nothing but microshadow::engine (cmake/install.cmake). It evaluates what an engine calls (the shaders'
// portable functions compiled as C++) against facts that do not come from the code under test.
#include <microshadow/engine.h>

#include <cmath>
#include <cstdio>

int main() {
  using namespace msh::shader;
  int failures = 0;
  const auto check = [&](bool ok, const char* what) {
    if (!ok) std::printf("FAIL: %s\n", what), ++failures;
  };
  // The early-out is exact: 2V + N·L < 1 means no light (the cone test needs angle(n, l) < 2θ).
  check(msh_ms_exact_zero(0.2f, 0.5f) && !msh_ms_exact_zero(0.3f, 0.5f), "exact_zero");
  // Chan 2018 at V = 1 is 1; at V = 0.75 the cone has cos_t = 0.5, so N.L = 0.25 gives (0.25 / 0.5)^2.
  check(msh_ms_chan2018(1.0f, 0.3f) == 1.0f, "chan_2018 at V = 1");
  check(msh_ms_chan2018(0.75f, 0.25f) == 0.25f, "chan_2018 at V = 0.75");
  // The ALU fit of the generic term is 0 inside the early-out and 1 at V = 1.
  check(msh_ms_generic_vndf_alu(0.2f, 0.5f, 0.7f, 0.5f) == 0.0f, "generic_vndf_alu early-out");
  check(std::abs(msh_ms_generic_vndf_alu(1.0f, 0.5f, 0.7f, 0.5f) - 1.0f) < 1e-3f,
        "generic_vndf_alu at V = 1");
  // Directional occlusion of a flat surface (transport = N·L): the term is 1.
  float flat[9] = {0, 0, 0, 1, 0, 0, 0, 0, 0};
  const float3 l(0.6f, 0.0f, 0.8f), n(0, 0, 1);
  check(std::abs(msh_dir_term(flat, l, n) - 1.0f) < 1e-6f, "directional flat");
  // The bump terminator is exactly 1 where the shading normal is the geometric one.
  check(msh_bump_conty2019(n, n, l, true) == 1.0f, "bump conty-2019, unperturbed");
  if (failures == 0) std::printf("engine umbrella: ok\n");
  return failures == 0 ? 0 : 1;
}
