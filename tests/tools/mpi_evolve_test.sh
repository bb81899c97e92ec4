#!/usr/bin/env bash
# `mpirun -np 3 sinew evolve` on loopback (docs/search.md, "Over MPI"):
#  1. a short search over 3 ranks reaches the single process's best point, cost and optimiser
#     state bit for bit;
#  2. a worker killed mid-run ends the job with mpirun's message naming the rank, and the
#     checkpoint of the last whole generation resumes in a single process.
#  3. a batch of three clips over the ranks and as a job array writes the same summary.
# Usage: mpi_evolve_test.sh SINEW MPIRUN WORKDIR SOURCE_DIR
set -euo pipefail
sinew=$1
mpirun=$2
work=$3
assets=$4/assets
rm -rf "$work" && mkdir -p "$work" && cd "$work"
run_mpi() { "$mpirun" --allow-run-as-root --oversubscribe -np 3 "$@"; }
short=(evolve --generations 3 --population 6 --window 1.5 --seed 3 --loop-strides 0)

# 1. The same search on one process and on three.
"$sinew" "${short[@]}" --threads 1 --out one > one.log
run_mpi "$sinew" "${short[@]}" --out three > three.log
grep -q "3 MPI ranks x" three.log || { echo "FAIL: the start line does not name the ranks"; cat three.log; exit 1; }
grep "^distributed over 3 ranks" three.log
python3 - <<'EOF'
import json, sys
one = json.load(open("one/checkpoint.json"))
three = json.load(open("three/checkpoint.json"))
for key in ("best_point", "best_terms", "optimizer", "genome_size"):
    if one[key] != three[key]:
        sys.exit(f"FAIL: '{key}' differs between one process and three ranks")
print(f"one process and 3 ranks: the same best point ({len(one['best_point'])} coordinates), "
      f"cost {one['best_terms']['total']!r} and optimiser state after {len(one['history'])} generations")
EOF

# 2. A worker killed mid-run.
run_mpi "$sinew" evolve --generations 500 --population 6 --window 3 --seed 3 --loop-strides 0 \
  --out killed > killed.log 2>&1 &
launcher=$!
for _ in $(seq 1 600); do  # until two generations are in the checkpoint (at most 60 s)
  if [ -f killed/checkpoint.json ] &&
     python3 -c "import json,sys; sys.exit(len(json.load(open('killed/checkpoint.json'))['history']) < 2)" 2>/dev/null; then
    break
  fi
  sleep 0.1
done
worker=""
for pid in $(pgrep -f "sinew evolve --generations 500" || true); do
  if tr '\0' '\n' < "/proc/$pid/environ" 2>/dev/null | grep -qx "OMPI_COMM_WORLD_RANK=1"; then
    worker=$pid
  fi
done
[ -n "$worker" ] || { echo "FAIL: no rank 1 found to kill"; cat killed.log; kill "$launcher"; exit 1; }
kill -9 "$worker"
status=0
wait "$launcher" || status=$?
[ "$status" -ne 0 ] || { echo "FAIL: the job went on after a rank died"; exit 1; }
grep -q "checkpoint after every generation: killed/checkpoint.json" killed.log ||
  { echo "FAIL: the start did not say where the checkpoint is"; cat killed.log; exit 1; }
grep -Eq "process rank 1 .*(exited on signal 9|Killed)" killed.log ||
  { echo "FAIL: no message names the rank that died"; cat killed.log; exit 1; }
generations=$(python3 -c "import json; print(len(json.load(open('killed/checkpoint.json'))['history']))")
echo "rank 1 killed: mpirun ended the job (exit $status); the checkpoint holds $generations whole generations"
"$sinew" evolve --resume killed/checkpoint.json --generations $((generations + 1)) --out resumed \
  --loop-strides 0 > resumed.log
grep -q "^gen *$((generations + 1)) " resumed.log || { echo "FAIL: the resume did not go on"; cat resumed.log; exit 1; }
echo "resumed in one process: generation $((generations + 1)) ran"

# 3. A batch of three clips over the ranks (rank 0 hands them out), and the same batch as a job
#    array of three single tasks: each writes its clip's files; the summary lists all three.
mkdir -p library
cp "$assets"/{biped_walk,hopper_hop,stepper_step}.bvh library/
batch=(evolve --batch library --generations 2 --population 6 --window 1 --seed 1 --loop-strides 0)
run_mpi "$sinew" "${batch[@]}" --out batch > batch.log
for task in 2 0 1; do "$sinew" "${batch[@]}" --batch-index "$task" --out array > "array_$task.log"; done
python3 - <<'PY'
import csv, json, sys
for out in ("batch", "array"):
    rows = list(csv.DictReader(open(f"{out}/summary.csv")))
    names = [r["folder"] for r in rows]
    if names != ["biped_walk", "hopper_hop", "stepper_step"] or any(r["status"] != "ok" for r in rows):
        sys.exit(f"FAIL: {out}/summary.csv: {rows}")
    if any((r["fell"] == "true") != bool(r["fell_because"]) for r in rows):
        sys.exit(f"FAIL: {out}/summary.csv: a fall without its reason, or a reason without a fall: {rows}")
    for name in names:
        json.load(open(f"{out}/{name}/best.json"))
    print(f"{out}: summary of 3 clips, " + ", ".join(f"{r['folder']} cost {r['cost']} (rank {r['rank']})" for r in rows))
one = {r["folder"]: r["cost"] for r in csv.DictReader(open("batch/summary.csv"))}
arr = {r["folder"]: r["cost"] for r in csv.DictReader(open("array/summary.csv"))}
if one != arr:
    sys.exit(f"FAIL: the ranks' batch and the job array differ: {one} vs {arr}")
PY
