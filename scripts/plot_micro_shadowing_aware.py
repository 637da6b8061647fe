#!/usr/bin/python3
"""Figures of the micro-BRDF-aware terms from `microshadow plot micro-shadowing-aware --out DIR` (maps.csv).

Writes DIR/aware_ndotv_<nv>.png: rows = generic VNDF, specular-aware, diffuse-aware (reciprocal), diffuse-aware
(flux), all azimuth means; columns = roughness 0.1 / 0.4 / 0.7 / 1; each panel the term over Visibility (x) and
N.L (y), in the layout of Zurita 2026, "Improving Direct Lighting Material Occlusion - Part 2".
Usage: /usr/bin/python3 scripts/plot_micro_shadowing_aware.py DIR
"""
import csv
import os
import sys

import matplotlib

matplotlib.use("Agg")
import matplotlib.pyplot as plt  # noqa: E402
import numpy as np  # noqa: E402
from figure_grid import label_panel  # noqa: E402

TERMS = [  # maps.csv's columns: registry ids (`microshadow methods`)
    ("generic-vndf", "generic VNDF"),
    ("specular-aware", "specular-aware"),
    ("diffuse-aware", "diffuse-aware"),
    ("diffuse-aware-flux", "diffuse-aware (flux)"),
]


def main(d):
    with open(os.path.join(d, "maps.csv"), newline="") as f:
        rows = list(csv.DictReader(f))
    data = {k: np.array([float(r[k]) for r in rows]) for k in rows[0].keys()}
    roughs = sorted(set(data["roughness"]))
    for nv in sorted(set(data["n_dot_v"]), reverse=True):
        fig, axes = plt.subplots(len(TERMS), len(roughs), figsize=(2.2 * len(roughs), 2.1 * len(TERMS)),
                                 squeeze=False)
        for i, (key, label) in enumerate(TERMS):
            for j, r in enumerate(roughs):
                sel = (data["roughness"] == r) & (data["n_dot_v"] == nv)
                n = int(round(np.sqrt(sel.sum())))
                order = np.lexsort((data["n_dot_l"][sel], data["visibility"][sel]))
                z = data[key][sel][order].reshape(n, n).T  # rows: N.L, columns: V
                ax = axes[i][j]
                ax.imshow(z, origin="lower", extent=(0, 1, 0, 1), vmin=0, vmax=1, cmap="gray",
                          interpolation="bilinear")
                ax.set_xticks([0, 0.5, 1])
                ax.set_yticks([0, 0.5, 1])
                label_panel(ax, i, j, len(TERMS), f"roughness {r:g}", f"{label}\nN.L", fontsize=7,
                            title_size=8)
        fig.suptitle(f"azimuth means, N.V = {nv:g}", fontsize=9)
        fig.tight_layout()
        out = os.path.join(d, f"aware_ndotv_{nv:g}.png")
        fig.savefig(out, dpi=80)
        plt.close(fig)
        print("wrote", out)


if __name__ == "__main__":
    if len(sys.argv) != 2:
        sys.exit("usage: plot_micro_shadowing_aware.py DIR")
    main(sys.argv[1])
