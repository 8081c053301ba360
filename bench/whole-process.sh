#!/bin/bash
# Target 4 with both engines at their defaults: `mega-sat frontier` as a whole process with
# --engine astar and then --engine sat on each paper-grid task, one at a time (A* stopped at
# 30 s), a line "task engine wall-seconds" each in OUT, then the astar/sat summary.
# usage: [REPS=N] bench/whole-process.sh OUT ['domains/*/delta/2/p* ...']
# REPS (default 1): rounds over the tasks whose processes both took under 2 s in the first
# round, astar and sat alternately; the summary takes each engine's median per task (single
# runs of such short processes land on either side of 1 from run to run).
# Run from the repository root with the project's .venv.
set -u
out=$1; pattern=${2:-'domains/*/delta/2/p* domains/*/delta/7/p* domains/*/delta/10/p*'}
reps=${REPS:-1}
# Bytecode first, as an installed package has it: where PYTHONDONTWRITEBYTECODE is set, every
# process would otherwise compile every module it imports from source (about 50 ms, more for
# the engine that imports more modules), which is not what a user's run pays.
.venv/bin/python -m compileall -q mega_sat > /dev/null
one() {  # TASK ENGINE: one whole process, its line appended to OUT
  local s
  s=$(date +%s.%N)
  timeout 40 .venv/bin/mega-sat frontier --task "$1" --engine "$2" --timeout 30 --json \
    --quiet > /dev/null 2>&1
  echo "$1 $2 $(echo "$(date +%s.%N) - $s" | bc)" >> "$out"
}
: > "$out"
short=()
for t in $pattern; do
  one "$t" astar
  one "$t" sat
  if tail -2 "$out" | awk '$3 >= 2 { slow = 1 } END { exit slow }'; then short+=("$t"); fi
done
for ((r = 2; r <= reps; r++)); do
  for t in "${short[@]}"; do
    one "$t" astar
    one "$t" sat
  done
done
.venv/bin/python - "$out" <<'PY'
import statistics, sys
runs = {}
for line in open(sys.argv[1]):
    task, engine, wall = line.split()
    runs.setdefault(task, {}).setdefault(engine, []).append(float(wall))
rows = {t: {e: statistics.median(w) for e, w in r.items()} for t, r in runs.items()}
ratio = {t: r["astar"] / r["sat"] for t, r in rows.items()}
for t, q in ratio.items():
    print(f"{t:36s} astar {rows[t]['astar']:6.2f}  sat {rows[t]['sat']:6.2f}  astar/sat {q:6.2f}")
qs = list(ratio.values())
print(f"astar/sat >= 1 on {sum(q >= 1 for q in qs)} of {len(qs)}; min {min(qs):.2f}, "
      f"median {statistics.median(qs):.2f}")
PY
