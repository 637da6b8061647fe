#!/usr/bin/python3
"""Draws the bump-terminator figure from the CSVs of `microshadow plot bump-terminator --out DIR`.

Usage: /usr/bin/python3 scripts/plot_bump_terminator.py DIR   -> DIR/bump_terminator.png
Panels: (a) Conty 2019 term vs light angle for several perturbation angles (like Ray Tracing Gems fig. 12.4);
(b) Chiang 2019 with the shading normal tilted toward the light, (c) both overlaid;
(d) a Lambert-shaded surface across the geometric terminator with and without the fix.
"""
import csv
import os
import sys

import matplotlib

matplotlib.use("Agg")
import matplotlib.pyplot as plt  # noqa: E402


def read(path):
    with open(path, newline="") as f:
        return list(csv.DictReader(f))


def main():
    if len(sys.argv) != 2:
        sys.exit("usage: plot_bump_terminator.py DIR")
    d = sys.argv[1]
    curves = read(os.path.join(d, "bump_terminator_curves.csv"))
    shading = read(os.path.join(d, "bump_terminator_shading.csv"))

    def series(method, delta, phi):
        rows = [r for r in curves if r["method"] == method and float(r["perturbation_deg"]) == delta
                and float(r["phi_deg"]) == phi]
        return [float(r["light_deg"]) for r in rows], [float(r["value"]) for r in rows]

    deltas = sorted({float(r["perturbation_deg"]) for r in curves})
    cmap = plt.get_cmap("viridis")
    colors = {dl: cmap(i / max(1, len(deltas) - 1)) for i, dl in enumerate(deltas)}

    def every_delta(ax, method, title):
        for dl in deltas:
            x, y = series(method, dl, 0.0)
            ax.plot(x, y, color=colors[dl], label=f"θd = {dl:g}°")
        ax.set_title(title)
        ax.legend(fontsize=8, loc="lower left")

    fig, axes = plt.subplots(2, 2, figsize=(11, 8.5))
    every_delta(axes[0][0], "conty-2019", "(a) Conty Estevez et al. 2019: G1 with α² = tan²θd / 8")
    every_delta(axes[0][1], "chiang-2019", "(b) Chiang et al. 2019, N_s tilted toward the light")

    ax = axes[1][0]
    for dl in (5.0, 20.0, 45.0, 75.0):
        x, y = series("conty-2019", dl, 0.0)
        ax.plot(x, y, color=colors[dl], label=f"θd = {dl:g}°: Conty (solid), Chiang (dashed)")
        x, y = series("chiang-2019", dl, 0.0)
        ax.plot(x, y, color=colors[dl], ls="--")
    ax.set_title("(c) both, N_s toward the light (Chiang = 1 if tilted sideways)")
    ax.legend(fontsize=8, loc="lower left")

    for a in (axes[0][0], axes[0][1], axes[1][0]):
        a.set_xlabel("light angle to the geometric normal θi (deg)")
        a.set_ylabel("shadowing term")
        a.set_xlim(0, 90)
        a.set_ylim(-0.02, 1.02)
        a.grid(alpha=0.3)

    ax = axes[1][1]
    styles = {10.0: "-", 30.0: "--"}
    for dl, ls in styles.items():
        rows = [r for r in shading if float(r["perturbation_deg"]) == dl]
        x = [float(r["light_deg"]) for r in rows]
        for key, col in (("none", "k"), ("conty-2019", "tab:blue"), ("chiang-2019", "tab:red")):
            ax.plot(x, [float(r[key]) for r in rows], color=col, ls=ls, label=f"{key}, θd = {dl:g}°")
    ax.axvline(90, color="gray", lw=0.8)
    ax.set_title("(d) Lambert max(0, N_s·L)·term, geometric shadow past 90°")
    ax.set_xlabel("light angle to the geometric normal θi (deg)")
    ax.set_ylabel("shaded value")
    ax.set_xlim(40, 110)
    ax.grid(alpha=0.3)
    ax.legend(fontsize=8)

    fig.suptitle("Bump-terminator terms (N_s tilted by θd; light at θi from N_g)")
    fig.tight_layout()
    out = os.path.join(d, "bump_terminator.png")
    fig.savefig(out + ".tmp.png", dpi=110)
    os.replace(out + ".tmp.png", out)
    print(out)


if __name__ == "__main__":
    main()
