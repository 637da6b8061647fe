// microshadow: bump-terminator terms, the HLSL entry point.
// SM 5.0+: DXC, FXC, glslang's HLSL front end.
// Use: `#include "<share>/shaders/hlsl/bump_terminator.hlsl"` (the compiler resolves the includes inside,
// relative to this file).
// The functions, written once for both languages, with sources and precision: shaders/portable/bump_terminator.h.
#ifndef MSH_BUMP_TERMINATOR_HLSL
#define MSH_BUMP_TERMINATOR_HLSL
#include "msh_prelude.hlsl"
#include "../portable/bump_terminator.h"
#endif  // MSH_BUMP_TERMINATOR_HLSL
