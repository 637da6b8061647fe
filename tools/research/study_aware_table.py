#!/usr/bin/python3
"""Per-component comparison of the micro-BRDF-aware terms with the older terms on a `microshadow study` run.

For each scale k >= 4, component and method (base roughness, shading normal, whole view), over the study's cells
(material x shape x light): the mean over cells of the relative footprint RMSE (rmse_footprint / gt_mean) and of
the mean bias (bias - 1, signed, and |bias - 1|), each with its standard error over cells (the spread of the cells,
sd / sqrt(n)), and the mean ground-truth noise floor of the footprint RMSE (relative). It also counts the cells
where `diffuse-aware+specular-aware` is lower than each other method, and gives the mean paired difference aware - method with its
standard error over cells, per metric.
Components with gt_mean below 2 % of the total's are skipped per cell (as the study's ranking does).
Usage: /usr/bin/python3 tools/research/study_aware_table.py DIR/results.json [--methods a,b,...]
"""
import json
import math
import sys

AWARE = "diffuse-aware+specular-aware"
DEFAULT = ["ao", "brinck-maximov-2016", "chan-2018", "generic-vndf", "lut3d", AWARE, "diffuse-aware-flux+specular-aware"]


def mean_se(xs):
    n = len(xs)
    if n == 0:
        return float("nan"), float("nan")
    m = sum(xs) / n
    if n < 2:
        return m, float("nan")
    sd = math.sqrt(sum((x - m) ** 2 for x in xs) / (n - 1))
    return m, sd / math.sqrt(n)


def main(path, methods):
    with open(path) as f:
        rows = json.load(f)["rows"]
    rows = [r for r in rows if r["ms_normal"] == "shading" and r["roughness"] == "base"]
    cell = lambda r: (r["material"], r["shape"], r["scale"], r["light"])  # noqa: E731
    total = {}
    for r in rows:
        if r["component"] == "total" and r["method"] == "none":
            total[cell(r)] = r["gt_mean"]["whole"]
    by = {}
    for r in rows:
        g = r["gt_mean"]["whole"]
        t = total.get(cell(r))
        if g is None or t is None or not g > 0.02 * t:
            continue
        if r["rmse_footprint"]["whole"] is None or r["bias"]["whole"] is None:
            continue
        by.setdefault((r["scale"], r["component"], r["method"]), {})[cell(r)] = (
            r["rmse_footprint"]["whole"] / g,
            r["bias"]["whole"] - 1.0,
            (r["rmse_footprint_floor"]["whole"] or 0.0) / g,
        )
    scales = sorted({k[0] for k in by if k[0] >= 4})
    for k in scales:
        for comp in ["diffuse", "specular", "total"]:
            print(f"\n### k = {k}, {comp}")
            print("| method | cells | footprint RMSE / GT mean | bias - 1 | abs(bias - 1) | floor | aware lower in (RMSE, abs bias); mean paired aware - method (RMSE, abs bias) |")
            print("|---|---|---|---|---|---|---|")
            aw = by.get((k, comp, AWARE), {})
            for m in methods:
                d = by.get((k, comp, m), {})
                if not d:
                    continue
                f = [x[0] for x in d.values()]
                b = [x[1] for x in d.values()]
                a = [abs(x) for x in b]
                fl = [x[2] for x in d.values()]
                fm, fs = mean_se(f)
                bm, bs = mean_se(b)
                am, as_ = mean_se(a)
                common = [c for c in d if c in aw]
                lower_f = sum(aw[c][0] < d[c][0] for c in common)
                lower_b = sum(abs(aw[c][1]) < abs(d[c][1]) for c in common)
                vs = ""
                if m != AWARE and common:
                    df, _ = mean_se([aw[c][0] - d[c][0] for c in common])
                    _, dfs = mean_se([aw[c][0] - d[c][0] for c in common])
                    da, das = mean_se([abs(aw[c][1]) - abs(d[c][1]) for c in common])
                    vs = (f"{lower_f}/{len(common)}, {lower_b}/{len(common)}; paired diff {df:+.4f} ± {dfs:.4f}, "
                          f"{da:+.4f} ± {das:.4f}")
                print(f"| {m} | {len(d)} | {fm:.4f} ± {fs:.4f} | {bm:+.4f} ± {bs:.4f} | {am:.4f} ± {as_:.4f} | "
                      f"{sum(fl) / len(fl):.4f} | {vs} |")


if __name__ == "__main__":
    args = sys.argv[1:]
    if not args:
        sys.exit(__doc__)
    ms = DEFAULT
    if "--methods" in args:
        i = args.index("--methods")
        ms = args[i + 1].split(",")
        del args[i:i + 2]
    main(args[0], ms)
