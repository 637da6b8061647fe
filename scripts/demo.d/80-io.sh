#!/usr/bin/env bash
# File formats (docs/formats.md): a synthetic 3D RGBA volume converted to every format with
# `microshadow convert`, each result validated by the independent spec-based checker
# (tests/support/msh_iocheck.py), and a summary in $OUT/io/summary.json.
set -euo pipefail
D="$OUT/io"
mkdir -p "$D"
"$PYTHON" - "$D" <<'PY'
import sys, numpy as np
d = sys.argv[1]
z, y, x, c = np.meshgrid(np.arange(8), np.arange(16), np.arange(32), np.arange(4), indexing="ij")
v = (0.5 + 0.5 * np.sin(0.3 * x + 0.5 * y + 0.7 * z + 1.1 * c)).astype("<f4")   # (D, H, W, C) = (8, 16, 32, 4)
np.save(f"{d}/volume.npy", v)
v.tofile(f"{d}/volume.raw")
PY
CHECK="$PYTHON tests/support/msh_iocheck.py"
{
  "$MSH" convert "$D/volume.npy" "$D/volume_rgba16f.dds"
  "$MSH" convert "$D/volume.npy" "$D/volume_rgba8.dds" --pixel-format rgba8
  "$MSH" convert "$D/volume.npy" "$D/volume_rgba16f.ktx2"
  "$MSH" convert "$D/volume.npy" "$D/volume_rgba32f.ktx2" --pixel-format rgba32f
  "$MSH" convert "$D/volume.npy" "$D/volume_half.exr"
  "$MSH" convert "$D/volume.npy" "$D/volume_16bit.png"
  "$MSH" convert "$D/volume.npy" "$D/volume.h" --symbol demo_volume
  "$MSH" convert "$D/volume_rgba32f.ktx2" "$D/volume_roundtrip.npy"
} > "$D/convert.jsonl"
$CHECK dds "$D/volume_rgba16f.dds" "$D/volume.raw" 8 16 32 4 rgba16f > /dev/null
$CHECK dds "$D/volume_rgba8.dds" "$D/volume.raw" 8 16 32 4 rgba8 > /dev/null
$CHECK ktx2 "$D/volume_rgba16f.ktx2" "$D/volume.raw" 8 16 32 4 rgba16f > /dev/null
$CHECK ktx2 "$D/volume_rgba32f.ktx2" "$D/volume.raw" 8 16 32 4 rgba32f > /dev/null
$CHECK png "$D/volume_16bit.png" "$D/volume.raw" 8 16 32 4 16 > /dev/null
$CHECK npy "$D/volume_roundtrip.npy" "$D/volume.raw" 8 16 32 4 > /dev/null
"$PYTHON" - "$D" > "$D/summary.json" <<'PY'
import json, os, sys
d = sys.argv[1]
files = sorted(f for f in os.listdir(d) if f.startswith("volume") and not f.endswith(".raw"))
print(json.dumps({"validated_by_independent_checker": ["volume_rgba16f.dds", "volume_rgba8.dds",
                  "volume_rgba16f.ktx2", "volume_rgba32f.ktx2", "volume_16bit.png", "volume_roundtrip.npy"],
                  "files": {f: os.path.getsize(os.path.join(d, f)) for f in files}}))
PY
echo "io: $(cat "$D/summary.json")" >&2
