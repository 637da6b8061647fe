#!/usr/bin/env python3
"""The one SPIR-V static cost counter of the project (scripts/method_costs.py, tests/test_shaders_directional.cpp,
tools/research/lut_spirv_counts.py and tools/research/count_micro_shadowing_fit_ops.sh all call it).

glslangValidator compiles the GLSL compute source (includes from shaders/glsl) to Vulkan SPIR-V, spirv-opt -O
inlines and optimizes it, and the instructions of the functions left are counted:
- instructions: every instruction from OpFunction to OpFunctionEnd (OpLabel, OpPhi, OpLoopMerge etc.
  included; OpLine, OpNoLine, OpName and decorations not);
- arithmetic: the float and vector arithmetic, one rule for every caller: the OpF* instructions (add, sub,
  mul, div, negate, rem, mod and the OpFOrd*/OpFUnord* comparisons; not OpFunction*), OpDot,
  OpVectorTimesScalar, OpMatrixTimes*, OpVectorTimesMatrix, OpSelect and every GLSL.std.450 extended
  instruction (FMax, Fma, Sqrt, ...), counted under the extended instruction's name;
- image_samples: the OpImageSample* instructions (hardware-filtered fetches, before any runtime early-out).

Usage: scripts/spirv_cost.py KERNEL.comp [--json]   (prints the counts and the arithmetic by opcode)
"""
import json, os, re, subprocess, sys, tempfile

ROOT = os.path.dirname(os.path.dirname(os.path.abspath(__file__)))
INC = os.path.join(ROOT, "shaders/glsl")
SKIP = {"OpLine", "OpNoLine", "OpName", "OpSource", "OpDecorate", "OpMemberName", "OpMemberDecorate"}
VECTOR_ARITH = {"OpDot", "OpVectorTimesScalar", "OpMatrixTimesScalar", "OpMatrixTimesVector",
                "OpMatrixTimesMatrix", "OpVectorTimesMatrix", "OpSelect"}
# The start of every counting kernel: records `vec4 rec[]` in, one float per invocation `o[]` out, 64
# invocations a group. Callers add their sampler bindings (from 2), #includes and main().
KERNEL_HEAD = """#version 450
#extension GL_GOOGLE_include_directive : require
layout(local_size_x = 64) in;
layout(std430, binding = 0) readonly buffer In { vec4 rec[]; };
layout(std430, binding = 1) writeonly buffer Out { float o[]; };
"""


def is_arithmetic(op):
    """Whether opcode `op` (or a GLSL.std.450 instruction name, which has no 'Op' prefix) is arithmetic."""
    if not op.startswith("Op"):
        return True  # an extended instruction
    if op.startswith("OpF") and not op.startswith("OpFunction"):
        return True
    return op in VECTOR_ARITH


def count_disassembly(dis):
    """The counts of spirv-dis output `dis` (text): a dict of instructions, arithmetic, image_samples, ops."""
    total, arith, samples, ops, inside = 0, 0, 0, {}, False
    for line in dis.splitlines():
        words = line.split()
        op = next((w for w in words if w.startswith("Op")), None)
        if op == "OpFunction":
            inside = True
        if inside and op is not None and op not in SKIP:
            total += 1
            if op == "OpExtInst":  # %r = OpExtInst %type %set Name args...
                op = words[words.index("OpExtInst") + 3]
            if is_arithmetic(op):
                arith += 1
                ops[op] = ops.get(op, 0) + 1
            samples += op.startswith("OpImageSample")
        if op == "OpFunctionEnd":
            inside = False
    return {"instructions": total, "arithmetic": arith, "image_samples": samples, "ops": ops}


def spirv_counts(src):
    """The counts (count_disassembly) of the compute shader source `src`."""
    with tempfile.TemporaryDirectory() as d:
        comp, spv, opt = (os.path.join(d, n) for n in ("s.comp", "s.spv", "o.spv"))
        open(comp, "w").write(src)
        subprocess.run(["glslangValidator", "-V", "-I" + INC, "-S", "comp", comp, "-o", spv], check=True,
                       stdout=subprocess.DEVNULL)
        subprocess.run(["spirv-opt", "-O", spv, "-o", opt], check=True)
        dis = subprocess.run(["spirv-dis", "--raw-id", opt], check=True, capture_output=True, text=True).stdout
    return count_disassembly(dis)


def spirv_cost(src):
    """(instructions, image samples) of the compute shader source `src`."""
    c = spirv_counts(src)
    return c["instructions"], c["image_samples"]


def main(argv):
    if len(argv) < 2 or argv[1] in ("-h", "--help"):
        print(__doc__.strip())
        return 0 if len(argv) >= 2 else 2
    c = spirv_counts(open(argv[1]).read())
    if "--json" in argv[2:]:
        print(json.dumps(c, sort_keys=True))
    else:
        hist = ", ".join(f"{op} {n}" for op, n in sorted(c["ops"].items()))
        print(f"{c['instructions']} instructions, {c['arithmetic']} arithmetic ({hist}), "
              f"{c['image_samples']} image samples")
    return 0


if __name__ == "__main__":
    sys.exit(main(sys.argv))
