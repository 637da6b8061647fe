#!/usr/bin/env python3
"""Plots the baked GGX albedo table (demo part 60): E(mu) for several roughness values, the averages Ebar(r), and
the multiscatter DFG channels. Usage: plot_brdf_tables.py DIR (reads DIR/ggx_albedo_32.npy, DIR/dfg_multiscatter_64.npy)."""
import sys
import numpy as np
import matplotlib
matplotlib.use("Agg")
import matplotlib.pyplot as plt

d = sys.argv[1]
e = np.load(f"{d}/ggx_albedo_32.npy")[0]  # (height = r, width = mu, channels: E, Ebar, E_Fc, Ebar_Fc)
n = e.shape[1]
mu = np.arange(n) / (n - 1)
fig, ax = plt.subplots(1, 3, figsize=(15, 4.2))
for j in range(0, n, 5):
    ax[0].plot(mu, e[j, :, 0], label=f"r = {j / (n - 1):.2f}")
ax[0].set(xlabel="N.V", ylabel="E(N.V, r)", title="GGX single-scattering albedo, F = 1")
ax[0].legend(fontsize=7)
r = np.arange(n) / (n - 1)
ax[1].plot(r, e[:, 0, 1], label="Ebar(r) (9.57)")
ax[1].plot(r, e[:, 0, 3], label="Ebar_Fc(r)")
ax[1].set(xlabel="perceptual roughness r", title="cosine-weighted averages")
ax[1].legend()
dfg = np.load(f"{d}/dfg_multiscatter_64.npy")[0]
im = ax[2].imshow(dfg[:, :, 1], origin="lower", extent=[0, 1, 0, 1], vmin=0, vmax=1)
ax[2].set(xlabel="N.V", ylabel="r", title="multiscatter DFG.y = E (Filament layout)")
fig.colorbar(im, ax=ax[2])
fig.tight_layout()
fig.savefig(f"{d}/ggx_albedo.png", dpi=110)
print(f"{d}/ggx_albedo.png")
