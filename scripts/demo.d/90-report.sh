#!/usr/bin/env bash
# Renderer and report (docs/renderer.md): procedural texture sets, the comparison set (plaster plane and sphere,
# a directional light at several elevations, every micro-shadowing method side by side with the same exposure),
# the ray-traced height-field ground truth and each method's error against it, bump-terminator and Hanika
# figures, then $OUT/report.html gathering every area's figures.
set -euo pipefail
R="$OUT/render"
mkdir -p "$R/materials" "$R/plane" "$R/sphere" "$R/terminator"
SIZE=${RENDER_SIZE:-384}
"$MSH" gen-material --kind plaster --size 256 --out "$R/materials/plaster" > "$R/gen_plaster.json"
"$MSH" gen-material --kind bark --size 256 --out "$R/materials/bark" > "$R/gen_bark.json"

# The LUT area's table when its demo part ran; otherwise the LUT module's default table (baked in-process).
LUT=()
[[ -f "$OUT/lut/micro_shadowing_lut.npy" ]] && LUT=(--lut "$OUT/lut/micro_shadowing_lut.npy")
# The study's methods, from the method table (`microshadow methods`); the report reads their labels there.
"$MSH" methods --study --json > "$R/methods.json"
METHODS=$("$MSH" methods --study --names)
SMOOTH_METHODS=$("$MSH" methods --study --uses-ndotl --names)
COMMON=(--assets "$R" --width "$SIZE" --height "$SIZE" --quiet "${LUT[@]}")
: > "$R/renders.jsonl"
for el in 10 25 45; do
  "$MSH" render examples/plaster_plane.json "${COMMON[@]}" --spp 4 --vndf-samples 16 --light-elevation "$el" \
    --method "$METHODS" --out "$R/plane/el${el}" | sed "s/^{/{\"scene\":\"plane\",\"elevation\":$el,/" >> "$R/renders.jsonl"
  # Ground truth: the height map as ray-traced micro-geometry, 16 samples per pixel.
  "$MSH" render examples/plaster_plane.json "${COMMON[@]}" --spp 16 --light-elevation "$el" \
    --method ground-truth --out "$R/plane/el${el}_ground-truth" |
    sed "s/^{/{\"scene\":\"plane\",\"elevation\":$el,/" >> "$R/renders.jsonl"
  # Ablation: N·L and N·V of the term from the unperturbed normal (the bake's frame) instead of the shading normal.
  "$MSH" render examples/plaster_plane.json "${COMMON[@]}" --spp 4 --vndf-samples 16 --light-elevation "$el" \
    --ms-normal smooth --method "$SMOOTH_METHODS" --out "$R/plane/el${el}_smooth" > /dev/null
  "$MSH" render examples/plaster_sphere.json "${COMMON[@]}" --spp 4 --vndf-samples 16 --light-elevation "$el" \
    --method "$METHODS" --out "$R/sphere/el${el}" | sed "s/^{/{\"scene\":\"sphere\",\"elevation\":$el,/" >> "$R/renders.jsonl"
done
: > "$R/errors.jsonl"
for el in 10 25 45; do
  for m in ${METHODS//,/ }; do
    "$MSH" compare "$R/plane/el${el}_$m.exr" "$R/plane/el${el}_ground-truth.exr" --downsample 8 \
      --diff "$R/plane/el${el}_${m}_diff.png" | sed "s/^{/{\"elevation\":$el,\"method\":\"$m\",/" >> "$R/errors.jsonl"
  done
  for m in ${SMOOTH_METHODS//,/ }; do
    "$MSH" compare "$R/plane/el${el}_smooth_$m.exr" "$R/plane/el${el}_ground-truth.exr" --downsample 8 |
      sed "s/^{/{\"elevation\":$el,\"method\":\"smooth:$m\",/" >> "$R/errors.jsonl"
  done
done
# Bump terminator on a strongly normal-mapped sphere (every method of `methods --bump`; the report reads their
# labels there), and the Hanika offset on a low-poly sphere.
"$MSH" methods --bump --json > "$R/bump_methods.json"
for b in $("$MSH" methods --bump --names | tr , ' '); do
  "$MSH" render examples/bump_sphere.json --assets "$R" --quiet --bump-terminator "$b" \
    --out "$R/terminator/bump_$b" > /dev/null
done
"$MSH" render examples/lowpoly_sphere.json --quiet --no-hanika --out "$R/terminator/lowpoly_no_offset" > /dev/null
"$MSH" render examples/lowpoly_sphere.json --quiet --hanika --out "$R/terminator/lowpoly_hanika" > /dev/null
"$MSH" render examples/meshes_and_lights.json --quiet --out "$R/terminator/meshes_representative" > /dev/null
"$MSH" render examples/meshes_and_lights.json --quiet --area-lights --out "$R/terminator/meshes_area" > /dev/null
"$PYTHON" scripts/render_report.py "$OUT"
echo "render: $OUT/report.html" >&2
