#!/usr/bin/env bash
# Evaluations per second of one search on 1, 2 and 3 MPI ranks (one thread each; the third rank
# oversubscribes a 2-core machine) against one process on 1 and 2 threads, the communication per
# generation, and whether every run reached the same best cost (it must: docs/search.md).
# Usage: bench/mpi_evolve_bench.sh [SINEW] [GENERATIONS] [OUT]
set -euo pipefail
root=$(cd "$(dirname "${BASH_SOURCE[0]}")/.." && pwd)
sinew=${1:-$root/build/release/app/sinew}
generations=${2:-6}
out=${3:-$(mktemp -d)}
mkdir -p "$out"
args=(evolve --generations "$generations" --population 16 --window 4 --seed 1 --loop-strides 0)
echo "search: the bundled biped, population 16, window 4 s, $generations generations, seed 1; load $(cut -d' ' -f1-3 /proc/loadavg)"
printf '%-22s %9s %9s  %s\n' "run" "eval/s" "wall s" "communication per generation"
run() {  # LABEL RANKS THREADS
  local dir="$out/$1" t0 t1
  rm -rf "$dir"
  t0=$(date +%s.%N)
  if [ "$2" -eq 1 ]; then
    "$sinew" "${args[@]}" --threads "$3" --out "$dir" > "$dir.log"
  else
    mpirun --allow-run-as-root --oversubscribe -np "$2" "$sinew" "${args[@]}" --threads "$3" \
      --out "$dir" > "$dir.log"
  fi
  t1=$(date +%s.%N)
  local evals wall comm
  evals=$(tail -1 "$dir/history.csv" | cut -d, -f2)
  wall=$(tail -1 "$dir/history.csv" | cut -d, -f3)
  comm=$(grep '^distributed' "$dir.log" | sed 's/.*generations; per generation //' || true)
  printf '%-22s %9.2f %9.1f  %s\n' "$1" "$(echo "$evals / $wall" | bc -l)" "$(echo "$t1 - $t0" | bc -l)" "${comm:--}"
}
run "1 process, 1 thread" 1 1
run "1 process, 2 threads" 1 2
run "2 ranks x 1 thread" 2 1
run "3 ranks x 1 thread" 3 1
python3 - "$out" <<'PY'
import json, os, sys
out = sys.argv[1]
runs = sorted(d for d in os.listdir(out) if os.path.isdir(os.path.join(out, d)))
best = {d: json.load(open(os.path.join(out, d, "checkpoint.json")))["best_point"] for d in runs}
same = all(best[d] == best[runs[0]] for d in runs)
print("the same best point in every run:", "yes" if same else "NO")
sys.exit(0 if same else 1)
PY
