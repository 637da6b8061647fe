#!/usr/bin/python3
"""The Pareto table of the directional channels' storage forms (docs/directional-occlusion.md, "Compact
forms") from a `microshadow study` run whose terms include `directional-view` (float) and its forms
`directional-view@FORM`, beside the cone terms: per form its bytes per texel, fetches per pixel, SPIR-V
instructions, and the diffuse and total mean (max) |bias - 1| over every directional light and material per
view and scale (scripts/study_targets.py's aggregation); then the issue's two targets, checked per cell
(material, component, k, view):
  - a form of <= 8 B and <= 2 fetches within +0.01 mean and +0.03 worst light of float directional-view;
  - a form of <= 4 B and 1 fetch at least 2x closer (mean |bias - 1|) than the best cone term at every k.
Usage: /usr/bin/python3 tools/research/compact_forms.py DIR/results.json [--json OUT.json]
"""
import json
import math
import os
import sys

sys.path.insert(0, os.path.join(os.path.dirname(os.path.abspath(__file__)), "..", "..", "scripts"))
from study_targets import aggregate, view_of  # noqa: E402

FLOAT = "directional-view"
CONES = ["ao", "chan-2018", "diffuse-aware-alu+lut3d", "diffuse-aware-alu+generic-vndf-alu"]
# SPIR-V instructions after spirv-opt -O of the evaluation from the fetched data (tests/test_shaders_directional.cpp
# SpirvCost; docs/shaders.md); None where no shader was measured.
SPIRV = {"float": 97, "unorm8": 97, "bc4": 97, 4: 166, 8: 259}


def cost(form):
    """(bytes per texel, fetches per pixel, SPIR-V) of a form name ("float", "unorm8", "bc4", "pca<K>[x16|f]")."""
    if form == "float":
        return 84.0, 6, SPIRV["float"]
    if form == "unorm8":
        return 21.0, 6, SPIRV["unorm8"]
    if form == "bc4":
        return 10.5, 11, SPIRV["bc4"]
    k = int(form[3:].split("x")[0].rstrip("f"))
    bits = 16 if form.endswith("x16") else 32 if form.endswith("f") else 8
    return k * bits / 8, math.ceil(k / 4), SPIRV.get(k) if bits == 8 else None


def main():
    path = sys.argv[1]
    args = dict(zip(sys.argv[2::2], sys.argv[3::2]))
    res = json.load(open(path))
    terms = res["config"]["terms"]
    forms = ["float"] + [t.split("@", 1)[1] for t in terms if t.startswith(FLOAT + "@")]
    cones = [t for t in terms if t in CONES]
    methods = [FLOAT] + [FLOAT + "@" + f for f in forms[1:]] + cones
    cells = aggregate(res, methods, ["diffuse", "total"])
    by = {(c["material"], c["component"], c["scale"], c["method"], c["view"]): c for c in cells}
    scales = sorted({c["scale"] for c in cells})
    views = sorted({c["view"] for c in cells}, key=lambda v: tuple(float(x) for x in v.split("/")))
    mats = sorted({c["material"] for c in cells if c["material"] != "all"})
    name = lambda f: FLOAT if f == "float" else FLOAT + "@" + f  # noqa: E731
    out = {"source": path, "forms": [], "targets": {}}
    for view in views:
        ks = [k for k in scales if ("all", "diffuse", k, FLOAT, view) in by]
        if not ks:
            continue
        print(f"\n### view {view}: mean (max) |bias - 1|, all materials, per k = {', '.join(map(str, ks))}\n")
        print("| form | B/texel | fetches | SPIR-V | diffuse | total |")
        print("|---|---:|---:|---:|---|---|")
        for f in forms + cones:
            m = name(f) if f in forms else f
            b, n, s = cost(f) if f in forms else (1, 1, None)
            cols = []
            for comp in ("diffuse", "total"):
                cols.append(" · ".join(
                    f"{by[('all', comp, k, m, view)]['mean_abs_dev']:.3f} ({by[('all', comp, k, m, view)]['max_abs_dev']:.2f})"
                    if ("all", comp, k, m, view) in by else "–" for k in ks))
            print(f"| {m} | {b:g} | {n} | {s if s else '–'} | {cols[0]} | {cols[1]} |")
    # Target 1: every cell within +0.01 mean, +0.03 worst of float.
    print("\n### targets, per cell (material, component, k, view)\n")
    for f in forms[1:]:
        b, n, _ = cost(f)
        m = name(f)
        worst_mean = worst_max = -1e9
        fails = total = 0
        where = ""
        for mat in mats:
            for comp in ("diffuse", "total"):
                for k in scales:
                    for view in views:
                        a, r = by.get((mat, comp, k, m, view)), by.get((mat, comp, k, FLOAT, view))
                        if not a or not r:
                            continue
                        dm, dx = a["mean_abs_dev"] - r["mean_abs_dev"], a["max_abs_dev"] - r["max_abs_dev"]
                        total += 1
                        if dm > 0.01 or dx > 0.03:
                            fails += 1
                        if dm > worst_mean:
                            worst_mean, where = dm, f"{mat} {comp} k={k} view {view}"
                        worst_max = max(worst_max, dx)
        # Target 2: 2x closer than the best cone term, all materials, per k and view (diffuse and total).
        ratio = math.inf
        rwhere = ""
        for comp in ("diffuse", "total"):
            for k in scales:
                for view in views:
                    a = by.get(("all", comp, k, m, view))
                    cs = [by[("all", comp, k, c, view)]["mean_abs_dev"] for c in cones if ("all", comp, k, c, view) in by]
                    if a and cs and a["mean_abs_dev"] > 0 and min(cs) / a["mean_abs_dev"] < ratio:
                        ratio, rwhere = min(cs) / a["mean_abs_dev"], f"{comp} k={k} view {view}"
        t1 = b <= 8 and n <= 2
        t2 = b <= 4 and n <= 1
        print(f"- {m} ({b:g} B, {n} fetches): cells beyond +0.01 mean / +0.03 worst of float: {fails} of {total}; "
              f"largest mean excess {worst_mean:+.3f} ({where}), largest worst-light excess {worst_max:+.3f}; "
              f"best cone / form mean, smallest: {ratio:.2f}x ({rwhere})"
              + ("  [target 1 form]" if t1 else "") + ("  [target 2 form]" if t2 else ""))
        out["targets"][m] = {"bytes": b, "fetches": n, "cells": total, "cells_beyond": fails,
                             "max_mean_excess": round(worst_mean, 4), "max_worst_excess": round(worst_max, 4),
                             "worst_mean_cell": where, "min_cone_ratio": round(ratio, 3), "min_ratio_cell": rwhere,
                             "target1_meets": t1 and fails == 0, "target2_meets": t2 and ratio >= 2}
    if "--json" in args:
        for c in cells:
            for key in ("mean_abs_dev", "max_abs_dev", "rmse_footprint_rel"):
                c[key] = round(c[key], 4)
        out["cells"] = cells
        with open(args["--json"], "w") as fo:
            json.dump(out, fo, indent=1)


if __name__ == "__main__":
    main()
