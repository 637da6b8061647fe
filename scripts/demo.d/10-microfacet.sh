#!/usr/bin/env bash
# Microfacet core (docs/microfacet.md): the GGX directional albedo E(mu, alpha) against the three published
# values of docs/theory.md §2 (Blender Cycles' table_ggx_E), then a small grid of E and a few NDF evaluations.
set -euo pipefail
D="$OUT/microfacet"
mkdir -p "$D"
e() { "$MSH" eval microfacet --albedo --ndotv "$1" --alpha "$2" --json | "$PYTHON" -c 'import json,sys; print("%.6f" % json.load(sys.stdin)["E"])'; }
{
  echo "mu        alpha      E (ours)   published   |diff|"
  a2=$("$PYTHON" -c 'print((15/31)**2)')
  m2=$("$PYTHON" -c 'print(15/31)')
  for row in "1 1 0.306853" "1 $a2 0.926694" "$m2 1 0.457779"; do
    set -- $row
    ours=$(e "$1" "$2")
    "$PYTHON" -c "print('%-9.6f %-10.6f %-10s %-11s %.1e' % ($1, $2, '$ours', '$3', abs($ours - $3)))"
  done
  echo
  echo "E(mu, alpha), GGX, F = 1, height-correlated G2 (rows mu, columns alpha)"
  printf "%-6s" "mu"
  for a in 0.01 0.1 0.25 0.5 0.75 1; do printf " %9s" "$a"; done
  echo
  for mu in 0.05 0.25 0.5 0.75 1; do
    printf "%-6s" "$mu"
    for a in 0.01 0.1 0.25 0.5 0.75 1; do printf " %9s" "$(e "$mu" "$a")"; done
    echo
  done
} | tee "$D/ggx_albedo_table.txt" >&2
{
  for ndf in ggx beckmann blinn-phong gtr; do
    "$MSH" eval microfacet --ndf "$ndf" --alpha 0.3 --ndotv 0.5 --json
  done
  "$MSH" eval microfacet --ndf ggx --alpha 0.2 --alpha-y 0.5 --ndotv 0.3 --phi 0.7 --json
  "$MSH" eval microfacet --ndf gtr --alpha 0.3 --gamma 1 --ndotv 0.2 --json
} > "$D/eval_examples.jsonl"
echo "microfacet: $D/ggx_albedo_table.txt, $D/eval_examples.jsonl" >&2
