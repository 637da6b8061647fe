#!/usr/bin/python3
"""Fits the coefficients of the ALU-only micro-shadowing approximations in
include/microshadow/occlusion/micro_shadowing_fit.h (docs/micro-shadowing.md, "ALU-only approximation") to the
exact azimuth-mean term, and checks them on an independent validation set.

    microshadow plot micro-shadowing-fit --out train.csv --samples 40000 --seed 1 --near-step 8000 \\
        --skip-early-out
    microshadow plot micro-shadowing-fit --out val.csv --samples 20000 --seed 2
    /usr/bin/python3 tools/research/fit_micro_shadowing.py train.csv --validate val.csv

Two models, both f = Pcap * P1 * L / P2 (see the header for the formulas):
  fast       generic_vndf_alu: linear forms in (r, V, k = N.V/(N.V + alpha)), 9 coefficients, 40 operations;
  two-stage  generic_vndf_alu_pixel / generic_vndf_alu_light: cubic forms in (r, cos_t, w_z) (a and q through
             exp2), the light's cone term pinned to 0 at the early-out boundary, 60 coefficients; per-light cost
             23 operations.
Least squares (scipy.optimize.least_squares, trust region) on the training points, then --reweight passes
weighted by sqrt(1 + (e/tau)^2) of the previous residual e (pulls the max down). Prints each model's
coefficients as the C++ array and its RMS / p99 / max error (in 1/255) in float64 on the training and
validation sets; `plot micro-shadowing-fit` measures the C++ float functions themselves.
Needs python3-numpy and python3-scipy (Debian packages).
"""
import argparse
import sys

import numpy as np
from scipy.optimize import least_squares


def load(path):
    d = np.genfromtxt(path, delimiter=",", names=True)
    return d["visibility"], d["ndotl"], d["ndotv"], d["roughness"], d["exact"]


def common(V, nl, nv, r):
    r = np.clip(r, 0.01, 1.0)
    alpha = r * r
    c, s = np.sqrt(1 - V), np.sqrt(V)
    nl2 = nl * nl
    sl = np.sqrt(np.maximum(0.0, 1 - nl2))
    return r, alpha, c, s, nl2, sl, s * nl - c * sl


def fast(p, V, nl, nv, r):
    """generic_vndf_alu in float64 (same operations as the C++ header)."""
    r, alpha, c, s, nl2, sl, d = common(V, nl, nv, r)
    k = nv / (nv + alpha)
    a = alpha * (p[0] + p[1] * r + p[2] * V + p[3] * k)
    a2 = a * a
    q = a2 * (p[4] + p[5] * V + p[6] * k)
    g = (p[7] + p[8] * r) * (1 - V)
    p1 = 1 + d / np.sqrt(a2 + (1 - a2) * d * d)
    p2 = 1 + nl / np.sqrt(a2 + (1 - a2) * nl2)
    f = p1 * (V + g * (nl - 1)) / ((V + (1 - V) * q) * p2)
    return np.clip(np.where(2 * V + nl < 1, 0.0, f), 0, 1)


def cubic(p, x, y, z):
    """The 20-term cubic of the header, in its order: 1, x, y, z, x², y², z², xy, xz, yz, x³, y³, z³, x²y, x²z,
    y²x, y²z, z²x, z²y, xyz."""
    return (p[0] + p[1] * x + p[2] * y + p[3] * z + p[4] * x * x + p[5] * y * y + p[6] * z * z + p[7] * x * y
            + p[8] * x * z + p[9] * y * z + p[10] * x ** 3 + p[11] * y ** 3 + p[12] * z ** 3 + p[13] * x * x * y
            + p[14] * x * x * z + p[15] * y * y * x + p[16] * y * y * z + p[17] * z * z * x + p[18] * z * z * y
            + p[19] * x * y * z)


def two_stage(p, V, nl, nv, r):
    """generic_vndf_alu_pixel + generic_vndf_alu_light in float64."""
    r, alpha, c, s, nl2, sl, d = common(V, nl, nv, r)
    wz = nv / np.sqrt(nv * nv + alpha * alpha * (1 - nv * nv))
    a = alpha * np.exp2(cubic(p[0:20], r, c, wz))
    a2 = a * a
    q = a2 * np.exp2(cubic(p[20:40], r, c, wz))
    g = cubic(p[40:60], r, c, wz) * (1 - V)
    inv_st = np.sqrt(a2 + (1 - a2) * V) / np.maximum(s, 1e-6)
    p1 = 1 + d / np.sqrt(a2 + (1 - a2) * d * d) * inv_st
    p2 = 1 + nl / np.sqrt(a2 + (1 - a2) * nl2)
    f = p1 * (V + g * (nl - 1)) / ((V + (1 - V) * q) * p2)
    return np.clip(np.where(2 * V + nl < 1, 0.0, f), 0, 1)


MODELS = {
    # name: (model, start, C++ array, default reweighted passes; on the fast form they lower neither error)
    "fast": (fast, np.array([1.0, 0, 0, 0, 1.0, 0, 0, 0, 0]), "kGenericVndfAluFast", 0),
    "two-stage": (two_stage, np.zeros(60), "kGenericVndfAluTwoStage", 1),
}


def report(name, err, r):
    a = np.abs(err) * 255
    print(f"  {name}: n {len(a)}  RMS {np.sqrt(np.mean(a ** 2)):.2f}/255  p99 {np.quantile(a, 0.99):.2f}/255"
          f"  max {a.max():.2f}/255")
    for lo, hi in [(0.1, 0.25), (0.25, 0.55), (0.55, 1.0 + 1e-12)]:
        m = (r >= lo) & (r < hi)
        if m.any():
            print(f"      r in [{lo:.2f}, {min(hi, 1):.2f}{')' if hi < 1 else ']'}: RMS {np.sqrt(np.mean(a[m] ** 2)):.2f}"
                  f"  p99 {np.quantile(a[m], 0.99):.2f}  max {a[m].max():.2f}")


def main():
    ap = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
    ap.add_argument("train", help="CSV from `plot micro-shadowing-fit` (training seed)")
    ap.add_argument("--validate", help="CSV from `plot micro-shadowing-fit` (another seed)")
    ap.add_argument("--model", choices=list(MODELS) + ["all"], default="all")
    ap.add_argument("--reweight", type=int,
                    help="reweighted least-squares passes after the plain fit (default: fast 0, two-stage 1)")
    ap.add_argument("--tau", type=float, default=3.0, help="reweighting scale, in 1/255 (default 3)")
    args = ap.parse_args()
    train = load(args.train)
    val = load(args.validate) if args.validate else None
    for name, (model, p0, cname, passes) in MODELS.items():
        if args.model not in ("all", name):
            continue
        fit = least_squares(lambda p: model(p, *train[:4]) - train[4], p0, method="trf", x_scale="jac",
                            max_nfev=8000)
        if not fit.success:
            sys.exit(f"fit_micro_shadowing: {name}: {fit.message}")
        p = fit.x
        # Reweighted passes toward a smaller max: weight sqrt(1 + (e/tau)^2) from the previous residual e.
        for _ in range(passes if args.reweight is None else args.reweight):
            w = np.sqrt(1 + ((model(p, *train[:4]) - train[4]) / (args.tau / 255)) ** 2)
            fit = least_squares(lambda q: (model(q, *train[:4]) - train[4]) * w, p, method="trf",
                                x_scale="jac", max_nfev=3000)
            p = fit.x
        print(f"{name}:")
        print(f"  inline constexpr std::array<double, {len(p)}> {cname} = {{"
              + ", ".join(f"{x:.6g}" for x in p) + "};")
        report("train (float64)", model(p, *train[:4]) - train[4], train[3])
        if val is not None:
            report("validation (float64)", model(p, *val[:4]) - val[4], val[3])


if __name__ == "__main__":
    main()
