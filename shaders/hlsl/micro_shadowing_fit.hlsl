// microshadow: ALU-only generic VNDF micro-shadowing fits, the HLSL entry point.
// SM 5.0+: DXC, FXC, glslang's HLSL front end.
// Use: `#include "<share>/shaders/hlsl/micro_shadowing_fit.hlsl"` (the compiler resolves the includes inside,
// relative to this file).
// The functions, written once for both languages, with sources and precision: shaders/portable/micro_shadowing_fit.h.
#ifndef MSH_MICRO_SHADOWING_FIT_HLSL
#define MSH_MICRO_SHADOWING_FIT_HLSL
#include "msh_prelude.hlsl"
#include "../portable/micro_shadowing_fit.h"
#endif  // MSH_MICRO_SHADOWING_FIT_HLSL
