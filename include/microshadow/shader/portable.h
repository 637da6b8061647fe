// The run-time forms, written once: shaders/portable/*.h (the functions the GLSL and HLSL shaders run)
// compiled as C++ through the C++ prelude (<microshadow/shader/cpp_prelude.h>), in namespace msh::shader
// with the shaders' own names: msh::shader::msh_ms_chan2018(vis, n_dot_l) is the same source as the GLSL
// and HLSL msh_ms_chan2018. Each function's source, domain and float32 precision are in the comment above
// it in shaders/portable/; docs/shaders.md says how the three builds are checked against each other and
// against the double-precision references (include/microshadow/occlusion, bsdf, lut).
// Include directory: the folder holding shaders/portable (the repository root; installed,
// <prefix>/share/microshadow), which the CMake targets microshadow::core and microshadow::engine and
// microshadow-core.pc add. Every function is `inline` (MSH_FN).
#pragma once

#include <microshadow/shader/cpp_prelude.h>

namespace msh::shader {
// In the order the GLSL entry points require (each module's top comment names what it needs first).
// clang-format off
#include <shaders/portable/hash.h>
#include <shaders/portable/micro_shadowing.h>
#include <shaders/portable/micro_shadowing_fit.h>
#include <shaders/portable/micro_shadowing_area.h>
#include <shaders/portable/micro_shadowing_aware.h>
#include <shaders/portable/micro_shadowing_aware_fit.h>
#include <shaders/portable/ltc.h>
#include <shaders/portable/directional.h>
#include <shaders/portable/bump_terminator.h>
// clang-format on
}  // namespace msh::shader
