#!/usr/bin/python3
"""Fits the 8 coefficients of the ALU-only micro-shadowing approximation (generic_vndf_alu in
include/microshadow/occlusion/micro_shadowing_fit.h; docs/micro-shadowing.md, "ALU-only approximation") to the
exact azimuth-mean term, and validates them on an independent set.

    microshadow plot micro-shadowing-fit --out train.csv --samples 40000 --seed 1 --near-step 8000 --skip-early-out
    microshadow plot micro-shadowing-fit --out val.csv --samples 20000 --seed 2
    /usr/bin/python3 scripts/fit_micro_shadowing.py train.csv [--validate val.csv]

Least squares (scipy.optimize.least_squares, trust region) on the training points, starting from the
physical values (a = alpha, q = a^2: p = 1,0,0,0, 1,0,0,0). Prints the coefficients as the C++ array, then
the RMS / p99 / max error (in 1/255) of this script's float64 model on the training and validation sets.
The validation CSV's `alu` column is the C++ float function itself: its statistics are printed by the CLI.
Needs python3-numpy and python3-scipy (Debian packages).
"""
import argparse
import itertools
import sys

import numpy as np
from scipy.optimize import least_squares


def load(path):
    d = np.genfromtxt(path, delimiter=",", names=True)
    return d["visibility"], d["ndotl"], d["ndotv"], d["roughness"], d["exact"]


def model(p, V, nl, nv, r):
    """generic_vndf_alu in float64 (same formula as the C++ header)."""
    alpha = np.maximum(r * r, 1e-4)
    c, s = np.sqrt(1 - V), np.sqrt(V)
    nl2 = nl * nl
    sl = np.sqrt(np.maximum(0.0, 1 - nl2))
    d = s * nl - c * sl
    k = nv / (nv + alpha)
    a = alpha * (p[0] + p[1] * r + p[2] * V + p[3] * k)
    a2 = a * a
    q = a2 * (p[4] + p[5] * r + p[6] * V + p[7] * k)
    p1 = 1 + d / np.sqrt(a2 + (1 - a2) * d * d)
    p2 = 1 + nl / np.sqrt(a2 + (1 - a2) * nl2)
    f = V * p1 / ((V + (1 - V) * q) * p2)
    f = np.where(2 * V + nl < 1, 0.0, f)
    return np.clip(f, 0, 1)


def report(name, err, r):
    a = np.abs(err) * 255
    print(f"{name}: n {len(a)}  RMS {np.sqrt(np.mean(a ** 2)):.2f}/255  p99 {np.quantile(a, 0.99):.2f}/255"
          f"  max {a.max():.2f}/255")
    for lo, hi in [(0.1, 0.25), (0.25, 0.55), (0.55, 1.0 + 1e-12)]:
        m = (r >= lo) & (r < hi)
        if m.any():
            print(f"    r in [{lo:.2f}, {hi:.2f}): RMS {np.sqrt(np.mean(a[m] ** 2)):.2f}  "
                  f"p99 {np.quantile(a[m], 0.99):.2f}  max {a[m].max():.2f}")


def main():
    ap = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
    ap.add_argument("train")
    ap.add_argument("--validate")
    args = ap.parse_args()
    V, nl, nv, r, f = load(args.train)
    p0 = np.array([1.0, 0, 0, 0, 1.0, 0, 0, 0])
    fit = least_squares(lambda p: model(p, V, nl, nv, r) - f, p0, method="trf", x_scale="jac", max_nfev=5000)
    p = fit.x
    # Both linear forms must stay positive on the input cube: k = N.V/(N.V + alpha) <= 1/(1 + alpha).
    for rr, vv, kk in itertools.product([0.0, 0.1, 1.0], [0.0, 1.0], [0.0, 1.0]):
        kk = min(kk, 1 / (1 + max(rr * rr, 1e-4)))
        b = np.array([1, rr, vv, kk])
        if not (b @ p[:4] > 0 and b @ p[4:] > 0):
            sys.exit(f"fit_micro_shadowing: a linear form is not positive at r={rr} V={vv} k={kk}")
    print("inline constexpr std::array<double, 8> kGenericVndfAluCoeffs = {"
          + ", ".join(f"{x:.6g}" for x in p) + "};")
    report("train (fitted model, float64)", model(p, V, nl, nv, r) - f, r)
    if args.validate:
        V, nl, nv, r, f = load(args.validate)
        report("validation (fitted model, float64)", model(p, V, nl, nv, r) - f, r)


if __name__ == "__main__":
    main()
