#!/usr/bin/python3
"""A figure of study images side by side: one row per material, one column per method (the ground truth
first), each labelled with its whole-view bias (term / ground truth of the mean radiance, total component).
The images are the study's featured ones (DIR/images/<material>_<shape>_k<k>_<light>_<method>.png); methods
may come from several study runs of the same configuration (the ground truth is the same in each).
Usage: /usr/bin/python3 tools/research/study_figure.py --out FIG.png --materials gravel,rock --scale 4
       --light dir-el10-az0 --methods ao,directional,directional-view DIR [DIR ...]
"""
import argparse
import json
import os
import sys

import matplotlib

matplotlib.use("Agg")
import matplotlib.image as mpimg  # noqa: E402
import matplotlib.pyplot as plt  # noqa: E402


def main():
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--out", required=True)
    ap.add_argument("--materials", required=True)
    ap.add_argument("--scale", type=int, required=True)
    ap.add_argument("--light", required=True)
    ap.add_argument("--methods", required=True)
    ap.add_argument("--shape", default="plane")
    ap.add_argument("dirs", nargs="+")
    a = ap.parse_args()
    mats, methods = a.materials.split(","), a.methods.split(",")
    bias = {}
    for d in a.dirs:
        for r in json.load(open(os.path.join(d, "results.json")))["rows"]:
            if (r["component"] == "total" and r["ms_normal"] == "shading" and r["roughness"] == "base"
                    and r["scale"] == a.scale and r["light"] == a.light and r["shape"] == a.shape):
                bias[(r["material"], r["method"])] = r["bias"]["whole"]

    def image(mat, method):
        name = f"{mat}_{a.shape}_k{a.scale}_{a.light}_{method}.png"
        for d in a.dirs:
            p = os.path.join(d, "images", name)
            if os.path.exists(p):
                return mpimg.imread(p)
        sys.exit(f"study_figure: no {name} in {', '.join(a.dirs)}")

    cols = ["ground-truth"] + methods
    fig, axes = plt.subplots(len(mats), len(cols), figsize=(1.9 * len(cols), 2.05 * len(mats)), squeeze=False)
    for i, mat in enumerate(mats):
        for j, m in enumerate(cols):
            ax = axes[i][j]
            ax.imshow(image(mat, m), interpolation="nearest")
            ax.set_xticks([]), ax.set_yticks([])
            label = m if m == "ground-truth" else f"{m}\nbias {bias[(mat, m)]:.2f}"
            ax.set_title(label, fontsize=7)
            if j == 0:
                ax.set_ylabel(mat, fontsize=9)
    fig.tight_layout()
    tmp = a.out + ".tmp.png"
    fig.savefig(tmp, dpi=110)
    os.replace(tmp, a.out)


if __name__ == "__main__":
    main()
