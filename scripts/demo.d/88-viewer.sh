#!/usr/bin/env bash
# The browser viewer (docs/viewer.md): a static copy of the page, the GLSL files, the built-in plaster and the
# default tables in $OUT/viewer/. Serve it with `microshadow view --root $OUT/viewer` (or
# `microshadow view` for the live one) and open the printed URL.
set -euo pipefail
"$MSH" view --export "$OUT/viewer" --cache "$BUILD/viewer_cache" > /dev/null
echo "viewer: $OUT/viewer/ (serve: $MSH view --root $OUT/viewer, then open the URL it prints)" >&2
