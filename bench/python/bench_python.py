#!/usr/bin/python3
"""Evaluations per second through the Python module vs the same computation in plain numpy.

Usage: PYTHONPATH=build/python /usr/bin/python3 bench/python/bench_python.py [--n 4194304] [--repeat 5]

Inputs: n uniform random float32 values per argument (visibility, N.L, N.V, roughness in [0, 1]). Each row
is the best of --repeat calls: wall-clock evaluations per second and CPU seconds per call (all threads; the
module runs on oneTBB threads, numpy on one). The exact generic term is timed on a smaller array (it is a
quadrature per element). The LUT rows use the default table (baked once before timing) and, for numpy, a
seed-layout table with one roughness channel (trilinear fetch written with numpy fancy indexing).
"""
import argparse
import os
import time

import numpy as np

import microshadow as msh


def best(f, repeat):
    wall, cpu = [], []
    for _ in range(repeat):
        t0, c0 = time.perf_counter(), time.process_time()
        f()
        wall.append(time.perf_counter() - t0)
        cpu.append(time.process_time() - c0)
    return min(wall), min(cpu)


def numpy_trilinear(table, c, v, nl, nv):
    """Seed-layout LUT fetch of channel c as a GPU does it (docs/lut.md): texel coordinate x = u (n - 1),
    clamp-to-edge linear filtering on each axis."""
    nz, ny, nx, _ = table.shape

    def taps(u, n):
        x = np.clip(u, 0, 1) * np.float32(n - 1)
        i0 = np.minimum(x.astype(np.int32), n - 1)
        return i0, np.minimum(i0 + 1, n - 1), x - i0

    x0, x1, fx = taps(v, nx)
    y0, y1, fy = taps(nl, ny)
    z0, z1, fz = taps(nv, nz)
    t = table[..., c]

    def lerp(a, b, f):
        return a + (b - a) * f

    c00 = lerp(t[z0, y0, x0], t[z0, y0, x1], fx)
    c01 = lerp(t[z0, y1, x0], t[z0, y1, x1], fx)
    c10 = lerp(t[z1, y0, x0], t[z1, y0, x1], fx)
    c11 = lerp(t[z1, y1, x0], t[z1, y1, x1], fx)
    out = lerp(lerp(c00, c01, fy), lerp(c10, c11, fy), fz)
    return np.where(2 * v + nl < 1, np.float32(0), out)


def main():
    ap = argparse.ArgumentParser()
    ap.add_argument("--n", type=int, default=1 << 22)
    ap.add_argument("--n-exact", type=int, default=4096)
    ap.add_argument("--repeat", type=int, default=5)
    a = ap.parse_args()
    g = np.random.default_rng(1)
    v, nl, nv, r = (g.random(a.n, dtype=np.float32) for _ in range(4))
    rows = []

    def row(name, n, f):
        wall, cpu = best(f, a.repeat)
        rows.append((name, n / wall / 1e6, cpu))

    one = np.float32(1)
    row("chan-2018           module", a.n, lambda: msh.eval_micro_shadowing("chan-2018", v, nl))
    row("chan-2018           numpy", a.n, lambda: np.square(np.clip(nl / np.sqrt(one - v), 0, 1)))
    row("brinck-maximov-2016 module", a.n, lambda: msh.eval_micro_shadowing("brinck-maximov-2016", v, nl))
    row("brinck-maximov-2016 numpy", a.n, lambda: np.clip(nl + 2 * v * v - one, 0, 1))
    row("part1-analytic      module", a.n, lambda: msh.eval_micro_shadowing("part1-analytic", v, nl))
    with np.errstate(divide="ignore", invalid="ignore"):
        row("part1-analytic      numpy", a.n, lambda: np.where(
            (v == 0) | (v == 1), v, np.clip(nl / np.sqrt(one - v**5), 0, 1) ** (np.float32(0.75) / v)))

    msh.eval_micro_shadowing("lut3d", 0.9, 0.9, 0.5, 0.5)  # bakes the default table once (cached)
    row("lut3d (default cone) module", a.n, lambda: msh.eval_micro_shadowing("lut3d", v, nl, nv, r))
    row("lut3d +phi (H=3)     module", a.n, lambda: msh.eval_micro_shadowing(
        "lut3d", v, nl, nv, r, phi=np.float32(np.pi) * r))
    seed_t, _ = msh.bake_micro_shadowing_lut(layout="seed", n_vis=32, n_nl=32, n_nv=16, samples=256)
    row("lut (seed, 1 channel) numpy", a.n, lambda: numpy_trilinear(seed_t, 1, v, nl, nv))

    m = a.n_exact
    row("generic-vndf exact  module", m, lambda: msh.eval_micro_shadowing("generic-vndf", v[:m], nl[:m], nv[:m],
                                                                          r[:m]))
    row("generic-vndf 64 smp module", m, lambda: msh.eval_micro_shadowing(
        "generic-vndf", v[:m], nl[:m], nv[:m], r[:m], phi=np.float32(1.0), samples=64))

    print(f"n = {a.n} float32 elements ({a.n_exact} for generic-vndf), best of {a.repeat}, "
          f"{os.cpu_count()} CPUs")
    print(f"{'computation':32s} {'M evals/s':>10s} {'CPU s/call':>11s}")
    for name, rate, cpu in rows:
        print(f"{name:32s} {rate:10.2f} {cpu:11.4f}")


if __name__ == "__main__":
    main()
