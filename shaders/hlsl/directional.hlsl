// microshadow: directional micro-occlusion (9 or 21 linear channels per texel), the HLSL entry point.
// SM 5.0+: DXC, FXC, glslang's HLSL front end.
// Use: `#include "<share>/shaders/hlsl/directional.hlsl"` (the compiler resolves the includes inside,
// relative to this file).
// The functions, written once for both languages, with sources and precision: shaders/portable/directional.h.
#ifndef MSH_DIRECTIONAL_HLSL
#define MSH_DIRECTIONAL_HLSL
#include "msh_prelude.hlsl"
#include "../portable/directional.h"
#endif  // MSH_DIRECTIONAL_HLSL
