// microshadow: micro-BRDF-aware micro-shadowing, the HLSL entry point.
// SM 5.0+: DXC, FXC, glslang's HLSL front end.
// Use: `#include "<share>/shaders/hlsl/micro_shadowing_aware.hlsl"` (the compiler resolves the includes inside,
// relative to this file).
// Include shaders/hlsl/micro_shadowing.hlsl first.
// The functions, written once for both languages, with sources and precision: shaders/portable/micro_shadowing_aware.h.
#ifndef MSH_MICRO_SHADOWING_AWARE_HLSL
#define MSH_MICRO_SHADOWING_AWARE_HLSL
#include "msh_prelude.hlsl"
#include "../portable/micro_shadowing_aware.h"
#endif  // MSH_MICRO_SHADOWING_AWARE_HLSL
