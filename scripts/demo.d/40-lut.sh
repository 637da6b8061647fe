#!/usr/bin/env bash
# Micro-shadowing LUT (docs/lut.md): the default cone-layout tables and their as-used accuracy; the seed-layout
# tables in every format, the exact reference on N.V slices, and the figures (slices, error maps of the seed
# layout's 3D and 2D LUTs).
set -euo pipefail
D="$OUT/lut"
mkdir -p "$D"
# The default (cone-layout) tables, plain and azimuth-aware, and their as-used accuracy.
"$MSH" bake micro-shadowing --quiet --out "$D/micro_shadowing_lut_cone.dds" > "$D/bake_cone.json"
"$MSH" bake micro-shadowing --quiet --out "$D/micro_shadowing_lut_cone.npy" > /dev/null
"$MSH" bake micro-shadowing --quiet --2d --out "$D/micro_shadowing_lut_cone_2d.dds" > /dev/null
"$MSH" bake micro-shadowing --quiet --azimuth --out "$D/micro_shadowing_lut_cone_azimuth.dds" > "$D/bake_cone_azimuth.json"
"$MSH" verify micro-shadowing-lut "$D/micro_shadowing_lut_cone.dds" --samples 4000 --json > "$D/verify_cone.json"
"$MSH" verify micro-shadowing-lut "$D/micro_shadowing_lut_cone_azimuth.dds" --samples 4000 --against azimuth \
  --json > "$D/verify_cone_azimuth.json"
# The seed layout (the post's table) in every format; the slice figure and error maps are of this layout.
"$MSH" bake micro-shadowing --quiet --layout seed --out "$D/micro_shadowing_lut.npy" > "$D/bake_3d.json"
"$MSH" bake micro-shadowing --quiet --layout seed --out "$D/micro_shadowing_lut.dds" > /dev/null
"$MSH" bake micro-shadowing --quiet --layout seed --2d --out "$D/micro_shadowing_lut_2d.npy" > "$D/bake_2d.json"
"$MSH" bake micro-shadowing --quiet --layout seed --2d --out "$D/micro_shadowing_lut_2d.dds" > /dev/null
"$MSH" bake micro-shadowing --quiet --layout seed --2d --out "$D/micro_shadowing_lut_2d.ktx2" > /dev/null
"$MSH" bake micro-shadowing --quiet --layout seed --2d --out "$D/micro_shadowing_lut_2d.exr" > /dev/null
"$MSH" bake micro-shadowing --quiet --layout seed --2d --symbol micro_shadowing_lut_2d \
  --out "$D/micro_shadowing_lut_2d.h" > /dev/null
"$MSH" bake micro-shadowing --quiet --layout seed --azimuth --out "$D/micro_shadowing_lut_azimuth.dds" \
  > "$D/bake_azimuth.json"
"$MSH" plot micro-shadowing-lut --lut "$D/micro_shadowing_lut.npy" --lut2d "$D/micro_shadowing_lut_2d.npy" \
  --out "$D" > "$D/exact_slices_summary.json"
"$PYTHON" scripts/plot_lut.py "$D" > "$D/figures.json"
echo "lut: $(cat "$D/figures.json")" >&2
