#!/usr/bin/env bash
# Shaders (docs/shaders.md): compile the micro-shadowing GLSL/HLSL includes inside a small engine-style compute
# kernel to SPIR-V, and record the precision measured on the local Vulkan device (lavapipe) by the shader test.
set -euo pipefail
D="$OUT/shaders"
mkdir -p "$D"
GLSLANG="$(command -v glslangValidator || echo /usr/bin/glslangValidator)"
if [ ! -x "$GLSLANG" ]; then
  echo "shaders: glslangValidator missing (Debian glslang-tools), skipped" >&2
  exit 0
fi
# A per-light micro-shadowing pass: LUT (3D, early-out), the 2D LUT, Chan 2018, and a 16-point estimate.
{
  echo '#version 450'
  echo '#extension GL_GOOGLE_include_directive : require'
  echo '#include "micro_shadowing.glsl"'  # with -I shaders/glsl, as a user includes it (docs/shaders.md)
  cat <<'GLSL'
layout(local_size_x = 64) in;
layout(std430, binding = 0) readonly buffer Px { vec4 px[]; };   // (vis, roughness, unused, unused)
layout(std430, binding = 1) readonly buffer Dirs { vec4 dir[]; }; // 2 per pixel: v, l (shading frame)
layout(std430, binding = 2) writeonly buffer Out { vec4 res[]; };
layout(binding = 3) uniform sampler3D ms_lut;
layout(binding = 4) uniform sampler2D ms_lut_2d;
void main() {
  uint i = gl_GlobalInvocationID.x;
  vec3 v = dir[2u * i].xyz, l = dir[2u * i + 1u].xyz;
  float vis = px[i].x, r = px[i].y;
  res[i] = vec4(msh_ms_lut_sample(ms_lut, vis, l.z, v.z, r), msh_ms_lut_sample_2d(ms_lut_2d, vis, l.z, r),
                msh_ms_chan2018(vis, l.z), msh_ms_generic_vndf_estimate(vis, vec2(r * r), v, l, 16, true, 1u));
}
GLSL
} > "$D/micro_shadowing_example.comp"
{
  echo '#include "micro_shadowing.hlsl"'
  cat <<'HLSL'
[[vk::binding(0)]] StructuredBuffer<float4> px;
[[vk::binding(1)]] StructuredBuffer<float4> dir;
[[vk::binding(2)]] RWStructuredBuffer<float4> res;
[[vk::binding(3)]] Texture3D<float4> ms_lut;
[[vk::binding(3)]] SamplerState ms_lut_sampler;
[[vk::binding(4)]] Texture2D<float4> ms_lut_2d;
[[vk::binding(4)]] SamplerState ms_lut_2d_sampler;
[numthreads(64, 1, 1)]
void main(uint3 id : SV_DispatchThreadID) {
  uint i = id.x;
  float3 v = dir[2 * i].xyz, l = dir[2 * i + 1].xyz;
  float vis = px[i].x, r = px[i].y;
  res[i] = float4(msh_ms_lut_sample(ms_lut, ms_lut_sampler, vis, l.z, v.z, r),
                  msh_ms_lut_sample_2d(ms_lut_2d, ms_lut_2d_sampler, vis, l.z, r), msh_ms_chan2018(vis, l.z),
                  msh_ms_generic_vndf_estimate(vis, float2(r * r, r * r), v, l, 16, true, 1u));
}
HLSL
} > "$D/micro_shadowing_example.hlsl"
"$GLSLANG" -V --target-env vulkan1.1 -I"$PWD/shaders/glsl" -o "$D/micro_shadowing_example_glsl.spv" "$D/micro_shadowing_example.comp" > "$D/glslang.log"
"$GLSLANG" -V --target-env vulkan1.1 -I"$PWD/shaders/hlsl" -D -S comp -e main -o "$D/micro_shadowing_example_hlsl.spv" \
  "$D/micro_shadowing_example.hlsl" >> "$D/glslang.log"
# The measured precision (skips the Vulkan part, with the reason, where no device exists).
T="$BUILD/bin/test_shaders_micro_shadowing"
if [ -x "$T" ]; then
  "$T" --gtest_brief=0 > "$D/precision.txt" 2>&1 || { cat "$D/precision.txt" >&2; exit 1; }
fi
echo "shaders: $D/micro_shadowing_example_{glsl,hlsl}.spv, $D/precision.txt" >&2
