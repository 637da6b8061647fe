#!/usr/bin/python3
"""The micro-shadowing figures of Zurita 2026 ("Improving Direct Lighting Material Occlusion - Part 2"),
computed through the Python module instead of the CSVs of `microshadow plot micro-shadowing`
(scripts/plot_micro_shadowing.py draws those): every method as a map over (Visibility, N.L), one row per
roughness, one figure per N.V; and the terms against Visibility at a few N.L.

Usage: PYTHONPATH=build/python /usr/bin/python3 examples/python/seed_figures.py --out DIR [--size 33]
Writes DIR/maps_ndotv_<nv>.png and DIR/curves.png.
"""
import argparse
import os

import matplotlib

matplotlib.use("Agg")
import matplotlib.pyplot as plt  # noqa: E402
import numpy as np  # noqa: E402

import microshadow as msh  # noqa: E402

METHODS = [
    ("reference", "reference step"),
    ("brinck-maximov-2016", "Brinck-Maximov 2016"),
    ("chan-2018", "Chan 2018"),
    ("part1-analytic", "Part 1 analytic"),
    ("generic-vndf", "generic VNDF (exact, azimuth mean)"),
    ("lut3d", "LUT (default table)"),
]
ROUGHNESS = [0.0, 0.1, 0.4, 0.7, 1.0]
NDOTV = [1.0, 0.5, 0.1]


def main():
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--out", required=True)
    ap.add_argument("--size", type=int, default=33, help="grid points per axis of the maps")
    a = ap.parse_args()
    os.makedirs(a.out, exist_ok=True)

    # One call per method over the whole (roughness, N.V, N.L, Visibility) grid: broadcasting, no loop.
    n = a.size
    vis = np.linspace(0, 1, n)[None, None, None, :]
    nl = np.linspace(0, 1, n)[None, None, :, None]
    nv = np.array(NDOTV)[None, :, None, None]
    rough = np.array(ROUGHNESS)[:, None, None, None]
    maps = {m: msh.eval_micro_shadowing(m, vis, nl, nv, rough) for m, _ in METHODS}

    ext = [0, 1, 1, 0]  # x = Visibility left to right, y = N.L top to bottom (the LUT orientation)
    for k, v in enumerate(NDOTV):
        fig, axes = plt.subplots(len(ROUGHNESS), len(METHODS), figsize=(2.3 * len(METHODS), 2.2 * len(ROUGHNESS)),
                                 constrained_layout=True)
        for i, r in enumerate(ROUGHNESS):
            for j, (m, label) in enumerate(METHODS):
                ax = axes[i, j]
                im = ax.imshow(maps[m][i, k], extent=ext, vmin=0, vmax=1, cmap="magma", aspect="auto")
                if i == 0:
                    ax.set_title(label, fontsize=8)
                if j == 0:
                    ax.set_ylabel(f"roughness {r:g}\nN·L", fontsize=8)
                if i == len(ROUGHNESS) - 1:
                    ax.set_xlabel("Visibility", fontsize=8)
                ax.tick_params(labelsize=6)
        fig.colorbar(im, ax=axes, shrink=0.6, label="micro-shadowing term")
        fig.suptitle(f"Micro-shadowing terms over (Visibility, N·L), N·V = {v:g}")
        fig.savefig(os.path.join(a.out, f"maps_ndotv_{v:g}.png"), dpi=110)
        plt.close(fig)

    # Curves: the terms against Visibility at N.L = 0.2, 0.5, 0.8, N.V = 1, per roughness.
    vv = np.linspace(0, 1, 201)
    fig, axes = plt.subplots(1, 3, figsize=(13, 4), constrained_layout=True)
    for ax, l in zip(axes, [0.2, 0.5, 0.8]):
        for m, label in METHODS[:4]:
            ax.plot(vv, msh.eval_micro_shadowing(m, vv, l), label=label)
        for r in [0.1, 0.4, 0.7, 1.0]:
            ax.plot(vv, msh.eval_micro_shadowing("generic-vndf", vv, l, 1.0, r), "--", label=f"generic r={r:g}")
        ax.set_title(f"N·L = {l:g}, N·V = 1")
        ax.set_xlabel("Visibility")
        ax.set_ylim(-0.02, 1.02)
    axes[0].set_ylabel("term")
    axes[-1].legend(fontsize=7)
    fig.savefig(os.path.join(a.out, "curves.png"), dpi=110)
    plt.close(fig)
    print(f"wrote {len(NDOTV) + 1} PNGs to {a.out}")


if __name__ == "__main__":
    main()
