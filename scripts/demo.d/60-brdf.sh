#!/usr/bin/env bash
# BRDF models part 1 (docs/brdf.md): sphere grids like RTR4 figs. 9.39 / 9.41 and the diffuse models, the GGX
# albedo and DFG tables in engine formats, directional albedos of every core model, and a few evaluations.
set -euo pipefail
D="$OUT/brdf"
mkdir -p "$D"
"$MSH" plot brdf-figures --out "$D" --size 96
"$MSH" bake ggx-albedo --size 32 --samples 16384 --pixel-format rgba32f --out "$D/ggx_albedo_32.npy"
"$MSH" bake ggx-albedo --size 32 --samples 16384 --pixel-format rg16f --out "$D/ggx_albedo_32.dds"
"$MSH" bake dfg --size 128 --samples 1024 --variant split-sum --out "$D/dfg_split_sum_128.dds"
"$MSH" bake dfg --size 128 --samples 1024 --variant multiscatter --pixel-format rgba16f --out "$D/dfg_multiscatter_128.ktx2"
"$MSH" bake dfg --size 64 --samples 2048 --variant multiscatter --pixel-format rg32f --out "$D/dfg_multiscatter_64.npy"
{
  "$MSH" eval brdf --model ggx --roughness 0.7 --fresnel none --albedo --ndotv 0.5 --json
  "$MSH" eval brdf --model ggx --roughness 0.7 --fresnel none --multiscatter on --albedo --ndotv 0.5 --json
  "$MSH" eval brdf --model ggx --roughness 0.4 --fresnel conductor --ndotv 0.8 --light 0.2,0.1,0.97 --json
  "$MSH" eval brdf --model ggx-ksk --roughness 0.6 --rho 1 --multiscatter on --albedo --ndotv 0.3 --json
  "$MSH" eval brdf --model oren-nayar --sigma 0.5 --ndotv 0.5 --light -0.5,0,0.866 --json
} > "$D/eval_examples.jsonl"
# Directional albedo (white furnace, rho = 1) of every core model at a few N.V.
{
  echo "model,ndotv,albedo_r"
  for m in ggx beckmann ggx-dual lambert lambert-fresnel-n lambert-fresnel-h shirley ksk hammon oren-nayar \
           oren-nayar-qualitative ggx-lambert ggx-ksk; do
    extra=""
    case "$m" in lambert*|shirley|ksk|hammon|oren-nayar*|ggx-lambert|ggx-ksk) extra="--rho 1" ;; esac
    for mu in 0.1 0.5 1; do
      echo "$m,$mu,$("$MSH" eval brdf --model "$m" $extra --albedo --ndotv "$mu" --samples 16384 | cut -d' ' -f1)"
    done
  done
} > "$D/white_furnace.csv"
"$PYTHON" scripts/plot_brdf_tables.py "$D" > /dev/null
echo "brdf: $D/spheres_*.png, $D/ggx_albedo.png, $D/*.dds|ktx2|npy, $D/white_furnace.csv, $D/eval_examples.jsonl" >&2
