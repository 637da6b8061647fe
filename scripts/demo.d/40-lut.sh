#!/usr/bin/env bash
# Micro-shadowing LUT (docs/lut.md): the default tables in every format, the azimuth-aware table, the exact
# reference on N.V slices, and the figures (slices, error maps of the 3D and 2D LUTs).
set -euo pipefail
D="$OUT/lut"
mkdir -p "$D"
"$MSH" bake micro-shadowing --quiet --out "$D/micro_shadowing_lut.npy" > "$D/bake_3d.json"
"$MSH" bake micro-shadowing --quiet --out "$D/micro_shadowing_lut.dds" > /dev/null
"$MSH" bake micro-shadowing --quiet --2d --out "$D/micro_shadowing_lut_2d.npy" > "$D/bake_2d.json"
"$MSH" bake micro-shadowing --quiet --2d --out "$D/micro_shadowing_lut_2d.dds" > /dev/null
"$MSH" bake micro-shadowing --quiet --2d --out "$D/micro_shadowing_lut_2d.ktx2" > /dev/null
"$MSH" bake micro-shadowing --quiet --2d --out "$D/micro_shadowing_lut_2d.exr" > /dev/null
"$MSH" bake micro-shadowing --quiet --2d --symbol micro_shadowing_lut_2d --out "$D/micro_shadowing_lut_2d.h" > /dev/null
"$MSH" bake micro-shadowing --quiet --azimuth --out "$D/micro_shadowing_lut_azimuth.dds" > "$D/bake_azimuth.json"
"$MSH" plot micro-shadowing-lut --lut "$D/micro_shadowing_lut.npy" --lut2d "$D/micro_shadowing_lut_2d.npy" \
  --out "$D" > "$D/exact_slices_summary.json"
"$PYTHON" scripts/plot_lut.py "$D" > "$D/figures.json"
echo "lut: $(cat "$D/figures.json")" >&2
