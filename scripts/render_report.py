#!/usr/bin/env python3
"""Writes OUT/report.html: the renderer's comparison set, its error table against the ground truth, the
terminator figures, and every PNG the other demo parts wrote (OUT/<area>/*.png). Usage: render_report.py OUT"""
import html
import json
import os
import sys

import matplotlib

matplotlib.use("Agg")
import matplotlib.pyplot as plt  # noqa: E402

OUT = sys.argv[1]
R = os.path.join(OUT, "render")
# The methods the demo rendered and their labels: the method table (`microshadow methods --study --json`).
with open(os.path.join(R, "methods.json")) as f:
    _table = json.load(f)
METHODS = [m["name"] for m in _table]
LABELS = {m["name"]: m["label"] for m in _table}
LABELS["none"] = "no micro-shadowing"
LABELS["ground-truth"] = "ground truth (ray-traced height field)"


def load_jsonl(path):
    if not os.path.exists(path):
        return []
    with open(path) as f:
        return [json.loads(line) for line in f if line.strip()]


renders = load_jsonl(os.path.join(R, "renders.jsonl"))
errors = load_jsonl(os.path.join(R, "errors.jsonl"))
elevations = sorted({r["elevation"] for r in renders})
times = {(r["scene"], r["elevation"], r["method"]): r for r in renders}
err = {(e["elevation"], e["method"]): e for e in errors}


def rel(path):
    return os.path.relpath(path, OUT)


def fig(path, caption, width=None):
    w = f' style="width:{width}px"' if width else ""
    return (f'<figure><a href="{html.escape(rel(path))}"><img src="{html.escape(rel(path))}"{w}></a>'
            f"<figcaption>{html.escape(caption)}</figcaption></figure>")


# Error chart: RMSE and SSIM per method and elevation.
if errors:
    fig_, axes = plt.subplots(1, 3, figsize=(16, 4.2))
    for k, (key, title) in enumerate([("rmse", "RMSE (linear, per pixel)"), ("rmse_downsampled", "RMSE after 8×8 box average"),
                                      ("ssim", "SSIM (display luminance; 1 = identical)")]):
        ax = axes[k]
        width = 0.8 / max(1, len(elevations))
        for j, el in enumerate(elevations):
            vals = [err[(el, m)][key] if (el, m) in err else float("nan") for m in METHODS]
            ax.bar([i + j * width for i in range(len(METHODS))], vals, width, label=f"light elevation {el}°")
        ax.set_xticks([i + 0.4 - width / 2 for i in range(len(METHODS))])
        ax.set_xticklabels(METHODS, rotation=45, ha="right", fontsize=8)
        ax.set_title(title)
        ax.legend(fontsize=8)
    fig_.tight_layout()
    fig_.savefig(os.path.join(R, "errors.png"), dpi=90)
    plt.close(fig_)

h = []
h.append("""<!doctype html><html><head><meta charset="utf-8"><title>microshadow report</title><style>
body{font-family:sans-serif;max-width:1500px;margin:auto;padding:1em;color:#222}
figure{display:inline-block;margin:4px;vertical-align:top;text-align:center}
figure img{width:240px;image-rendering:pixelated;border:1px solid #ccc}
figcaption{font-size:12px;max-width:240px}
table{border-collapse:collapse;font-size:13px}td,th{border:1px solid #bbb;padding:3px 8px;text-align:right}
th{background:#eee} td:first-child{text-align:left} .row{white-space:nowrap;overflow-x:auto}
</style></head><body>""")
h.append("<h1>microshadow — what it does, in one page</h1>")


def study_verdict():
    """The multiscale study's verdict (OUT/study/results.json, docs/study.md): the first screen of the report."""
    path = os.path.join(OUT, "study", "results.json")
    if not os.path.exists(path):
        return ["<p><i>No study results (run <code>microshadow study --quick --out OUT/study</code>).</i></p>"]
    with open(path) as f:
        res = json.load(f)
    cfg, summ = res["config"], res["summary"]
    cells = [c for c in summ["cells"] if c["material"] == "all" and c["component"] == "total"]
    lights = []
    for g in res["ground_truth"]:
        if g["light"] not in lights:
            lights.append(g["light"])
    out = [f"<h2>Verdict: which micro-shadowing term comes closest (multiscale study, <code>{html.escape(cfg['name'])}"
           "</code>)</h2>",
           f"<p>A fine {cfg['fine_size']}² height field ({', '.join(cfg['materials'])}) is the real surface; the "
           "ground truth ray-traces it. Every term shades the texture set an engine would use at 1/k resolution "
           "(filtered normal, mean micro-occlusion), with the same camera; each pixel covers k × k fine texels. "
           "Cells: mean radiance of the term / ground truth over the whole view (1 = exact), total component; "
           f"<b>bold</b> = closest (within {summ['delta_bias']} of the best). "
           "Details, per material and component, the footprint RMSE and the N·L ablation: "
           "<a href='study/study.html'>study/study.html</a>, docs/study.md.</p>"]
    out.append("<table><tr><th>term</th>")
    for k in cfg["scales"]:
        for light in lights:
            out.append(f"<th>k={k}<br>{html.escape(light)}</th>")
    out.append("</tr>")
    for m in METHODS:
        out.append(f"<tr><td>{html.escape(LABELS[m])}</td>")
        for k in cfg["scales"]:
            for light in lights:
                c = next((c for c in cells if c["scale"] == k and c["light"] == light), None)
                if not c or m not in c["methods"]:
                    out.append("<td>—</td>")
                    continue
                v = c["methods"][m]["bias"]
                best = m in c["best_bias"]
                out.append(f"<td>{'<b>' if best else ''}{v:.3f}{'</b>' if best else ''}</td>")
        out.append("</tr>")
    out.append("</table>")
    abl = [a for a in summ.get("normal_ablation", []) if a["component"] == "total"]
    if abl:
        parts = []
        for k in cfg["scales"]:
            a = [x for x in abl if x["scale"] == k]
            if a:
                sh = sum(x["shading_abs_dev"] for x in a) / len(a)
                sm = sum(x["smooth_abs_dev"] for x in a) / len(a)
                parts.append(f"k = {k}: shading {sh:.3f}, unperturbed {sm:.3f}")
        out.append("<p>N·L of the terms from the shading or the unperturbed normal (mean |ratio − 1| over the "
                   "seven N·L terms and the lights): " + html.escape("; ".join(parts)) + ".</p>")
    return out


h.extend(study_verdict())
h.append("""<h2>The renderer's comparison set</h2>
<p><b>microshadow</b> is a C++ library and CLI for physically based direct lighting at the micro scale: microfacet
BRDFs, <i>micro-shadowing</i> (how much of a light a texel's micro-occlusion cone lets through), the bump-terminator
fix, the lookup tables that make them cheap in an engine, and this reference renderer that checks them against the
real thing. Below, a procedurally generated damaged-plaster texture set (rough left half, smooth right half, as in
Zurita 2026b's test) is lit by one directional light. Every micro-shadowing method sees only the normal map and the
baked micro-occlusion map; the <b>ground truth</b> ray-traces the same height field as real micro-geometry
(texel-resolution triangles, 16 samples per pixel), so its shadows are exact. All images use the same exposure.
Difference images: red = method brighter than the ground truth, blue = darker (|Δ luminance| × 4, display space).</p>""")

for el in elevations:
    h.append(f"<h2>Plane, light elevation {el}°</h2><div class='row'>")
    gt = os.path.join(R, "plane", f"el{el}_ground-truth.png")
    if os.path.exists(gt):
        h.append(fig(gt, LABELS["ground-truth"]))
    for m in METHODS:
        p = os.path.join(R, "plane", f"el{el}_{m}.png")
        if os.path.exists(p):
            h.append(fig(p, LABELS[m]))
    h.append("</div><div class='row'><figure style='width:240px'></figure>")
    for m in METHODS:
        p = os.path.join(R, "plane", f"el{el}_{m}_diff.png")
        if os.path.exists(p):
            h.append(fig(p, f"{m} − ground truth"))
    h.append("</div>")

if errors:
    h.append("<h2>Error against the ground truth (plane) and render time</h2>")
    h.append(fig(os.path.join(R, "errors.png"), "per method and light elevation", 1200))
    h.append("<table><tr><th>method</th>")
    for el in elevations:
        h.append(f"<th>RMSE {el}°</th><th>RMSE 8×8 {el}°</th><th>SSIM {el}°</th><th>time {el}° (s)</th>")
    h.append("</tr>")
    for m in METHODS + ["ground-truth"]:
        h.append(f"<tr><td>{html.escape(LABELS[m])}</td>")
        for el in elevations:
            e = err.get((el, m))
            t = times.get(("plane", el, m))
            if e:
                h.append(f"<td>{e['rmse']:.4f}</td><td>{e['rmse_downsampled']:.4f}</td><td>{e['ssim']:.3f}</td>")
            else:
                h.append("<td>—</td><td>—</td><td>—</td>")
            h.append(f"<td>{t['seconds']:.2f}</td>" if t else "<td>—</td>")
        h.append("</tr>")
    h.append("</table>")
    smooth = [m for m in METHODS if (elevations[0], "smooth:" + m) in err]
    if smooth:
        h.append("<h3>Ablation: N·L and N·V from the unperturbed normal (<code>--ms-normal smooth</code>)</h3>"
                 "<p>The default follows the seed and feeds the terms the normal-mapped shading normal. The micro-"
                 "occlusion bake measures its cone about the flat (unperturbed) normal; measuring N·L in that same "
                 "frame changes the errors as follows (same metrics, ground truth and renders otherwise).</p>")
        h.append("<table><tr><th>method</th>")
        for el in elevations:
            h.append(f"<th>RMSE {el}° shading → smooth</th><th>RMSE 8×8 {el}°</th><th>SSIM {el}°</th>")
        h.append("</tr>")
        for m in smooth:
            h.append(f"<tr><td>{html.escape(LABELS[m])}</td>")
            for el in elevations:
                a, b = err.get((el, m)), err.get((el, "smooth:" + m))
                if a and b:
                    h.append(f"<td>{a['rmse']:.4f} → {b['rmse']:.4f}</td>"
                             f"<td>{a['rmse_downsampled']:.4f} → {b['rmse_downsampled']:.4f}</td>"
                             f"<td>{a['ssim']:.3f} → {b['ssim']:.3f}</td>")
                else:
                    h.append("<td>—</td><td>—</td><td>—</td>")
            h.append("</tr>")
        h.append("</table>")
    if renders:
        r0 = renders[0]
        h.append(f"<p>Render size {r0['width']}×{r0['height']}, {r0['spp']} samples per pixel for the methods (16 "
                 "for the ground truth), on this machine (2 cores shared with the rest of the demo, so times are "
                 "indicative; see docs/renderer.md for benchmark numbers). RMSE is over linear RGB; "
                 "<i>RMSE 8×8</i> compares 8×8 box averages, i.e. the overall darkening a distant viewer sees; SSIM "
                 "(Wang et al. 2004, 11×11 Gaussian window) is computed on display luminance.</p>")

for el in elevations:
    h.append(f"<h2>Sphere, light elevation {el}° (no ground truth: the height field is only ray-traced on planes)</h2>"
             "<div class='row'>")
    for m in METHODS:
        p = os.path.join(R, "sphere", f"el{el}_{m}.png")
        if os.path.exists(p):
            h.append(fig(p, LABELS[m]))
    h.append("</div>")

h.append("<h2>Texture sets (procedural: height → normal map, roughness, baked micro-occlusion)</h2><div class='row'>")
for kind in ["plaster", "bark"]:
    for name in ["height", "normal", "micro_occlusion", "roughness", "basecolor"]:
        p = os.path.join(R, "materials", kind, f"{name}.png")
        if os.path.exists(p):
            h.append(fig(p, f"{kind}: {name}", 160))
h.append("</div>")

h.append("<h2>Terminators</h2><div class='row'>")
# The bump-terminator methods the demo rendered (`microshadow methods --bump --json`), then the Hanika offset.
with open(os.path.join(R, "bump_methods.json")) as f:
    bump = [(f"bump_{m['name']}", "bump-mapped sphere, grazing light: no fix" if m["name"] == "none" else m["label"])
            for m in json.load(f)]
for name, cap in bump + [("lowpoly_no_offset", "low-poly smooth-shaded sphere: shadow rays from the flat faces"),
                        ("lowpoly_hanika", "with the Hanika 2021 shadow-ray offset"),
                        ("meshes_representative", "Embree meshes, point + sphere light (representative point)"),
                        ("meshes_area", "same, sphere light by area sampling (reference)")]:
    p = os.path.join(R, "terminator", name + ".png")
    if os.path.exists(p):
        h.append(fig(p, cap))
h.append("</div>")

# Every other area's figures, each with the doc that explains it (output folder -> docs/ file).
AREA_DOCS = {"bump": "bump-terminator.md", "filter": "filtering.md", "io": "formats.md", "shaders": "shaders.md",
             "microfacet": "microfacet.md", "brdf": "brdf.md", "brdf-extra": "brdf-extra.md", "lut": "lut.md",
             "micro-shadowing": "micro-shadowing.md"}
for area in sorted(os.listdir(OUT)):
    d = os.path.join(OUT, area)
    if area == "render" or not os.path.isdir(d):
        continue
    pngs = sorted(f for f in os.listdir(d) if f.endswith(".png"))
    if not pngs:
        continue
    doc = AREA_DOCS.get(area, f"{area}.md")
    h.append(f"<h2>{html.escape(area)} (docs/{html.escape(doc)})</h2><div>")
    for f in pngs:
        h.append(fig(os.path.join(d, f), f, 360))
    h.append("</div>")

h.append("</body></html>")
with open(os.path.join(OUT, "report.html.tmp"), "w") as f:
    f.write("\n".join(h))
os.replace(os.path.join(OUT, "report.html.tmp"), os.path.join(OUT, "report.html"))
print(os.path.join(OUT, "report.html"))
