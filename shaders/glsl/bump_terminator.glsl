// microshadow: bump-terminator terms, the GLSL entry point.
// GLSL 4.00+ / GLSL ES 3.20 (`precise`); GLSL ES 3.00 (WebGL2) without it; OpenGL, Vulkan.
// No #version line. Use: after your #version, `#extension GL_GOOGLE_include_directive : require` then
// `#include "<share>/shaders/glsl/bump_terminator.glsl"` (glslang; glslc/shaderc enable the directive
// themselves), or the text with its includes expanded (what the viewer serves; `microshadow view --export
// DIR` writes it to DIR/shaders/glsl/).
// The functions, written once for both languages, with sources and precision: shaders/portable/bump_terminator.h.
#ifndef MSH_BUMP_TERMINATOR_GLSL
#define MSH_BUMP_TERMINATOR_GLSL
#include "msh_prelude.glsl"
#include "../portable/bump_terminator.h"
#endif  // MSH_BUMP_TERMINATOR_GLSL
