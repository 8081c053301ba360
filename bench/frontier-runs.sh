#!/bin/bash
# One `mega-sat frontier` per task folder, one at a time, with a time limit: a line per task
# (wall seconds of the whole process, exact, iterations, frontier pairs) and its JSON in OUT.
# usage: bench/frontier-runs.sh OUT TIMEOUT 'domains/*/delta/20/p*' [extra frontier options]
# Run from the repository root with the project's .venv.
set -u
out=$1; limit=$2; pattern=$3; shift 3
mkdir -p "$out"
for t in $pattern; do
  name=$(echo "$t" | sed 's#domains/##; s#/delta/#-d#; s#/#-#g')
  s=$(date +%s.%N)
  timeout $((${limit%.*} + 30)) .venv/bin/mega-sat frontier --task "$t" --timeout "$limit" \
    --json --quiet "$@" > "$out/$name.json" 2> "$out/$name.err"
  rc=$?
  wall=$(echo "$(date +%s.%N) - $s" | bc)
  .venv/bin/python - "$out/$name.json" "$name" "$rc" "$wall" <<'PY'
import json, sys
f, name, rc, wall = sys.argv[1:]
try:
    d = json.load(open(f))
except ValueError:
    print(f"{name:28s} rc={rc} wall={float(wall):6.2f} no JSON (see the .err file)")
    raise SystemExit
pts = [(len(p["explanation"]), p["robot_cost"]) for p in d["frontier"]]
it = d["stats"].get("iterations")
print(f"{name:28s} rc={rc} wall={float(wall):6.2f} exact={d['exact']} it={it} pts={pts}")
PY
done
