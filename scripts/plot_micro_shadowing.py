#!/usr/bin/python3
"""Figures for the micro-shadowing terms from the CSVs of `microshadow plot micro-shadowing --out DIR`.

Writes into DIR:
  maps_ndotv_<nv>.png     every method over (Visibility, N.L), one row per roughness (the plots of Zurita 2026b, Part 2)
  curves.png              the terms against Visibility at a few N.L, roughness 0.1/0.4/0.7/1, N.V = 1 and 0.1
  error_maps.png          older terms minus the exact generic term (N.V = 1 and 0.5), per roughness
  azimuth_error.png       exact term vs its azimuth mean (and Fourier truncations) at random configurations
Usage: /usr/bin/python3 scripts/plot_micro_shadowing.py DIR
"""
import csv
import os
import sys

import matplotlib

matplotlib.use("Agg")
import matplotlib.pyplot as plt  # noqa: E402
import numpy as np  # noqa: E402
from figure_grid import label_panel  # noqa: E402

# maps.csv's columns after the inputs are the methods, by registry id (`microshadow methods`): the closed
# forms, then the exact generic term (its azimuth mean), against which the others' errors are drawn.
INPUTS = ["roughness", "ndotv", "visibility", "ndotl"]
EXACT = "generic-vndf"
LABELS = {EXACT: "generic VNDF (exact, azimuth mean)"}
COLORS = ["k", "tab:blue", "tab:orange", "tab:green", "tab:purple", "tab:brown"]


def read_csv(path):
    with open(path, newline="") as f:
        rows = list(csv.DictReader(f))
    return {k: np.array([float(r[k]) for r in rows]) for k in rows[0].keys()}


def label(m):
    return LABELS.get(m, m)


def grid(d, rough, nv, key):
    sel = (d["roughness"] == rough) & (d["ndotv"] == nv)
    vis, nl, val = d["visibility"][sel], d["ndotl"][sel], d[key][sel]
    n = int(round(np.sqrt(sel.sum())))
    order = np.lexsort((vis, nl))  # rows = N.L, columns = Visibility
    return val[order].reshape(n, n)


def main():
    out = sys.argv[1]
    d = read_csv(os.path.join(out, "maps.csv"))
    older = [k for k in d if k not in INPUTS and k != EXACT]
    methods = older + [EXACT]
    colors = dict(zip(older, COLORS), **{EXACT: "tab:red"})
    roughs = sorted(set(d["roughness"]))
    nvs = sorted(set(d["ndotv"]), reverse=True)
    ext = [0, 1, 1, 0]  # x = Visibility left→right, y = N.L top→bottom (the LUT orientation of Zurita 2026b)

    for nv in nvs:
        fig, axes = plt.subplots(len(roughs), len(methods), figsize=(2.3 * len(methods), 2.2 * len(roughs)),
                                 constrained_layout=True)
        for i, r in enumerate(roughs):
            for j, m in enumerate(methods):
                ax = axes[i, j]
                im = ax.imshow(grid(d, r, nv, m), extent=ext, vmin=0, vmax=1, cmap="magma", aspect="auto")
                label_panel(ax, i, j, len(roughs), label(m), f"roughness {r:g}\nN·L")
        fig.colorbar(im, ax=axes, shrink=0.6)
        fig.suptitle(f"Micro-shadowing, N·V = {nv:g} (generic: mean over the relative azimuth)")
        fig.savefig(os.path.join(out, f"maps_ndotv_{nv:g}.png"), dpi=90)
        plt.close(fig)

    # Curves against Visibility at a few N.L.
    fig, axes = plt.subplots(2, 4, figsize=(16, 7), constrained_layout=True, sharey=True)
    for row, nv in enumerate([1.0, min(nvs)]):
        for col, r in enumerate([x for x in roughs if x > 0][:4]):
            ax = axes[row, col]
            for nl, ls in [(0.25, ":"), (0.5, "--"), (0.75, "-")]:
                sel = (d["roughness"] == r) & (d["ndotv"] == nv) & np.isclose(d["ndotl"], nl, atol=1e-9)
                if not sel.any():  # grid without this N.L: take the nearest row
                    nls = np.unique(d["ndotl"])
                    near = nls[np.argmin(np.abs(nls - nl))]
                    sel = (d["roughness"] == r) & (d["ndotv"] == nv) & (d["ndotl"] == near)
                vis = d["visibility"][sel]
                o = np.argsort(vis)
                for m in methods:
                    ax.plot(vis[o], d[m][sel][o], ls, color=colors[m], lw=1.2,
                            label=label(m) if nl == 0.75 else None)
            ax.set_title(f"roughness {r:g}, N·V = {nv:g}  (N·L: 0.25 dotted, 0.5 dashed, 0.75 solid)", fontsize=8)
            ax.set_xlabel("Visibility")
            ax.grid(alpha=0.3)
    axes[0, 0].legend(fontsize=7)
    fig.savefig(os.path.join(out, "curves.png"), dpi=90)
    plt.close(fig)

    # Error maps of the older terms against the exact generic term.
    for nv in [1.0, 0.5]:
        fig, axes = plt.subplots(len(roughs), len(older), figsize=(2.4 * len(older), 2.2 * len(roughs)),
                                 constrained_layout=True)
        for i, r in enumerate(roughs):
            g = grid(d, r, nv, EXACT)
            for j, m in enumerate(older):
                e = grid(d, r, nv, m) - g
                ax = axes[i, j]
                im = ax.imshow(e, extent=ext, vmin=-1, vmax=1, cmap="RdBu_r", aspect="auto")
                label_panel(ax, i, j, len(roughs), f"{label(m)}  rms {np.sqrt(np.mean(e ** 2)):.3f}",
                            f"roughness {r:g}\nN·L", title_size=7, every_title=True)
        fig.colorbar(im, ax=axes, shrink=0.6, label="term − exact generic")
        fig.suptitle(f"Error of the older terms vs the exact generic VNDF term, N·V = {nv:g}")
        fig.savefig(os.path.join(out, f"error_maps_ndotv_{nv:g}.png"), dpi=90)
        plt.close(fig)

    # Azimuth study.
    a = read_csv(os.path.join(out, "azimuth_error.csv"))
    fig, axes = plt.subplots(1, 3, figsize=(15, 4.5), constrained_layout=True)
    ax = axes[0]
    sc = ax.scatter(a["azimuth_mean"], a["exact"], c=a["phi"], s=4, cmap="viridis")
    ax.plot([0, 1], [0, 1], "k-", lw=0.8)
    ax.set_xlabel("azimuth mean (what a LUT stores)")
    ax.set_ylabel("exact term at the configuration's azimuth")
    fig.colorbar(sc, ax=ax, label="relative azimuth φ")
    ax = axes[1]
    for key, lab in [("error", "mean only"), ("error_h1", "+ cos φ"), ("error_h2", "+ cos 2φ"),
                     ("error_h4", "+ … cos 4φ")]:
        e = np.sort(np.abs(a[key]))
        ax.plot(e, np.linspace(0, 1, len(e)), label=lab)
    ax.axvline(0.5 / 255, color="gray", ls=":", label="0.5/255")
    ax.set_xscale("log")
    ax.set_xlim(1e-6, 1)
    ax.set_xlabel("|exact − approximation|")
    ax.set_ylabel("fraction of configurations")
    ax.legend(fontsize=8)
    ax.grid(alpha=0.3)
    ax = axes[2]
    ax.scatter(a["ndotv"], np.abs(a["error"]), s=4, c=a["roughness"], cmap="plasma")
    ax.set_xlabel("N·V")
    ax.set_ylabel("|exact − azimuth mean|")
    ax.set_title("ignoring the azimuth costs most at grazing N·V", fontsize=9)
    fig.savefig(os.path.join(out, "azimuth_error.png"), dpi=90)
    plt.close(fig)


if __name__ == "__main__":
    main()
