#!/usr/bin/env bash
# docs/figures/three_grazing.png (docs/three.md): the three.js example with the sun 7° above the horizon, the
# left half without micro-shadowing, the right half with the recommended pair, rendered by headless chromium
# (SwiftShader WebGL2) at 1280x720. Needs the build (CLI at build/bin/microshadow or $1), chromium, and
# `npm ci` in tests/browser and integrations/three (scripts/install-deps.sh).
#   bash tools/research/three_figure.sh [path/to/microshadow] [OUT.png]
set -euo pipefail
root="$(cd "$(dirname "${BASH_SOURCE[0]}")/../.." && pwd)"
bin="${1:-$root/build/bin/microshadow}"
png="$(realpath -m "${2:-$root/docs/figures/three_grazing.png}")"
tmp="$(mktemp -d)"
"$bin" view --three --export "$tmp/three" > /dev/null
"$bin" view --root "$tmp/three" --port 0 > "$tmp/server.out" 2> "$tmp/server.err" &
pid=$!
trap 'kill -INT "$pid" 2> /dev/null; wait "$pid" 2> /dev/null; rm -rf "$tmp"' EXIT
url=""
for _ in $(seq 100); do
  url="$(grep -o 'http://[^ ]*' "$tmp/server.out" || true)"
  [ -n "$url" ] && break
  sleep 0.1
done
[ -n "$url" ] || { echo "three_figure: the server printed no URL: $(cat "$tmp/server.err")" >&2; exit 1; }
(cd "$root/tests/browser" && node three_test.mjs --url "$url" --out "$tmp/shots" --module "$tmp/three/microshadow-three" \
  --figure "$png" --figure-only > "$tmp/node.out") || { cat "$tmp/node.out" >&2; exit 1; }
grep -q '"errors":\[\]' "$tmp/shots/results.json" || { echo "three_figure: errors: $(cat "$tmp/shots/results.json")" >&2; exit 1; }
echo "wrote $png"
