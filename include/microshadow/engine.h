// microshadow's engine surface: the run-time forms an engine calls, written once (CMake: microshadow::engine;
// docs/packaging.md). They are the shaders' own source, shaders/portable/*.h, compiled as C++ through the C++
// prelude of the portable dialect (<microshadow/shader/portable.h>, docs/shaders.md), in namespace
// msh::shader with the shader names: a C++ engine and its GLSL/HLSL shaders run the same functions.
//  - closed-form micro-shadowing terms and the exact early-out (msh_ms_reference_step, msh_ms_chan2018, ...,
//    msh_ms_exact_zero), the generic term's VNDF estimator (msh_ms_generic_vndf_estimate) and the samplers of
//    the tables we bake and install (msh_ms_lut_sample*, on a Texture2D/Texture3D view of the texels);
//  - the ALU-only fits of the generic and the diffuse-aware terms, the specular-aware closed form;
//  - the area-light forms (cap and LTC);
//  - directional micro-occlusion's run-time reconstruction (msh_dir_*);
//  - the bump-terminator terms (msh_bump_*) and GGX (msh_ggx_*).
// float32, header-only, C++20 standard library only, no I/O, no threads. The templated C++ forms of the same
// math (occlusion/, bsdf/, lut/, microfacet/; microshadow::core) are the references these are measured
// against (tests/test_shader_portable_cpp.cpp), and the library's own (double-precision) path.
// tests/package/check_core_headers.cmake checks that this header's include closure holds no reference/ or
// runtime/ header.
#pragma once

#include <microshadow/shader/portable.h>
