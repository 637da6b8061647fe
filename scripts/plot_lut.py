#!/usr/bin/python3
"""Figures of the micro-shadowing LUT (docs/lut.md), from the files `make demo` writes into DIR:

  DIR/micro_shadowing_lut.npy            3D LUT, shape (n_NV, n_NL, n_Vis, n_roughness)
  DIR/micro_shadowing_lut_2d.npy         2D LUT (N.V = 1), shape (1, n_NL, n_Vis, n_roughness)
  DIR/micro_shadowing_exact_slices.npy   exact azimuth mean on N.V slices (plot micro-shadowing-lut)
  DIR/micro_shadowing_exact_slices.json  which slices, roughness per channel

Writes DIR/lut_slices.png (Zurita 2026b's figure: roughness left to right, N.V top to bottom; in each panel
Visibility left to right and N.L top to bottom), DIR/lut_error_3d.png and DIR/lut_error_2d.png (LUT minus exact
on the same slices; the 2D LUT is used at every N.V, as an engine with only the 2D LUT would).
Usage: /usr/bin/python3 scripts/plot_lut.py DIR
"""
import json
import os
import sys

import matplotlib

matplotlib.use("Agg")
import matplotlib.pyplot as plt  # noqa: E402
import numpy as np  # noqa: E402
from figure_grid import label_panel  # noqa: E402


def grid(values, rows, roughness, title, path, cmap, vmin, vmax, label):
    n_rows, n_cols = values.shape[0], values.shape[-1]
    fig, axes = plt.subplots(n_rows, n_cols, figsize=(2.3 * n_cols + 1.2, 2.3 * n_rows + 0.6), squeeze=False)
    im = None
    for r in range(n_rows):
        for c in range(n_cols):
            ax = axes[r][c]
            # x = Visibility left -> right, y = N.L top -> bottom (row 0 = N.L 0 at the top).
            im = ax.imshow(values[r, :, :, c], origin="upper", extent=(0, 1, 1, 0), cmap=cmap, vmin=vmin,
                           vmax=vmax, interpolation="nearest")
            ax.set_xticks([0, 0.5, 1])
            ax.set_yticks([0, 0.5, 1])
            label_panel(ax, r, c, n_rows, f"roughness {roughness[c]:g}", f"N.V = {rows[r]:.3g}\nN.L", title_size=9)
    fig.suptitle(title, fontsize=10)
    fig.colorbar(im, ax=axes, shrink=0.6, label=label)
    fig.savefig(path, dpi=110)
    plt.close(fig)


def main():
    d = sys.argv[1] if len(sys.argv) > 1 else "out/lut"
    lut = np.load(os.path.join(d, "micro_shadowing_lut.npy"))
    lut2d = np.load(os.path.join(d, "micro_shadowing_lut_2d.npy"))
    exact = np.load(os.path.join(d, "micro_shadowing_exact_slices.npy"))
    meta = json.load(open(os.path.join(d, "micro_shadowing_exact_slices.json")))
    zs, nvs, rough = meta["slices_z"], meta["slices_n_dot_v"], meta["roughness"]
    assert lut.ndim == 4 and exact.shape[0] == len(zs), (lut.shape, exact.shape)

    grid(lut[zs], nvs, rough, "Micro-shadowing LUT slices (mean over azimuth of the generic VNDF term)",
         os.path.join(d, "lut_slices.png"), "gray", 0.0, 1.0, "value")
    err3 = lut[zs] - exact
    lim = 0.5 / 255.0
    grid(err3, nvs, rough,
         f"3D LUT minus exact at its texels (max |error| {np.abs(err3).max():.2e} = "
         f"{np.abs(err3).max() * 255:.2f}/255; scale ±0.5/255)",
         os.path.join(d, "lut_error_3d.png"), "RdBu_r", -lim, lim, "LUT - exact")
    err2 = np.broadcast_to(lut2d[0], exact.shape) - exact
    lim2 = max(0.05, float(np.abs(err2).max()))
    grid(err2, nvs, rough,
         f"2D LUT (N.V = 1) used at every N.V, minus exact (max |error| {np.abs(err2).max():.3f}, "
         f"mean {np.abs(err2).mean():.4f})",
         os.path.join(d, "lut_error_2d.png"), "RdBu_r", -lim2, lim2, "2D LUT - exact")
    print(json.dumps({"figures": ["lut_slices.png", "lut_error_3d.png", "lut_error_2d.png"],
                      "lut3d_max_abs_error": float(np.abs(err3).max()),
                      "lut2d_max_abs_error": float(np.abs(err2).max())}))


if __name__ == "__main__":
    main()
