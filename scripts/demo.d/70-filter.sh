#!/usr/bin/env bash
# Filtering demo (docs/filtering.md): a normal map whose slopes are i.i.d. Gaussian with a known per-axis
# standard deviation, filtered by `microshadow filter` with the three methods; prints the mean roughness per mip
# (as (mean α²)^(1/4), α = r²) next to the expected r' = (r0^4 + 2 s^2 (1 - 1/N))^(1/4), N = texels per footprint.
set -euo pipefail
: "${MSH:?}" "${OUT:?}" "${PYTHON:=/usr/bin/python3}"
dir="$OUT/filter"
mkdir -p "$dir"
S=0.12
R0=0.3
"$PYTHON" - "$dir/normal.png" "$S" <<'PY'
import struct, sys, zlib
import numpy as np
path, s = sys.argv[1], float(sys.argv[2])
w = h = 256
rng = np.random.default_rng(42)
b = rng.normal(0.0, s, size=(h, w, 2))
n = np.dstack([-b[..., 0], -b[..., 1], np.ones((h, w))])
n /= np.linalg.norm(n, axis=2, keepdims=True)
q = np.round((0.5 * n + 0.5) * 65535).astype('>u2')  # 16-bit RGB, n = 2c - 1
raw = b''.join(b'\x00' + q[y].tobytes() for y in range(h))
def chunk(t, d):
    return struct.pack('>I', len(d)) + t + d + struct.pack('>I', zlib.crc32(t + d) & 0xffffffff)
png = b'\x89PNG\r\n\x1a\n' + chunk(b'IHDR', struct.pack('>IIBBBBB', w, h, 16, 2, 0, 0, 0)) \
    + chunk(b'IDAT', zlib.compress(raw, 9)) + chunk(b'IEND', b'')
open(path, 'wb').write(png)
PY
for m in variance toksvig lean; do
  "$MSH" filter --normal "$dir/normal.png" --roughness-value "$R0" --out "$dir/$m/" --method "$m" --json \
    > "$dir/$m.json"
done
"$PYTHON" - "$dir" "$S" "$R0" <<'PY'
import json, sys
d, s, r0 = sys.argv[1], float(sys.argv[2]), float(sys.argv[3])
res = {m: json.load(open(f"{d}/{m}.json")) for m in ("variance", "toksvig", "lean")}
print(f"filter demo: 256x256 normal map, per-axis slope std {s}, base roughness {r0}")
print(" mip   size     N   expected  variance  toksvig   lean(x)  lean(y)")
for lv, lt, ll in zip(res["variance"]["levels"], res["toksvig"]["levels"], res["lean"]["levels"]):
    n = (256 // lv["width"]) ** 2
    exp = (r0 ** 4 + 2 * s * s * (1 - 1 / n)) ** 0.25
    r = lambda j, k="mean_alpha2": j[k] ** 0.25
    print(f" {lv['level']:3d} {lv['width']:4d}x{lv['height']:<4d} {n:5d}  {exp:.4f}    {r(lv):.4f}    "
          f"{r(lt):.4f}   {r(ll):.4f}   {r(ll, 'mean_alpha2_y'):.4f}")
PY
