#!/usr/bin/env python3
"""The decision guide, generated from committed measurement files (docs/measurements/) and the method registry
(`microshadow methods --json`: what each method reads, its shader call, when to use it): writes docs/choosing.md
and the table between the guide markers at the top of README.md; and README's list of every micro-shadowing
method. --check compares instead of writing and fails (exit 1) on any difference, or when a method of the study
set has no use sentence in the registry (test_guide runs it).
Usage: scripts/guide.py [--check] [--msh build/bin/microshadow]
"""
import json, os, subprocess, sys

ROOT = os.path.dirname(os.path.dirname(os.path.abspath(__file__)))
MEAS = os.path.join(ROOT, "docs", "measurements")
BEGIN, END = "<!-- guide:begin (scripts/guide.py writes this table; do not edit) -->", "<!-- guide:end -->"
METHODS_BEGIN = "<!-- methods:begin (scripts/guide.py writes this list from the registry; do not edit) -->"
METHODS_END = "<!-- methods:end -->"
# The names the registry's GLSL forms use (docs/viewer.md), with the link from README (docs/) or from docs/ ("").
def names(docs):
    return (f"over the viewer's names ([{docs}viewer.md]({docs}viewer.md)): `vis` = V, `nl` = N·L, `nv` = N·V, "
            "`rough` = perceptual roughness, `u_lut3d` and `u_lut3d_slabs` the 3D table and its slab count, `dir_v` "
            "the 21 directional channels (6 vec4), `l_t`, `view_t`, `n_t` the light, the view and the shading normal "
            "in the normal map's tangent frame")


# The cases of the first screen: (case, method).
CASES = [
    ("your texture set has a height map (relief: rock, brick, bark, gravel)", "directional-view"),
    ("only a micro-occlusion / AO map, no extra table", "diffuse-aware-alu+generic-vndf-alu"),
    ("only a micro-occlusion / AO map, one 3D table allowed", "diffuse-aware-alu+lut3d"),
]


def load(name):
    with open(os.path.join(MEAS, name)) as f:
        return json.load(f)


def exact_error(name):
    """RMS / max in 1/255 of a method's run-time form against its own exact term, and the source."""
    terms = {r["method"]: r["all"] for r in load("terms_vs_exact.json")["results"]}
    if name in ("reference", "brinck-maximov-2016", "chan-2018", "part1-analytic"):
        a = terms[name]
        return f"{a['rms_255']:.1f} / {a['max_255']:.0f} vs generic", "terms_vs_exact.json"
    if name == "generic-vndf-alu":
        a = terms[name]
        return f"{a['rms_255']:.2f} / {a['max_255']:.1f}", "terms_vs_exact.json"
    if name in ("lut3d", "lut2d"):
        a = load(f"{name}_vs_exact.json")["all"]
        return f"{a['rms_255']:.2f} / {a['max_255']:.2f}", f"{name}_vs_exact.json"
    if name == "diffuse-aware-alu":
        a = load("aware_alu_vs_exact.json")["diffuse-aware-alu"]["all"]
        return f"{a['rms_255']:.2f} / {a['max_255']:.1f}", "aware_alu_vs_exact.json"
    if name in ("none", "ao", "generic-vndf"):
        return "exact", ""
    if name in ("directional", "directional-view"):
        return "fit (docs/directional-occlusion.md)", ""
    return "–", ""


def facts_of(table, costs):
    """Per method, what the guide shows besides measurements, from the registry: the data per texel (its
    directional channels and the command that bakes them, V, roughness, the registry's table), bytes at 8 bits and fetches per pixel (4 texel
    channels per RGBA fetch, V one), table fetches per light (the image samples of its GLSL form in
    spirv_costs.json; none for a method that takes no table), the shader call (its first GLSL form; a pair: both
    lobes'), and the registry's use sentence."""
    by = {m["name"]: m for m in table}
    facts = {}
    for m in table:
        parts = [by[m["diffuse"]], by[m["specular"]]] if m["pair"] else [m]
        ch = max(p["texel_channels"] for p in parts)
        vis = any(p["uses_visibility"] for p in parts)
        rough = any(p["uses_roughness"] for p in parts)
        bake = next((p["texel_bake"] for p in parts if p["texel_channels"] == ch and p["texel_bake"]), "")
        reads = [f"{ch} directional channels" + (f" ({bake})" if bake else "")] if ch else []
        reads += [", ".join((["V"] if vis else []) + (["roughness"] if rough else []))] if vis or rough else []
        data = " + ".join(reads + [f"the {p['table_sample']}D table" for p in parts if p["table_sample"]])
        name = m["name"]
        fetches_light = (costs[name]["image_samples"] if name in costs else
                         "–" if any(p["accepts_lut"] for p in parts) else 0)
        facts[name] = {"data": data or "-", "bytes": ch + vis, "fetches_pixel": -(-ch // 4) + vis,
                       "fetches_light": fetches_light,
                       "call": " ; ".join(p["glsl"][0]["expr"] for p in parts) if all(p["glsl"] for p in parts)
                       else "–",
                       "use": m["use"]}
    return facts


def study(cells, method, comp):
    """'mean (max)' of |bias − 1| over the directional lights and materials, per scale."""
    out = []
    for k in cells["scales"]:
        c = cells["by"].get(("all", comp, k, method))
        out.append(f"{c['mean_abs_dev']:.2f} ({c['max_abs_dev']:.2f})" if c else "–")
    return " · ".join(out)


def view_cells(sv):
    """The view sweep's cells (docs/measurements/study_views.json) by (view, component, scale, method), all
    materials."""
    return {(c["view"], c["component"], c["scale"], c["method"]): c for c in sv["cells"] if c["material"] == "all"}


def views_of(sv):
    return sorted({c["view"] for c in sv["cells"]}, key=lambda v: tuple(float(x) for x in v.split("/")))


def view_study(by, view, method, comp, scales):
    """'mean (max)' per scale at one view, joined by ' · '."""
    out = []
    for k in scales:
        c = by.get((view, comp, k, method))
        out.append(f"{c['mean_abs_dev']:.2f} ({c['max_abs_dev']:.2f})" if c else "–")
    return " · ".join(out)


def views_text(sv):
    """The per-view lines of the README block and the per-view tables of docs/choosing.md."""
    by = view_cells(sv)
    scales = sorted({c["scale"] for c in sv["cells"]})
    views = views_of(sv)
    cfg = sv["config"]
    sweep = cfg["sweep"]
    what = (f"the full study's view sweep: {', '.join(cfg['materials'])} at {cfg['fine_size']}²; lights at "
            f"{' and '.join(f'{e:g}' for e in sweep['elevations'])}° × azimuths "
            f"{', '.join(f'{a:g}' for a in sweep['azimuths'])}°; k = {' · '.join(str(k) for k in scales)}")
    readme = [f"**By view** ({what}; `directional-view`, total, mean (max) |term / ground truth − 1| per k; "
              "view = degrees off the normal): " +
              "; ".join(f"{v.split('/')[0]}°: {view_study(by, v, 'directional-view', 'total', scales)}"
                        for v in views) + "."]
    doc = ["## By view", "",
           f"Study error per view ({what}); mean (max) |term / ground truth − 1| over the lights and materials "
           "per k; view = degrees off the normal / azimuth of the direction to the camera "
           "([study.md](study.md#views-azimuths-and-scales)).", ""]
    methods = [m for m in sweep["terms"] if any(k[3] == m for k in by)]
    for comp in ("total", "diffuse"):
        doc += [f"{comp}:", "", "| view | method | " + " | ".join(f"k = {k}" for k in scales) + " |",
                "|---|---|" + "---|" * len(scales)]
        for v in views:
            for m in methods:
                doc.append(f"| {v.replace('/', '° / ')}° | `{m}` | " +
                           " | ".join(view_study(by, v, m, comp, [k]) for k in scales) + " |")
        doc.append("")
    return readme, doc


def registry(msh):
    return json.loads(subprocess.run([msh, "methods", "--json"], check=True, capture_output=True, text=True).stdout)


def build(table):
    costs = load("spirv_costs.json")["methods"]
    facts = facts_of(table, costs)
    st = load("study_targets.json")
    cells = {"scales": st["config"]["scales"],
             "by": {(c["material"], c["component"], c["scale"], c["method"]): c for c in st["cells"]}}
    errors = [f"the registry's study method {m['name']} has no use sentence (src/occlusion/micro_shadowing_methods.cpp)"
              for m in table if m["in_study"] and not m["use"]]
    # Methods measured by a later run on the same configuration ("added": its shared cells equal the file's).
    methods = [m for m in st["config"]["terms"] + st.get("added", {}).get("methods", []) if m in facts]

    def instr(m):
        return str(costs[m]["instructions"]) if m in costs else "–"

    ks = ", ".join(f"k = {k}" for k in cells["scales"])
    mats = ", ".join(st["config"]["materials"]) + f" at {st['config']['fine_size']}²"
    lights = f"{len(st['config']['elevations']) * len(st['config']['azimuths'])} directional lights " \
             f"({', '.join(str(int(e)) for e in st['config']['elevations'])}° × azimuth " \
             f"{' and '.join(str(int(a)) for a in st['config']['azimuths'])}°)"
    readme = [BEGIN, "",
              f"**Which term to ship** (study: {mats}; {lights}; scales {ks}; |term / ground truth − 1| of the "
              "mean radiance, total, mean (max) over lights and materials per scale; "
              "[docs/choosing.md](docs/choosing.md) has every term):", "",
              "| your case | ship | data per texel | cost per light | study error, k = " +
              " · ".join(str(k) for k in cells["scales"]) + " | shader call |",
              "|---|---|---|---|---|---|"]
    for case, m in CASES:
        f = facts[m]
        readme.append(f"| {case} | `{m}` | {f['data']} ({f['bytes']} B at 8 bits) | {instr(m)} SPIR-V instr., "
                      f"{f['fetches_light']} fetches | {study(cells, m, 'total')} | `{f['call']}` |")
    views_path = os.path.join(MEAS, "study_views.json")
    v_readme, v_doc = views_text(load("study_views.json")) if os.path.exists(views_path) else ([], [])
    readme += ([""] + v_readme if v_readme else [])
    readme += ["", f"Shader calls are the registry's GLSL forms, {names('docs/')}.", ""]
    readme += ["For comparison, the best older term on the same cells: " +
               "; ".join(f"`{m}` {study(cells, m, 'total')}" for m in ("chan-2018", "lut3d") if m in methods) + ".",
               "", END]

    doc = ["# Choosing a micro-shadowing term", "",
           "Generated by `scripts/guide.py` from the measurement files in `docs/measurements/` (do not edit: "
           "`test_guide` fails when this text and the files disagree). A pair `D+S` is one term on the diffuse "
           "lobe and another on the specular lobe (`microshadow methods`).", "",
           "## Which term to ship", ""]
    for case, m in CASES:
        doc.append(f"- **{case}**: `{m}` — {facts[m]['use']}. Shader: `{facts[m]['call']}`.")
    doc += ["", f"Shader calls are the registry's GLSL forms (`microshadow methods --json`), {names('')}.",
            "", "## Every term of the study", "",
            f"Study error = |term / ground truth − 1| of the mean radiance over the whole view, mean (max) over "
            f"the {lights} and the materials {mats}, per scale ({ks}); components under 10 % of the total are "
            "left out per cell. Error vs exact = the run-time form against its own exact term at 10⁴ continuous "
            "random inputs (RMS / max, 1/255). SPIR-V = instructions of a compute kernel evaluating only the term "
            "after `spirv-opt -O` (≈ 8 of them the kernel's frame); fetches per light = table fetches after the "
            "early-out (the per-pixel fetches of the texel's own data are shared by all lights).", "",
            "| method | data per texel | bytes | fetches per pixel / light | SPIR-V | error vs exact | "
            "study error, total | study error, diffuse | use |",
            "|---|---|---:|---|---:|---|---|---|---|"]
    for m in methods:
        f = facts[m]
        err, _ = exact_error(m)
        doc.append(f"| `{m}` | {f['data']} | {f['bytes']} | {f['fetches_pixel']} / {f['fetches_light']} | "
                   f"{instr(m)} | {err} | {study(cells, m, 'total')} | {study(cells, m, 'diffuse')} | {f['use']} |")
    doc += [""] + v_doc if v_doc else []
    doc += ["", "## Where the numbers come from", "",
            "| file | command |", "|---|---|",
            "| `study_targets.json` | `microshadow study --fine-size 1024 --out DIR --threads 2` (22 min 34 s wall, 1631 s CPU on the 2-core machine, shared), then "
            "`scripts/study_targets.py DIR/results.json --json 1` |"] + \
        ([f"| `study_targets.json` (`added`: {', '.join(st['added']['methods'])}) | {st['added']['from']} |"]
         if "added" in st else []) + [
            "| `terms_vs_exact.json` | `microshadow verify micro-shadowing-term --method all --samples 10000 --json` |",
            "| `lut3d_vs_exact.json`, `lut2d_vs_exact.json` | `microshadow verify micro-shadowing-lut "
            "share/microshadow/tables/micro_shadowing{,_2d}.ktx2 --samples 10000 --json` |",
            "| `aware_alu_vs_exact.json` | `microshadow verify micro-shadowing-aware --method diffuse-aware-alu "
            "--samples 2000 --json` |",
            "| `spirv_costs.json` | `scripts/method_costs.py build/bin/microshadow` |"] + \
        (["| `study_views.json` | `microshadow study --out DIR --threads 2` (the full study, with its view sweep), "
          "then `scripts/study_targets.py DIR/results.json --sweep-lights 1 --methods none,ao,directional-view,"
          "directional,diffuse-aware-alu+lut3d --json 1` |"] if v_doc else []) + [
            "| the registry (`microshadow methods --json`) | data per texel, bytes and fetches per pixel (what each "
            "method reads: texel channels, 4 per fetch, and V), fetches per light (the image samples of its GLSL form "
            "in `spirv_costs.json`), shader call (its GLSL form), use |", ""]
    return "\n".join(readme) + "\n", "\n".join(doc), errors


def methods_block(table):
    """README's list of every method of the registry, one row each: name, what it is, what it reads beyond
    V and N·L, the options it takes, whether the study renders it by default."""
    rows = [METHODS_BEGIN, "| method | what it is | reads | options | study |", "|---|---|---|---|---|"]
    for m in table:
        if m["pair"]:
            reads = f"`{m['diffuse']}` on the diffuse lobe, `{m['specular']}` on the specular lobe"
        else:
            r = (["roughness"] if m["uses_roughness"] else []) + (["N·V"] if m["uses_ndotv"] else [])
            r += [f"{m['texel_channels']} texel channels"] if m.get("texel_channels") else []
            r += [] if m["uses_ndotl"] else ["no N·L"]
            reads = ", ".join(r) or "–"
        opts = [o for o, k in (("phi", "accepts_phi"), ("samples", "accepts_samples"), ("lut", "accepts_lut"),
                               ("roughness-y", "accepts_roughness_y")) if m[k]]
        summary = m["summary"].replace("|", "\\|")
        rows.append(f"| `{m['name']}` | {summary} | {reads} | {', '.join(opts) or '–'} | "
                    f"{'yes' if m['in_study'] else ''} |")
    return "\n".join(rows + [METHODS_END]) + "\n"


def replace_block(text, begin, end, block, errors, what):
    if begin not in text or end not in text:
        errors.append(f"README.md lacks the {what} markers")
        return text
    a, b = text.index(begin), text.index(end) + len(end) + 1
    return text[:a] + block + text[b:]


def main():
    check = "--check" in sys.argv
    cli = sys.argv[sys.argv.index("--msh") + 1] if "--msh" in sys.argv else os.path.join(ROOT, "build", "bin",
                                                                                          "microshadow")
    if not os.path.exists(cli):
        print(f"guide: no CLI at {cli} for the method registry (pass --msh)", file=sys.stderr)
        return 1
    table = registry(cli)
    readme_block, doc, errors = build(table)
    choosing = os.path.join(ROOT, "docs", "choosing.md")
    readme = os.path.join(ROOT, "README.md")
    text = open(readme).read()
    new_readme = replace_block(text, BEGIN, END, readme_block, errors, "guide")
    new_readme = replace_block(new_readme, METHODS_BEGIN, METHODS_END, methods_block(table), errors, "methods")
    if check:
        if not os.path.exists(choosing) or open(choosing).read() != doc:
            errors.append("docs/choosing.md differs from what scripts/guide.py writes (run it)")
        if new_readme != text:
            errors.append("README.md's guide table or list of methods differs from what scripts/guide.py writes "
                          "(run it)")
    else:
        open(choosing, "w").write(doc)
        open(readme, "w").write(new_readme)
    for e in errors:
        print("guide: " + e, file=sys.stderr)
    return 1 if errors else 0


if __name__ == "__main__":
    sys.exit(main())
