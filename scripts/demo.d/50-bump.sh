#!/usr/bin/env bash
# Bump terminator (docs/bump-terminator.md): the term against light angle for several perturbation angles, both
# methods (like Ray Tracing Gems fig. 12.4), a Conty-vs-Chiang comparison, and a few single evaluations.
set -euo pipefail
D="$OUT/bump"
mkdir -p "$D"
"$MSH" plot bump-terminator --out "$D" > "$D/plot_summary.json"
"$PYTHON" scripts/plot_bump_terminator.py "$D" > /dev/null
{
  for m in conty-2019 chiang-2019; do
    for l in 0,0,1 1,0,1 1,0,0.2 1,0,0.05; do
      "$MSH" eval bump-terminator --method "$m" --geometric-normal 0,0,1 --shading-normal 0.5,0,1 --light "$l" --json
    done
  done
} > "$D/eval_examples.jsonl"
echo "bump: $D/bump_terminator.png, $D/bump_terminator_compare.json, $D/eval_examples.jsonl" >&2
