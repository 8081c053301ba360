#!/bin/bash
# Target 4 with both engines at their defaults: `mega-sat frontier` as a whole process with
# --engine astar and then --engine sat on each paper-grid task, one at a time (A* stopped at
# 30 s), a line "task engine wall-seconds" each in OUT, then the astar/sat summary.
# usage: bench/whole-process.sh OUT ['domains/*/delta/2/p* ...']
# Run from the repository root with the project's .venv.
set -u
out=$1; pattern=${2:-'domains/*/delta/2/p* domains/*/delta/7/p* domains/*/delta/10/p*'}
# Bytecode first, as an installed package has it: where PYTHONDONTWRITEBYTECODE is set, every
# process would otherwise compile every module it imports from source (about 50 ms, more for
# the engine that imports more modules), which is not what a user's run pays.
.venv/bin/python -m compileall -q mega_sat > /dev/null
: > "$out"
for t in $pattern; do
  for e in astar sat; do
    s=$(date +%s.%N)
    timeout 40 .venv/bin/mega-sat frontier --task "$t" --engine $e --timeout 30 --json \
      --quiet > /dev/null 2>&1
    echo "$t $e $(echo "$(date +%s.%N) - $s" | bc)" >> "$out"
  done
done
.venv/bin/python - "$out" <<'PY'
import statistics, sys
rows = {}
for line in open(sys.argv[1]):
    task, engine, wall = line.split()
    rows.setdefault(task, {})[engine] = float(wall)
ratio = {t: r["astar"] / r["sat"] for t, r in rows.items()}
for t, q in ratio.items():
    print(f"{t:36s} astar {rows[t]['astar']:6.2f}  sat {rows[t]['sat']:6.2f}  astar/sat {q:6.2f}")
qs = list(ratio.values())
print(f"astar/sat >= 1 on {sum(q >= 1 for q in qs)} of {len(qs)}; min {min(qs):.2f}, "
      f"median {statistics.median(qs):.2f}")
PY
