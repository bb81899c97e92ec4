#!/usr/bin/env bash
# The headless editor in a pipeline: `sinew edit PROJECT --evolve --evolve-generations 2 --export
# DIR` (no window, no display) writes what `sinew evolve PROJECT --generations 2 --out DIR` writes:
# the same files, the same best controller (best.json byte for byte, so the same best cost) and
# the same best motion (best.bvh).
# Usage: edit_export_test.sh SINEW_BINARY SOURCE_DIR WORK_DIR
set -euo pipefail
sinew="$1"
source_dir="$2"
work="$3"
rm -rf "$work"
mkdir -p "$work"
project="$work/small.sinew.json"
cat >"$project" <<JSON
{"format": "sinew.project", "version": 2, "rig": "$source_dir/assets/biped_walk.bvh",
 "harmonics": 4, "terrain": "slope:2", "window_s": 1, "pushes": ["0.5,-20,0,0"],
 "search": {"population": 6, "seed": 5}}
JSON
# No display: the editor must not need one to export.
env -u DISPLAY -u WAYLAND_DISPLAY "$sinew" edit "$project" --evolve --evolve-generations 2 \
  --export "$work/editor" >"$work/editor.log"
"$sinew" evolve "$project" --generations 2 --out "$work/cli" >"$work/cli.log"
for name in best.json best.bvh best.glb history.csv checkpoint.json; do
  test -s "$work/editor/$name" || { echo "FAIL: the editor wrote no $name"; exit 1; }
  test -s "$work/cli/$name" || { echo "FAIL: sinew evolve wrote no $name"; exit 1; }
done
cmp "$work/editor/best.json" "$work/cli/best.json" ||
  { echo "FAIL: best.json differs"; diff "$work/editor/best.json" "$work/cli/best.json" | head; exit 1; }
cmp "$work/editor/best.bvh" "$work/cli/best.bvh" || { echo "FAIL: best.bvh differs"; exit 1; }
python3 - "$work" <<'PY'
import json, sys
work = sys.argv[1]
costs = [json.load(open(f"{work}/{side}/best.json"))["fitness"]["total"] for side in ("editor", "cli")]
problems = [json.load(open(f"{work}/{side}/checkpoint.json"))["problem"] for side in ("editor", "cli")]
gens = [len(json.load(open(f"{work}/{side}/checkpoint.json"))["history"]) for side in ("editor", "cli")]
assert costs[0] == costs[1], costs
assert problems[0] == problems[1], (problems[0], problems[1])
assert gens == [2, 2], gens
print(f"OK: editor and sinew evolve: best cost {costs[0]!r} after 2 generations, same best.json")
PY
