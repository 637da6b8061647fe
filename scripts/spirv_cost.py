"""SPIR-V static cost of a compute shader's main after `spirv-opt -O` (scripts/lut_spirv_counts.py,
scripts/method_costs.py): glslangValidator compiles the GLSL source (includes from shaders/glsl) to Vulkan
SPIR-V, spirv-opt -O inlines and optimizes it, and the instructions of the functions left (OpLabel, OpPhi,
OpLoopMerge etc. included; OpLine/OpName/OpDecorate not) and their image samples are counted."""
import os, re, subprocess, tempfile

ROOT = os.path.dirname(os.path.dirname(os.path.abspath(__file__)))
INC = os.path.join(ROOT, "shaders/glsl")
SKIP = re.compile(r"^\s*(OpLine|OpNoLine|OpName|OpSource|OpDecorate|OpMemberName|OpMemberDecorate)")


def spirv_cost(src):
    """(instructions, image samples) of the compute shader source `src`."""
    with tempfile.TemporaryDirectory() as d:
        comp, spv, opt = (os.path.join(d, n) for n in ("s.comp", "s.spv", "o.spv"))
        open(comp, "w").write(src)
        subprocess.run(["glslangValidator", "-V", "-I" + INC, "-S", "comp", comp, "-o", spv], check=True,
                       stdout=subprocess.DEVNULL)
        subprocess.run(["spirv-opt", "-O", spv, "-o", opt], check=True)
        dis = subprocess.run(["spirv-dis", "--raw-id", opt], check=True, capture_output=True, text=True).stdout
    body, inside = [], False
    for line in dis.splitlines():
        if "OpFunction " in line or line.strip().endswith("OpFunction"):
            inside = True
        if inside and not SKIP.match(line):
            body.append(line)
        if "OpFunctionEnd" in line:
            inside = False
    return len(body), sum("OpImageSample" in x for x in body)
