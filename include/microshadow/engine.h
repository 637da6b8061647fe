// microshadow's engine surface: what shader-side engine code ports or calls at run time, and nothing else
// (CMake: microshadow::engine; docs/packaging.md). C++20 standard library only, header-only, no I/O, no
// threads; every function here has a GLSL/HLSL twin in shaders/ (docs/shaders.md) except where noted.
//  - closed-form micro-shadowing terms and the exact early-out (occlusion/micro_shadowing.h,
//    occlusion/micro_shadowing_early_out.h; the VNDF-sampled term there is Zurita 2026's shader loop);
//  - the ALU-only fits of the generic and the diffuse-aware terms (micro_shadowing_fit.h,
//    micro_shadowing_aware_fit.h) and the specular-aware closed form (micro_shadowing_aware.h);
//  - the samplers of the tables we bake and install (lut/micro_shadowing_lut.h);
//  - the area-light forms (occlusion/micro_shadowing_area.h, bsdf/ltc.h, bsdf/ltc_shading.h);
//  - directional micro-occlusion's run-time reconstruction (occlusion/directional.h; shaders: directional.*);
//  - the bump-terminator terms (occlusion/bump_terminator.h) and GGX (microfacet/ggx.h, roughness.h).
// Not here: the exact references and quadratures (reference/), the bakers, loaders, renderer and study
// (the library, microshadow::microshadow). tests/package/check_core_headers.cmake checks that this header's
// include closure holds no reference/ or runtime/ header.
#pragma once

#include <microshadow/bsdf/ltc.h>
#include <microshadow/bsdf/ltc_shading.h>
#include <microshadow/lut/micro_shadowing_lut.h>
#include <microshadow/microfacet/ggx.h>
#include <microshadow/microfacet/roughness.h>
#include <microshadow/occlusion/bump_terminator.h>
#include <microshadow/occlusion/directional.h>
#include <microshadow/occlusion/micro_shadowing.h>
#include <microshadow/occlusion/micro_shadowing_area.h>
#include <microshadow/occlusion/micro_shadowing_aware.h>
#include <microshadow/occlusion/micro_shadowing_aware_fit.h>
#include <microshadow/occlusion/micro_shadowing_early_out.h>
#include <microshadow/occlusion/micro_shadowing_fit.h>
