#!/usr/bin/env python3
"""SPIR-V cost per light of every micro-shadowing method's GLSL form, from the method table itself
(`microshadow methods --json`: the viewer's GLSL expressions). For each form a compute shader evaluates only
that expression from a loaded record; glslangValidator compiles it to Vulkan SPIR-V, spirv-opt -O inlines and
optimizes it, and the static instruction count of main (OpLabel, OpPhi etc. included; OpLine/OpName/OpDecorate
not; about 15 are the record load and the store) and its image samples are kept. A pair is the sum of its two
lobes' forms (one light shades both lobes). Writes JSON to stdout (docs/measurements/spirv_costs.json);
with --check, compares instead with that committed file and exits 1 on any difference (test_spirv_costs).
Usage: scripts/method_costs.py path/to/microshadow [--check]
"""
import json, os, subprocess, sys

from spirv_cost import KERNEL_HEAD, ROOT, spirv_cost

MODULES = ["micro_shadowing.glsl", "micro_shadowing_fit.glsl", "micro_shadowing_aware.glsl",
           "micro_shadowing_aware_fit.glsl", "directional.glsl"]
HEAD = KERNEL_HEAD + """layout(binding = 2) uniform sampler3D u_lut3d;
layout(binding = 3) uniform sampler3D u_lut2d;
layout(binding = 4) uniform sampler3D u_lut_az;
layout(std140, binding = 5) uniform P { int u_samples, u_lut3d_slabs, u_lut2d_slabs, u_lut_az_slabs, u_lut_az_harmonics; };
"""


def count(expr):
    src = HEAD + "".join(f'#include "{m}"\n' for m in MODULES) + """
void main() {
  uint i = gl_GlobalInvocationID.x;
  vec4 a = rec[3u * i], b = rec[3u * i + 1u], c = rec[3u * i + 2u];
  float vis = a.x, nl = a.y, nv = a.z, rough = a.w, alpha = rough * rough, cos_phi = b.w;
  vec3 v = b.xyz, l = c.xyz;
  // The directional forms' inputs (the viewer's names): the channels and the tangent-space vectors, loaded
  // from the record without arithmetic.
  vec4 dir_c0 = a, dir_c1 = b;
  float dir_c8 = c.w;
  vec4 dir_v[6] = vec4[6](a, b, c, a.wzyx, b.wzyx, c.wzyx);
  vec3 l_t = c.xyz, view_t = b.xyz, n_t = a.xyz;
  o[i] = %s;
}
""" % expr
    n, f = spirv_cost(src)
    return {"instructions": n, "image_samples": f}


def main():
    if len(sys.argv) < 2 or sys.argv[1] in ("-h", "--help"):
        print(__doc__.strip())
        return 0 if len(sys.argv) >= 2 else 2
    table = json.loads(subprocess.run([sys.argv[1], "methods", "--json"], check=True, capture_output=True,
                                      text=True).stdout)
    by_name = {m["name"]: m for m in table}
    out = {"command": "scripts/method_costs.py build/bin/microshadow", "baseline": count("0.0"), "methods": {}}
    for m in table:
        if m["pair"]:
            continue
        if m["glsl"]:
            out["methods"][m["name"]] = dict(count(m["glsl"][0]["expr"]), expr=m["glsl"][0]["expr"])
    for m in table:
        if m["pair"] and m["diffuse"] in out["methods"] and m["specular"] in out["methods"]:
            d, s = out["methods"][m["diffuse"]], out["methods"][m["specular"]]
            base = out["baseline"]["instructions"]
            out["methods"][m["name"]] = {"instructions": d["instructions"] + s["instructions"] - base,
                                         "image_samples": d["image_samples"] + s["image_samples"],
                                         "expr": d["expr"] + " ; " + s["expr"]}
    if "--check" in sys.argv[2:]:
        path = os.path.join(ROOT, "docs/measurements/spirv_costs.json")
        committed = json.load(open(path))
        # The baseline and every form, compared alike.
        want = {"baseline": committed["baseline"], **committed["methods"]}
        got = {"baseline": out["baseline"], **out["methods"]}
        bad = [k for k in sorted(set(want) | set(got)) if want.get(k) != got.get(k)]
        for k in bad:
            print(f"{k}: committed {want.get(k)}, measured {got.get(k)}")
        print(f"{len(out['methods'])} forms, {len(bad)} differ from {path}")
        return 1 if bad else 0
    print(json.dumps(out, indent=1, sort_keys=True))
    return 0


if __name__ == "__main__":
    sys.exit(main())
