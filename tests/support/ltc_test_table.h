// The small LTC tables of the LTC shader tests (test_shaders_ltc, test_shaders_ltc_micro_shadowing): fitted
// by the library in the test (msh::fit_ltc_table) with each test's quick options.
#pragma once

#include <microshadow/bsdf/runtime/ltc_baker.h>

namespace msh::test {

inline bsdf::LtcTable small_ltc_table(int size, int error_samples, int max_iterations, int moment_samples) {
  bsdf::LtcFitOptions o;
  o.size = size, o.error_samples = error_samples, o.max_iterations = max_iterations;
  o.moment_samples = moment_samples;
  return bsdf::fit_ltc_table(o);
}

}  // namespace msh::test
