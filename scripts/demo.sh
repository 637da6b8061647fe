#!/usr/bin/env bash
# The main job: runs every part in scripts/demo.d/ in name order, each with BUILD and OUT set.
# Each part writes under $OUT; out/report.html gathers them.
set -euo pipefail
BUILD=${1:-build}
OUT=${2:-out}
export BUILD OUT
export MSH="$BUILD/bin/microshadow"
export PYTHON=/usr/bin/python3
mkdir -p "$OUT"
for part in scripts/demo.d/*.sh; do
  echo "== demo: $(basename "$part")" >&2
  bash "$part"
done
echo "demo: outputs in $OUT/" >&2
