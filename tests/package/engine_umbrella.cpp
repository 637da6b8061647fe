// The engine surface (<microshadow/engine.h>) alone, compiled with -Wall -Wextra -Werror and linked against
// nothing but microshadow::engine (cmake/install.cmake). It evaluates what an engine calls against facts
// that do not come from the code under test.
#include <microshadow/engine.h>

#include <cmath>
#include <cstdio>

int main() {
  namespace ms = msh::micro_shadowing;
  int failures = 0;
  const auto check = [&](bool ok, const char* what) {
    if (!ok) std::printf("FAIL: %s\n", what), ++failures;
  };
  // The early-out is exact: 2V + N·L < 1 means no light (the cone test needs angle(n, l) < 2θ).
  check(ms::exact_zero(0.2f, 0.5f) && !ms::exact_zero(0.3f, 0.5f), "exact_zero");
  // Chan 2018 at V = 1 is 1; the ALU fit of the generic term is 0 inside the early-out and 1 at V = 1.
  check(ms::chan_2018(1.0f, 0.3f) == 1.0f, "chan_2018");
  check(ms::generic_vndf_alu(0.2f, 0.5f, 0.7f, 0.5f) == 0.0f, "generic_vndf_alu early-out");
  check(std::abs(ms::generic_vndf_alu(1.0f, 0.5f, 0.7f, 0.5f) - 1.0f) < 1e-3f, "generic_vndf_alu at V = 1");
  // Directional occlusion of a flat surface (transport = N·L): the term is 1.
  const float flat[msh::directional::kDirectionalChannels] = {0, 0, 0, 1, 0, 0, 0, 0, 0};
  const msh::Vec3f l(0.6f, 0.0f, 0.8f), n(0, 0, 1);
  check(std::abs(msh::directional::directional_term(flat, l, n) - 1.0f) < 1e-6f, "directional flat");
  if (failures == 0) std::printf("engine umbrella: ok\n");
  return failures == 0 ? 0 : 1;
}
