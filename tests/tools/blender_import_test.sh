#!/usr/bin/env bash
# Exports the bundled walk (and, when present, a real Bandai capture and the Fox) with
# `sinew convert`, and the best motion of a short `sinew evolve`, and imports them in Blender: BVH with the same bone and frame counts, glTF
# with the same bone count (Blender keys glTF at its own scene rate, so frames are not compared).
# Skips (exit 77) without Blender.
set -euo pipefail
sinew=$1 source_dir=$2 shared=$3
if ! command -v blender >/dev/null; then
  echo "blender is not installed; skipping (./scripts/test installs it)"
  exit 77
fi
work=$(mktemp -d)
trap 'rm -rf "$work"' EXIT
specs=()
"$sinew" convert "$source_dir/assets/biped_walk.bvh" "$work/walk.bvh" >/dev/null
"$sinew" convert "$source_dir/assets/biped_walk.bvh" "$work/walk.glb" >/dev/null
specs+=("$work/walk.bvh:22:129" "$work/walk.glb:22:0")
# What the search evolves: two short generations are enough to have a best motion to export
# (a 2 s window at 30 fps: 61 frames, or fewer if the best one fell and stopped early).
"$sinew" evolve --generations 2 --population 4 --window 2 --out "$work/evolved" >/dev/null
frames=$("$sinew" info --json "$work/evolved/best.bvh" | python3 -c 'import json,sys; print(json.load(sys.stdin)["frames"])')
specs+=("$work/evolved/best.bvh:22:$frames" "$work/evolved/best.glb:22:0")
bandai="$shared/bvh/bandai_dataset-1_walk_normal_001.bvh"
if [ -f "$bandai" ]; then
  "$sinew" convert "$bandai" "$work/bandai.bvh" >/dev/null
  "$sinew" convert "$shared/gltf/Fox.glb" "$work/fox_walk.glb" --animation Walk >/dev/null
  specs+=("$work/bandai.bvh:22:195" "$work/fox_walk.glb:24:0")
else
  echo "note: $bandai not found; checking the bundled walk only"
fi
status=0
blender -b --factory-startup --python-exit-code 1 \
  --python "$source_dir/tests/tools/blender_import.py" -- "${specs[@]}" >"$work/blender.log" 2>&1 ||
  status=$?
grep -E "^blender:" "$work/blender.log" || true
if [ "$status" -ne 0 ]; then
  echo "Blender exited with $status; the end of its log:"
  tail -n 30 "$work/blender.log"
fi
exit "$status"
