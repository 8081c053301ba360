#!/bin/bash
# One `mega-sat frontier` per task folder, one at a time, with a time limit: a line per task
# (wall seconds of the whole process, exact, iterations, frontier pairs) and its JSON in OUT.
# usage: bench/frontier-runs.sh OUT TIMEOUT 'domains/*/delta/20/p*' [extra frontier options]
# Run from the repository root with the project's .venv.  TREE=/path/to/checkout runs that
# source tree's mega_sat instead of the installed one (e.g. an older commit's worktree).
set -u
out=$1; limit=$2; pattern=$3; shift 3
mkdir -p "$out"
tree=${TREE:+$(realpath "$TREE")}  # resolved before the runs change directory
for t in $pattern; do
  name=$(echo "$t" | sed 's#domains/##; s#/delta/#-d#; s#/#-#g')
  s=$(date +%s.%N)
  if [ -n "$tree" ]; then  # from OUT, so that the current directory does not shadow TREE
    (cd "$out" && timeout $((${limit%.*} + 30)) "$OLDPWD/bench/mega-sat-from.sh" "$tree" \
      frontier --task "$OLDPWD/$t" --timeout "$limit" --json --quiet "$@" \
      > "$name.json" 2> "$name.err")
  else
    timeout $((${limit%.*} + 30)) .venv/bin/mega-sat frontier --task "$t" --timeout "$limit" \
      --json --quiet "$@" > "$out/$name.json" 2> "$out/$name.err"
  fi
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
