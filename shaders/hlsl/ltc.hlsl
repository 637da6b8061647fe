// microshadow: linearly transformed cosines (area lights), the HLSL entry point.
// SM 5.0+: DXC, FXC, glslang's HLSL front end.
// Use: `#include "<share>/shaders/hlsl/ltc.hlsl"` (the compiler resolves the includes inside,
// relative to this file).
// The functions, written once for both languages, with sources and precision: shaders/portable/ltc.h.
#ifndef MSH_LTC_HLSL
#define MSH_LTC_HLSL
#include "msh_prelude.hlsl"
#include "../portable/ltc.h"
#endif  // MSH_LTC_HLSL
