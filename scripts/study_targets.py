#!/usr/bin/python3
"""The relief targets on a `microshadow study` run: per view, method, component and scale k, over every
directional light (every elevation and azimuth of that view) and every material: the mean and the max of
|bias - 1| (whole view, base roughness, shading normal) and the mean footprint RMSE / GT mean; and per material
the same. Components carrying under 10 % of the total are left out per cell (as the study's ranking leaves
out < 2 %). A view is "angle/azimuth" in degrees ("30/270": the study's main camera; rows from before views
were added count as that).
Usage: /usr/bin/python3 scripts/study_targets.py DIR/results.json [--methods a,b] [--component total,diffuse]
       [--views 30/270,75/270] [--sweep-lights 1] [--json 1]
       (--sweep-lights: only the view sweep's lights at every view and scale, so that views compare alike) (one JSON object instead of the tables: docs/measurements/study_targets.json)
       /usr/bin/python3 scripts/study_targets.py docs/measurements/study_targets_2048.json [--methods a,b]
       [--component ...] (the same tables from a stored --json file)
"""
import json
import sys
from collections import defaultdict


def view_of(r):
    """A row's view as "angle/azimuth" (a cell of this script's carries it already)."""
    if isinstance(r.get("view"), str):
        return r["view"]
    return f"{r.get('view', 30):g}/{r.get('view_azimuth', 270):g}"


def aggregate(res, methods, comps, sweep_lights=False):
    """One cell per (material or "all", component, k, method) of a results.json: mean and max |bias - 1| over
    the directional lights and the mean footprint RMSE / GT mean, unrounded."""
    total = {}
    for r in res["rows"]:
        # The ground truth is the same for every method (a run need not include `none`).
        if r["component"] == "total" and r["ms_normal"] == "shading" and r["roughness"] == "base":
            total.setdefault((r["material"], r["shape"], r["scale"], view_of(r), r["light"]), r["gt_mean"]["whole"])
    acc = defaultdict(list)
    sweep = res["config"].get("sweep", {})
    for r in res["rows"]:
        if r.get("light_type") != "directional" or r["ms_normal"] != "shading" or r["roughness"] != "base":
            continue
        if r["method"] not in methods or r["component"] not in comps:
            continue
        if sweep_lights and (r["elevation"] not in sweep["elevations"] or r["azimuth"] not in sweep["azimuths"]):
            continue
        b, f, g = r["bias"]["whole"], r["rmse_footprint"]["whole"], r["gt_mean"]["whole"]
        t = total.get((r["material"], r["shape"], r["scale"], view_of(r), r["light"]))
        if b is None or g is None or not t or g < 0.10 * t:
            continue
        for mat in ("all", r["material"]):
            acc[(mat, r["component"], r["scale"], r["method"], view_of(r))].append(
                (abs(b - 1), f / g if f is not None else None))
    cells = []
    for (mat, comp, k, m, view), v in sorted(acc.items()):
        d = [x[0] for x in v]
        fr = [x[1] for x in v if x[1] is not None]
        cells.append({"material": mat, "component": comp, "scale": k, "method": m, "view": view, "lights": len(d),
                      "mean_abs_dev": sum(d) / len(d), "max_abs_dev": max(d),
                      "rmse_footprint_rel": sum(fr) / max(1, len(fr))})
    return cells


def print_tables(cells, methods, comps, views=None):
    """Per view, component and material, one row per method: mean / max |bias - 1| / footprint RMSE per k."""
    by = {(c["material"], c["component"], c["scale"], c["method"], view_of(c)): c for c in cells}
    mats = sorted({k[0] for k in by})
    scales = sorted({k[2] for k in by})
    all_views = sorted({k[4] for k in by}, key=lambda v: tuple(float(x) for x in v.split("/")))
    for view in views or all_views:
        for comp in comps:
            for mat in mats:
                if not any((mat, comp, k, m, view) in by for k in scales for m in methods):
                    continue
                print(f"\nview {view}, {comp}, {mat}: mean |bias-1| / max |bias-1| / mean footprint RMSE rel, per k")
                print("| method | " + " | ".join(f"k = {k}" for k in scales) + " |")
                print("|---|" + "---:|" * len(scales))
                for m in methods:
                    row = []
                    for k in scales:
                        c = by.get((mat, comp, k, m, view))
                        row.append("–" if c is None else
                                   f"{c['mean_abs_dev']:.3f} / {c['max_abs_dev']:.3f} / {c['rmse_footprint_rel']:.3f}")
                    print(f"| {m} | " + " | ".join(row) + " |")


def main():
    path = sys.argv[1]
    args = dict(zip(sys.argv[2::2], sys.argv[3::2]))
    res = json.load(open(path))
    comps = args.get("--component", "total,diffuse,specular").split(",")
    views = args["--views"].split(",") if "--views" in args else None
    if "cells" in res:  # a stored --json output: its cells are already the aggregates
        default = res["config"]["terms"] + res.get("added", {}).get("methods", [])
        methods = args.get("--methods", ",".join(default)).split(",")
        return print_tables(res["cells"], methods, comps, views)
    methods = args.get("--methods", ",".join(res["config"]["terms"])).split(",")
    sweep_lights = bool(args.get("--sweep-lights"))
    if sweep_lights and not res["config"].get("sweep", {}).get("views"):
        sys.exit("study_targets: --sweep-lights needs a run with the view sweep")
    cells = aggregate(res, methods, comps, sweep_lights)
    if args.get("--json"):
        for c in cells:
            for key in ("mean_abs_dev", "max_abs_dev", "rmse_footprint_rel"):
                c[key] = round(c[key], 4)
        keys = ("name", "materials", "fine_size", "scales", "elevations", "azimuths", "terms", "views", "view_azimuths",
                "sweep")
        out = {"source": path, "config": {k: res["config"][k] for k in keys if k in res["config"]},
               "sweep_lights": sweep_lights,
               "cells": cells}
        print(json.dumps(out, indent=1))
        return
    print_tables(cells, methods, comps, views)


if __name__ == "__main__":
    main()
