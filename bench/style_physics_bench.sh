#!/usr/bin/env bash
# Style through physics on the Bandai walks (issue 15): for each row NEUTRAL -> STYLED at weight 1
# (normal -> tired, happy, angry) and tired -> normal (the style removed: the tired walk with the
# normal->tired style at weight -1), `sinew evolve --rig NEUTRAL_OR_SOURCE --style ... --minutes M`
# on every core, then its style report and loop. Prints a Markdown table (docs/search.md keeps
# one): the target's and the simulated run's score and amount of the style, the loop's, how long
# the best stayed up, tracking error, foot slide of the loop before/after the plant, its seam.
# A long experiment, not a test: 4 rows x M minutes.
#   bench/style_physics_bench.sh [SINEW_BINARY] [MINUTES] [OUT_DIR] [WINDOW_S]
set -euo pipefail
root=$(cd "$(dirname "${BASH_SOURCE[0]}")/.." && pwd)
sinew=${1:-$root/build/release/app/sinew}
minutes=${2:-5}
out=${3:-$(mktemp -d)}
window=${4:-10}
data=$root/../shared/data/bvh
if [ ! -d "$data" ]; then
  echo "style_physics_bench: $data not found" >&2
  exit 77
fi
bandai() { echo "$data/bandai_dataset-1_walk_$1_001.bvh"; }
# name | rig (the clip evolved) | neutral | styled | weight
rows=("normal->tired|$(bandai normal)|$(bandai normal)|$(bandai tired)|1"
      "normal->happy|$(bandai normal)|$(bandai normal)|$(bandai happy)|1"
      "normal->angry|$(bandai normal)|$(bandai normal)|$(bandai angry)|1"
      "tired->normal|$(bandai tired)|$(bandai normal)|$(bandai tired)|-1")
mkdir -p "$out"
echo "| row | target score / amount | simulated run score / amount | loop score / amount | closest (run, loop) | up s | tracking deg | loop slide cm before -> after | loop seam deg (step) | evaluations | wall s |"
echo "|---|---|---|---|---|---|---|---|---|---|---|"
for row in "${rows[@]}"; do
  IFS='|' read -r name rig neutral styled weight <<< "$row"
  dir="$out/${name/->/_to_}"
  start=$(date +%s.%N)
  if ! "$sinew" evolve --rig "$rig" --style "$neutral,$styled:$weight" --minutes "$minutes" \
      --window "$window" --seed 1 --out "$dir" > "$dir.log" 2>&1; then
    echo "| $name | evolve failed: $(tail -1 "$dir.log") |||||||||"
    continue
  fi
  wall=$(python3 -c "import sys; print(f'{float(sys.argv[2]) - float(sys.argv[1]):.0f}')" "$start" "$(date +%s.%N)")
  python3 - "$name" "$dir" "$wall" <<'PY'
import json, os, re, sys
name, d, wall = sys.argv[1:4]
log = open(f"{d}.log").read()
style = json.load(open(f"{d}/style.json"))["styles"][0]
best = json.load(open(f"{d}/best.json"))["fitness"]
evals = re.search(r"\((\d+) evaluations\)", log)
def pair(m):
    return f"{m['score']:.2f} / {m['amount']:.2f}" if m else "-"
run = style.get("simulated")
closest_run = json.load(open(f"{d}/style.json")).get("simulated_closest", "-")
loop_cell = slide = seam = "-"
closest_loop = "-"
if os.path.exists(f"{d}/loop.json"):
    loop = json.load(open(f"{d}/loop.json"))
    ls = loop.get("style", {}).get("styles", [{}])[0].get("simulated")
    loop_cell = pair(ls)
    closest_loop = loop.get("style", {}).get("simulated_closest", "-")
    slide = f"{loop['slide_before_cm_mean']:.1f} -> {loop['slide_after_cm_mean']:.1f}"
    seam = f"{loop['seam_deg']:.1f} ({loop['step_deg_max']:.1f})"
else:
    m = re.search(r"no best_loop: (.*)", log)
    loop_cell = "no loop" + (f": {m.group(1)[:60]}" if m else "")
print(f"| {name} | {pair(style['target'])} | {pair(run) if run else 'not measured'} | {loop_cell} | "
      f"{closest_run}, {closest_loop} | {best['survived_s']:.1f} | "
      f"{best['track_err_rad_rms'] * 57.2958:.1f} | {slide} | {seam} | "
      f"{evals.group(1) if evals else '?'} | {wall} |")
PY
done
