// The inputs on which the shader tests compare the GLSL/HLSL ports of the ALU fits with the C++ code
// (tests/test_shaders_micro_shadowing_fit.cpp, tests/test_shaders_micro_shadowing_aware_fit.cpp).
#pragma once

#include <microshadow/math/sampling.h>

#include <cmath>
#include <string>
#include <vector>

#include "shader_kernel.h"

namespace msh::test {

struct FitInput {
  float vis, nl, nv, r;
};

// 2^14 uniform random inputs over the domain (roughness also below 0.1), the early-out boundary
// 2 vis + N.L = 1 (and, with `nv_boundaries`, 2 vis + N.V = 1), the cone boundary N.L = cos_t (likewise for
// N.V), and degenerate values (0, 1, outside [0, 1], tiny).
inline std::vector<FitInput> fit_inputs(bool nv_boundaries) {
  std::vector<FitInput> recs;
  Pcg32 rng(909);
  auto u = [&] { return rng.next_float(); };
  for (int i = 0; i < (1 << 14); ++i) recs.push_back({u(), 1 - u(), 1 - u(), u()});
  for (int i = 0; i < 512; ++i) {
    const float vis = u();
    const float nl = i % 2 ? 1.0f - 2.0f * vis : std::sqrt(1.0f - vis);
    recs.push_back({vis, nl, u(), u()});
    if (nv_boundaries) recs.push_back({vis, u(), nl, u()});
  }
  const float vals[] = {0.0f, 1.0f, -0.5f, 2.0f, 1e-7f, 0.5f, 0.999999f};
  for (float a : vals)
    for (float b : vals)
      for (float c : vals)
        for (float d : {0.0f, 1e-6f, 0.1f, 1.0f, 1.5f}) recs.push_back({a, b, c, d});
  return recs;
}

// The fit tests' kernel around shader library `library`: record i is a FitInput read as the vec4 r = (vis,
// N.L, N.V, roughness); o[i] (of GLSL type `out_type`) = `value`, a GLSL expression in r (respelled for HLSL
// by vk::hlsl_spelling).
inline vk::Kernel fit_kernel(const std::string& library, const std::string& out_type,
                             const std::string& value) {
  return vk::framed_kernel({library}, {{"in vec4 rec", "out " + out_type + " o"}, {}, ""}, "",
                           "  vec4 r = rec[i];\n  o[i] = " + value + ";\n");
}

}  // namespace msh::test
