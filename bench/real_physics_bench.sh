#!/usr/bin/env bash
# Real capture made physical: for every walk, run and dog clip in ../shared/data/bvh and the four
# bundled creatures, `sinew evolve --rig CLIP --minutes M` on every core, then the best controller
# replayed for 10 s and for 30 s. Prints a Markdown table (docs/physics.md keeps one):
#   clip, links, DOF, mass, stood up (10 s replay, 30 s replay), distance, speed vs the clip's,
#   tracking error against the clip's model (and against the evolved target), evaluations, wall
#   time, push robustness (bench/push_robustness.py: the largest impulse held at every moment of
#   a stride, and at 2 s; how many of 20 pushes of 40 N s were held), why it fell.
# A long experiment, not a test: 13 clips x M minutes (M=5: about 70 minutes on 2 cores) per seed.
#   [SEEDS="1 2 ..."] bench/real_physics_bench.sh [SINEW_BINARY] [MINUTES] [OUT_DIR] [CLIP...]
# EVOLVE_ARGS (default none): more `sinew evolve` options for every search, e.g.
#   EVOLVE_ARGS="--trials 5 --trial-push 0.66" for robustness trials at 40 N s on a 60 kg figure.
# HARDEN_ARGS (default none): robustness options for a second, hardening search of MINUTES more:
#   each search resumed (`sinew evolve --resume DIR/checkpoint.json HARDEN_ARGS`) and its best
#   measured again in a "(hardened)" row, e.g. HARDEN_ARGS="--trials 5 --trial-push 0.66".
# FROM (default none): with HARDEN_ARGS, harden the searches of an earlier run of this bench
#   (FROM/<clip>/) instead of searching again; their own rows are not printed.
# SEEDS (default 1): one search, and one row, per seed and clip. One search's outcome varies with
# its seed about as much as any controller change measured on the dog (docs/physics.md), so judge
# a change by several.
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
echo "| clip | links | DOF | mass kg | up (10 s) | up (30 s) | distance m | speed m/s (clip) | tracking deg: clip (own target) | evaluations | wall s | push N s f/b/l/r: every moment (at 2 s) | 40 N s held | fell because |"
echo "|---|---|---|---|---|---|---|---|---|---|---|---|---|---|"
read -r -a seeds <<< "${SEEDS:-1}"
read -r -a evolve_args <<< "${EVOLVE_ARGS:-}"
read -r -a harden_args <<< "${HARDEN_ARGS:-}"
# One row: replays of DIR/best.json (10 s, 30 s), the clip's analysis, pushes, and the figures.
#   row NAME DIR WALL_S CLIP
row() {
  local name=$1 dir=$2 wall=$3 clip=$4
  "$sinew" simulate --rig "$clip" --controller "$dir/best.json" --seconds 10 --json "$dir/replay10.json" > "$dir.replay10.log" 2>&1
  "$sinew" simulate --rig "$clip" --controller "$dir/best.json" --seconds 30 --json "$dir/replay30.json" > "$dir.replay30.log" 2>&1
  "$sinew" analyze "$clip" --json "$dir/analysis.json" > /dev/null 2>&1 || true
  python3 - "$name" "$dir" "$wall" "$sinew" "$clip" "$root/bench/push_robustness.py" <<'PY'
import json, re, subprocess, sys
name, d, wall, sinew, clip, push_script = sys.argv[1:7]
r10 = json.load(open(f"{d}/replay10.json"))
r30 = json.load(open(f"{d}/replay30.json"))
head = open(f"{d}.replay10.log").readline()
m = re.search(r"(\d+) links, (\d+) degrees of freedom, ([\d.]+) kg", head)
links, dof, mass = m.groups() if m else ("?", "?", "?")
evals = re.search(r"\((\d+) evaluations\)", open(f"{d}.evolve.log").read())
# Tracking against the clip's own model (the search's reference: best.json's fitness, the same run
# as the replay bit for bit) and, in brackets, against the evolved target the body follows.
clip_track = json.load(open(f"{d}/best.json"))["fitness"]["track_err_rad_rms"] * 57.29578
clip_speed = "?"
try:
    v = json.load(open(f"{d}/analysis.json"))["travel_velocity_m_s"]
    clip_speed = f"{(v[0] ** 2 + v[2] ** 2) ** 0.5:.2f}"
except Exception:
    pass
# Push robustness (bench/push_robustness.py): per direction, the largest impulse on the pelvis
# held at all five moments of a stride from 2 s, and at 2 s alone; and how many of the 20 pushes
# of 40 N s were held. Walks that stay up 10 s only.
pushes, at_aim = "-", "-"
if not r10["fell"]:
    out = subprocess.run([sys.executable, push_script, sinew, clip, f"{d}/best.json", f"{d}/analysis.json"],
                         capture_output=True, text=True).stdout.split()
    if len(out) == 3:
        pushes, at_aim = f"{out[0]} ({out[1]})", out[2]
print(f"| {name} | {links} | {dof} | {mass} | {r10['seconds']:.1f} s | {r30['seconds']:.1f} s | "
      f"{r10['distance_m']:.1f} | {r10['speed_m_s']:.2f} ({clip_speed}) | "
      f"{clip_track:.1f} ({r10['track_err_rad_rms'] * 57.29578:.1f}) | {evals.group(1) if evals else '?'} | {wall} | {pushes} | {at_aim} | "
      f"{r10.get('fall_reason', '') if r10['fell'] else '-'} |")
PY
}

seconds_since() { python3 -c "import sys; print(f'{float(sys.argv[2]) - float(sys.argv[1]):.0f}')" "$1" "$(date +%s.%N)"; }

for clip in "${clips[@]}"; do
for seed in "${seeds[@]}"; do
  name=$(basename "$clip" .bvh)
  dir="$out/$name"
  if [ ${#seeds[@]} -gt 1 ]; then
    dir="$out/$name.seed$seed"
    name="$name (seed $seed)"
  fi
  if [ -n "${FROM:-}" ]; then  # an earlier run's search, not searched again
    dir="$FROM/${dir#"$out"/}"
    wall=-
  else
    start=$(date +%s.%N)
    "$sinew" evolve --rig "$clip" --minutes "$minutes" --seed "$seed" --out "$dir" \
        "${evolve_args[@]}" > "$dir.evolve.log" 2>&1 || {
      echo "| $name | - | - | - | - | - | - | - | - | - | - | - | evolve failed: $(tail -1 "$dir.evolve.log") |"
      continue
    }
    wall=$(seconds_since "$start")
    row "$name" "$dir" "$wall" "$clip"
  fi
  # Hardened: a gait that stands its 10 s replay, searched MINUTES more with HARDEN_ARGS.
  if [ ${#harden_args[@]} -gt 0 ] &&
     python3 -c "import json, sys; sys.exit(json.load(open(sys.argv[1]))['fell'])" "$dir/replay10.json"; then
    hard="$out/$(basename "$dir").hardened"
    total=$(python3 -c "import json, sys; print(json.load(open(sys.argv[1]))['settings']['minutes'] + float(sys.argv[2]))" \
        "$dir/checkpoint.json" "$minutes")
    start=$(date +%s.%N)
    "$sinew" evolve --resume "$dir/checkpoint.json" --minutes "$total" --out "$hard" \
        "${harden_args[@]}" > "$hard.evolve.log" 2>&1 || {
      echo "| $name (hardened) | - | - | - | - | - | - | - | - | - | - | - | evolve failed: $(tail -1 "$hard.evolve.log") |"
      continue
    }
    row "$name (hardened)" "$hard" "$(seconds_since "$start")" "$clip"
  fi
done
done
