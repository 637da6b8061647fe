#!/usr/bin/env bash
# The multiscale study, reduced (docs/study.md): a fine plaster height field as the real surface, coarse texture
# sets at 1/k (k = 1, 4, 16), every micro-shadowing term against the ray-traced ground truth. Writes
# $OUT/study/results.json, results.csv, summary.md, study.html; the report's first screen shows its verdict.
# The full study: `microshadow study --out DIR` (8 minutes on 2 idle cores; see docs/study.md).
set -euo pipefail
"$MSH" study --quick --out "$OUT/study" > "$OUT/study.json"
echo "study: $OUT/study/study.html" >&2
