// microshadow: micro-shadowing terms and LUT samplers, the GLSL entry point.
// GLSL 4.50 / GLSL ES 3.20 and GLSL ES 3.00 (WebGL2); OpenGL, Vulkan.
// No #version line. Use: after your #version, `#extension GL_GOOGLE_include_directive : require` then
// `#include "<share>/shaders/glsl/micro_shadowing.glsl"` (glslang; glslc/shaderc enable the directive
// themselves), or the text with its includes expanded (what the viewer serves; `microshadow view --export
// DIR` writes it to DIR/shaders/glsl/).
// The functions, written once for both languages, with sources and precision: shaders/portable/micro_shadowing.h.
#ifndef MSH_MICRO_SHADOWING_GLSL
#define MSH_MICRO_SHADOWING_GLSL
#include "msh_prelude.glsl"
#include "../portable/hash.h"
#include "../portable/micro_shadowing.h"
#endif  // MSH_MICRO_SHADOWING_GLSL
