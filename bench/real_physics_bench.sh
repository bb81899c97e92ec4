#!/usr/bin/env bash
# Real capture made physical: for every walk, run and dog clip in ../shared/data/bvh and the four
# bundled creatures, `sinew evolve --rig CLIP --minutes M` on every core, then the best controller
# replayed for 10 s and for 30 s. Prints a Markdown table (docs/physics.md keeps one):
#   clip, links, DOF, mass, stood up (10 s replay, 30 s replay), distance, speed vs the clip's,
#   tracking error, evaluations, wall time, why it fell.
# A long experiment, not a test: 13 clips x M minutes (M=5: about 70 minutes on 2 cores).
#   bench/real_physics_bench.sh [SINEW_BINARY] [MINUTES] [OUT_DIR] [CLIP...]
set -euo pipefail
root=$(cd "$(dirname "${BASH_SOURCE[0]}")/.." && pwd)
sinew=${1:-$root/build/release/app/sinew}
minutes=${2:-5}
out=${3:-$(mktemp -d)}
shift $(($# < 3 ? $# : 3))
shared=$root/../shared/data/bvh
clips=("$@")
if [ ${#clips[@]} -eq 0 ]; then
  if [ -d "$shared" ]; then
    for f in "$shared"/*.bvh; do
      clips+=("$f")  # every real clip there is locomotion: walks, runs, the dog
    done
  else
    echo "real_physics_bench: $shared not found; only the bundled creatures" >&2
  fi
  clips+=("$root/assets/biped_walk.bvh" "$root/assets/quadruped_trot.bvh"
          "$root/assets/hopper_hop.bvh" "$root/assets/stepper_step.bvh")
fi
mkdir -p "$out"
echo "| clip | links | DOF | mass kg | up (10 s) | up (30 s) | distance m | speed m/s (clip) | tracking deg | evaluations | wall s | fell because |"
echo "|---|---|---|---|---|---|---|---|---|---|---|---|"
for clip in "${clips[@]}"; do
  name=$(basename "$clip" .bvh)
  dir="$out/$name"
  start=$(date +%s.%N)
  "$sinew" evolve --rig "$clip" --minutes "$minutes" --seed 1 --out "$dir" > "$dir.evolve.log" 2>&1 || {
    echo "| $name | - | - | - | - | - | - | - | - | - | - | evolve failed: $(tail -1 "$dir.evolve.log") |"
    continue
  }
  wall=$(python3 -c "import sys; print(f'{float(sys.argv[2]) - float(sys.argv[1]):.0f}')" "$start" "$(date +%s.%N)")
  "$sinew" simulate --rig "$clip" --controller "$dir/best.json" --seconds 10 --json "$dir/replay10.json" > "$dir.replay10.log" 2>&1
  "$sinew" simulate --rig "$clip" --controller "$dir/best.json" --seconds 30 --json "$dir/replay30.json" > "$dir.replay30.log" 2>&1
  "$sinew" analyze "$clip" --json "$dir/analysis.json" > /dev/null 2>&1 || true
  python3 - "$name" "$dir" "$wall" <<'PY'
import json, re, sys
name, d, wall = sys.argv[1], sys.argv[2], sys.argv[3]
r10 = json.load(open(f"{d}/replay10.json"))
r30 = json.load(open(f"{d}/replay30.json"))
head = open(f"{d}.replay10.log").readline()
m = re.search(r"(\d+) links, (\d+) degrees of freedom, ([\d.]+) kg", head)
links, dof, mass = m.groups() if m else ("?", "?", "?")
evals = re.search(r"\((\d+) evaluations\)", open(f"{d}.evolve.log").read())
clip_speed = "?"
try:
    v = json.load(open(f"{d}/analysis.json"))["travel_velocity_m_s"]
    clip_speed = f"{(v[0] ** 2 + v[2] ** 2) ** 0.5:.2f}"
except Exception:
    pass
print(f"| {name} | {links} | {dof} | {mass} | {r10['seconds']:.1f} s | {r30['seconds']:.1f} s | "
      f"{r10['distance_m']:.1f} | {r10['speed_m_s']:.2f} ({clip_speed}) | "
      f"{r10['track_err_rad_rms'] * 57.29578:.1f} | {evals.group(1) if evals else '?'} | {wall} | "
      f"{r10.get('fall_reason', '') if r10['fell'] else '-'} |")
PY
done
