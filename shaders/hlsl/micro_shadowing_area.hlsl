// microshadow: area-light micro-shadowing, the HLSL entry point.
// SM 5.0+: DXC, FXC, glslang's HLSL front end.
// Use: `#include "<share>/shaders/hlsl/micro_shadowing_area.hlsl"` (the compiler resolves the includes inside,
// relative to this file).
// Include shaders/hlsl/micro_shadowing.hlsl and shaders/hlsl/micro_shadowing_fit.hlsl first.
// The functions, written once for both languages, with sources and precision: shaders/portable/micro_shadowing_area.h.
#ifndef MSH_MICRO_SHADOWING_AREA_HLSL
#define MSH_MICRO_SHADOWING_AREA_HLSL
#include "msh_prelude.hlsl"
#include "../portable/micro_shadowing_area.h"
#endif  // MSH_MICRO_SHADOWING_AREA_HLSL
