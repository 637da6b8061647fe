#!/usr/bin/env bash
# Micro-shadowing (docs/micro-shadowing.md): every term over (Visibility, N.L) for roughness 0-1 and several N.V
# (the plots of Zurita 2026b), error maps of the older terms against the exact generic VNDF term, the cost of ignoring
# the azimuth, an exact-vs-Monte-Carlo check, and a few single evaluations.
set -euo pipefail
D="$OUT/micro-shadowing"
mkdir -p "$D"
"$MSH" plot micro-shadowing --out "$D" --mc-samples 1048576 > "$D/plot_summary.json"
"$PYTHON" scripts/plot_micro_shadowing.py "$D"
{
  for m in reference brinck-maximov-2016 chan-2018 part1-analytic generic-vndf; do
    "$MSH" eval micro-shadowing --method "$m" --visibility 0.7 --roughness 0.4 --ndotl 0.6 --ndotv 0.8 --json
  done
  "$MSH" eval micro-shadowing --method generic-vndf --visibility 0.7 --roughness 0.4 --ndotl 0.6 --ndotv 0.8 \
    --phi 2.5 --json
  "$MSH" eval micro-shadowing --method generic-vndf --visibility 0.7 --roughness 0.4 --ndotl 0.6 --ndotv 0.8 \
    --phi 2.5 --samples 16 --json
} > "$D/eval_examples.jsonl"
echo "micro-shadowing: $D/maps_ndotv_*.png, error_maps_*.png, curves.png, azimuth_error.png, summary.json" >&2
