#!/usr/bin/env python3
"""SPIR-V cost of each LUT sampler of shaders/glsl/micro_shadowing.glsl (docs/shaders.md, docs/lut.md).

For each method a minimal compute shader calls only that function; glslangValidator compiles it to Vulkan
SPIR-V, spirv-opt -O inlines and optimizes it, and the static instruction count of main (OpLabel, OpPhi,
OpLoopMerge etc. included; OpLine/OpName not) and its image-sample instructions (hardware-filtered fetches,
before any runtime early-out) are printed as a Markdown table. Usage: tools/research/lut_spirv_counts.py
"""
import os
import sys

sys.path.insert(0, os.path.join(os.path.dirname(os.path.abspath(__file__)), "..", "..", "scripts"))
from spirv_cost import KERNEL_HEAD, spirv_cost  # noqa: E402

LIB = '#include "micro_shadowing.glsl"\n'
HEAD = KERNEL_HEAD + """layout(binding = 2) uniform sampler3D lut3;
layout(binding = 3) uniform sampler2D lut2;
"""
METHODS = [
    ("seed 3D (`msh_ms_lut_sample`)", "msh_ms_lut_sample(lut3, a.x, a.y, a.z, a.w)"),
    ("seed 2D (`msh_ms_lut_sample_2d`)", "msh_ms_lut_sample_2d(lut2, a.x, a.y, a.w)"),
    ("seed azimuth-aware, H = 2 (`msh_ms_lut_sample_azimuth`)",
     "msh_ms_lut_sample_azimuth(lut3, 2, a.x, a.y, a.z, a.w, b.x)"),
    ("cone plain (`msh_ms_lut_sample_cone`)", "msh_ms_lut_sample_cone(lut3, 16, a.x, a.y, a.z, a.w)"),
    ("cone azimuth-aware, H = 3 (`msh_ms_lut_sample_cone_azimuth`)",
     "msh_ms_lut_sample_cone_azimuth(lut3, 16, 3, a.x, a.y, a.z, a.w, b.x)"),
]


def count(call):
    src = HEAD + LIB + """
void main() {
  uint i = gl_GlobalInvocationID.x;
  vec4 a = rec[2u * i], b = rec[2u * i + 1u];
  o[i] = %s;
}
""" % call
    return spirv_cost(src)


def main():
    print("| method | SPIR-V instructions (spirv-opt -O) | image samples |")
    print("|---|---|---|")
    for label, call in METHODS:
        n, f = count(call)
        print(f"| {label} | {n} | {f} |")
    return 0


if __name__ == "__main__":
    sys.exit(main())
