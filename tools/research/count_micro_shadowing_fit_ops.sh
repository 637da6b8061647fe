#!/usr/bin/env bash
# Arithmetic instruction counts of the ALU-only micro-shadowing shaders (shaders/glsl/micro_shadowing_fit.glsl;
# docs/micro-shadowing.md, "ALU-only approximation"): each function is compiled alone into a compute kernel
# (glslangValidator -V), optimized (spirv-opt -O) and its arithmetic instructions counted by opcode, by the
# project's one counter (scripts/spirv_cost.py, whose rule says what is arithmetic). Needs glslang-tools,
# spirv-tools and python3. Usage: tools/research/count_micro_shadowing_fit_ops.sh
set -euo pipefail
here="$(cd "$(dirname "$0")" && pwd)"
tmp="$(mktemp -d)"
trap 'rm -rf "$tmp"' EXIT
declare -A body=(
  [one-call]='o[i] = msh_ms_generic_vndf_alu(r.x, r.y, r.z, r.w);'
  [pixel]='MshMsAluPixel p = msh_ms_generic_vndf_alu_pixel(r.x, r.z, r.w); o[i] = p.vis + p.c + p.s + p.a2 + p.oma2 + p.inv_st + p.g + p.den;'
  [light]='MshMsAluPixel p = MshMsAluPixel(r.x, r.y, r.z, r.w, q.x, q.y, q.z, q.w); o[i] = msh_ms_generic_vndf_alu_light(p, q.x * q.y);'
)
for f in one-call pixel light; do
  {
    echo '#version 450'
    echo '#extension GL_GOOGLE_include_directive : require'
    echo '#include "micro_shadowing_fit.glsl"'
    echo 'layout(local_size_x = 64) in;'
    echo 'layout(std430, binding = 0) readonly buffer In { vec4 rec[]; };'
    echo 'layout(std430, binding = 1) writeonly buffer Out { float o[]; };'
    echo "void main() { uint i = gl_GlobalInvocationID.x; vec4 r = rec[2u * i]; vec4 q = rec[2u * i + 1u]; ${body[$f]} }"
  } > "$tmp/k.comp"
  # The kernel's own glue (the pixel kernel's 7 adds summing the struct, the light kernel's q.x * q.y) is
  # counted too: subtract it (docs/micro-shadowing.md).
  echo "$f: $(python3 "$here/../../scripts/spirv_cost.py" "$tmp/k.comp")"
done
