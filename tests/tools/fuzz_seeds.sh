#!/usr/bin/env bash
# Seeds for the fuzzers, written by Sinew itself from the bundled assets: a .glb of the walk, the
# walk's coefficients and an evolved controller for it, and a checkpoint of a search on the hopper.
# Usage: fuzz_seeds.sh SINEW SOURCE_DIR OUT_DIR
set -euo pipefail
sinew=$1
source_dir=$2
out=$3
rm -rf "$out"
mkdir -p "$out/gltf" "$out/coefficients" "$out/checkpoint" "$out/work"
walk="$source_dir/assets/biped_walk.bvh"
"$sinew" convert "$walk" "$out/gltf/walk.glb" >/dev/null
"$sinew" convert "$walk" "$out/gltf/walk.gltf" >/dev/null
"$sinew" style --neutral "$walk" --styled "$walk" -o "$out/coefficients/walk_target.json" >/dev/null
"$sinew" evolve --rig "$walk" --generations 1 --population 4 --window 0.5 --threads 1 \
  --out "$out/work/walk" >/dev/null
cp "$out/work/walk/best.json" "$out/coefficients/walk_controller.json"
"$sinew" evolve --rig "$source_dir/assets/hopper_hop.bvh" --generations 1 --population 4 \
  --window 0.5 --threads 1 --out "$out/work/hopper" >/dev/null
cp "$out/work/hopper/checkpoint.json" "$out/checkpoint/hopper.json"
rm -rf "$out/work"
ls -l "$out"/*/
