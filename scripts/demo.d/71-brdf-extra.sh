#!/usr/bin/env bash
# Sphere grids of the cloth / thin-film / clear-coat models (docs/brdf-extra.md), shaded analytically by
# `microshadow plot brdf-spheres` (key light front-left + rim light behind). Rows: Imageworks sheen (α = 0.15,
# 0.25, 0.40, 0.65, 1.0 as in RTR4 Fig. 9.43, over nothing), velvet 9.73–9.74, Uncharted 2 rim, wrap lighting,
# Kajiya-Kay exponents, thin film thickness 100–700 nm, clear coat roughness.
set -euo pipefail
: "${MSH:?}" "${OUT:?}"
dir="$OUT/brdf-extra"
mkdir -p "$dir"
"$MSH" plot brdf-spheres --out "$dir/cloth_spheres.png" --size 128 \
  --row "imageworks-sheen:roughness=0.387,0.5,0.632,0.806,1.0:sheen-color=1,1,1" \
  --row "velvet-cloth:alpha=0.15,0.3,0.5,0.75,1.0:base-color=0.5,0.1,0.1" \
  --row "uncharted2-cloth:k-rim=0,0.25,0.5,0.75,1:base-color=0.2,0.3,0.7" \
  --row "wrap-diffuse:wrap=0,0.25,0.5,0.75,1:scatter-color=0.4,0.1,0.05:base-color=0.8,0.6,0.5" \
  --row "kajiya-kay:exponent=4,16,64,256,1024:diffuse=0.1,0.05,0.02:specular=0.8,0.6,0.3" > /dev/null
"$MSH" plot brdf-spheres --out "$dir/layered_spheres.png" --size 128 \
  --row "thin-film:thickness=100,250,400,550,700:roughness=0.45" \
  --row "clearcoat:coat-roughness=0,0.1,0.2,0.4,0.7:base-color=0.6,0.05,0.05:coat-tint=0.9,0.9,0.6" \
  --row "clearcoat:metallic=0,0.25,0.5,0.75,1:coat-normal=-0.4,0,1:coat-roughness=0.1:base-roughness=0.6:base-color=0.9,0.6,0.3" \
  > /dev/null
echo "brdf-extra: $dir/cloth_spheres.png, $dir/layered_spheres.png"
