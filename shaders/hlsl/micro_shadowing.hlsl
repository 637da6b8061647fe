// microshadow: micro-shadowing terms and LUT samplers, the HLSL entry point.
// SM 5.0+: DXC, FXC, glslang's HLSL front end.
// Use: `#include "<share>/shaders/hlsl/micro_shadowing.hlsl"` (the compiler resolves the includes inside,
// relative to this file).
// The functions, written once for both languages, with sources and precision: shaders/portable/micro_shadowing.h.
#ifndef MSH_MICRO_SHADOWING_HLSL
#define MSH_MICRO_SHADOWING_HLSL
#include "msh_prelude.hlsl"
#include "../portable/hash.h"
#include "../portable/micro_shadowing.h"
#endif  // MSH_MICRO_SHADOWING_HLSL
