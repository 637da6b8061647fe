#!/usr/bin/python3
"""Fits the coefficients of the ALU-only diffuse micro-BRDF-aware term diffuse_aware_alu
(include/microshadow/occlusion/micro_shadowing_aware_fit.h; docs/micro-shadowing-aware.md, "Run-time form of
the diffuse-aware term") to the exact azimuth-mean term diffuse_aware_exact_azimuth_mean (reciprocal form).

    microshadow plot micro-shadowing-fit --term diffuse-aware --out rec.csv --samples 4000 --seed 1 \\
        --near-step 500 --skip-early-out
    /usr/bin/python3 tools/research/fit_micro_shadowing_aware.py rec.csv

The model is the header's, in float64: f = Pcap * T_l L_l * T_v L_v, cubic forms in (r, cos_t, w), started
from the generic term's two-stage coefficients (kGenericVndfAluTwoStage, read from micro_shadowing_fit.h).
Least squares (scipy.optimize.least_squares, trust region) on --train-rows rows drawn at random (numpy
default_rng(0)); the other rows are a holdout. Prints the C++ array and the training and holdout errors (in
1/255); the as-used error of the C++ float function at independent Sobol points is `microshadow verify
micro-shadowing-aware --method diffuse-aware-alu`. Needs python3-numpy and python3-scipy.
"""
import argparse
import os
import sys

import numpy as np
from scipy.optimize import least_squares

sys.path.insert(0, os.path.dirname(os.path.abspath(__file__)))
from fit_micro_shadowing import cubic, load, report  # noqa: E402  (the generic fit's basis and report)


def stretched_z(n, alpha):
    return n / np.sqrt(n * n + alpha * alpha * (1 - n * n))


def cone_factor(V, c, s, nx, a, g):
    a2 = a * a
    sx = np.sqrt(np.maximum(0.0, 1 - nx * nx))
    d = s * nx - c * sx
    inv_st = np.sqrt(a2 + (1 - a2) * V) / np.maximum(s, 1e-6)
    p1 = 1 + d / np.sqrt(a2 + (1 - a2) * d * d) * inv_st
    p2 = 1 + nx / np.sqrt(a2 + (1 - a2) * nx * nx)
    return p1 * (V + g * (1 - V) * (nx - 1)) / (V * p2)


def model(p, V, nl, nv, r):
    r = np.clip(r, 0.01, 1.0)
    alpha = r * r
    c, s = np.sqrt(1 - V), np.sqrt(V)
    wl, wv = stretched_z(nl, alpha), stretched_z(nv, alpha)
    a_l = alpha * np.exp2(cubic(p[0:20], r, c, wv))
    a_v = alpha * np.exp2(cubic(p[0:20], r, c, wl))
    q = alpha * alpha * np.exp2(cubic(p[20:40], r, c, wl * wv))
    f = (cone_factor(V, c, s, nl, a_l, cubic(p[40:60], r, c, wv))
         * cone_factor(V, c, s, nv, a_v, cubic(p[40:60], r, c, wl)) * V / (V + (1 - V) * q))
    zero = (2 * V + nl < 1) | (2 * V + nv < 1)
    return np.clip(np.where(zero, 0.0, f), 0, 1)


def generic_two_stage_coefficients():
    """kGenericVndfAluTwoStage from include/microshadow/occlusion/micro_shadowing_fit.h (the start)."""
    path = os.path.join(os.path.dirname(os.path.abspath(__file__)), "..", "..", "include", "microshadow",
                        "occlusion", "micro_shadowing_fit.h")
    text = open(path).read()
    body = text[text.index("kGenericVndfAluTwoStage = {"):]
    body = body[body.index("{") + 1:body.index("}")]
    return np.array([float(x) for x in body.replace("\n", " ").split(",") if x.strip()])


def main():
    ap = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
    ap.add_argument("train", help="CSV from `plot micro-shadowing-fit --term diffuse-aware`")
    ap.add_argument("--train-rows", type=int, default=2500, help="rows fitted (the rest: holdout)")
    ap.add_argument("--max-nfev", type=int, default=3000)
    args = ap.parse_args()
    V, nl, nv, r, exact = load(args.train)
    idx = np.random.default_rng(0).permutation(len(V))
    tr, ho = idx[:args.train_rows], idx[args.train_rows:]
    p0 = generic_two_stage_coefficients()
    fit = least_squares(lambda q: (model(q, V, nl, nv, r) - exact)[tr], p0, method="trf", x_scale="jac",
                        max_nfev=args.max_nfev)
    p = np.array([float(f"{x:.6g}") for x in fit.x])  # the printed (committed) precision
    print(f"inline constexpr std::array<double, {len(p)}> kDiffuseAwareAluReciprocal = {{"
          + ", ".join(f"{x:.6g}" for x in p) + "};")
    e = model(p, V, nl, nv, r) - exact
    report("train (float64)", e[tr], r[tr])
    if len(ho):
        report("holdout (float64)", e[ho], r[ho])


if __name__ == "__main__":
    main()
