#!/bin/bash
# Frontiers of the paper grid (Delta = 2/7/10, 36 tasks) from two source trees, compared with
# their timing fields removed (and, for each that differs, the coarsest difference: pairs,
# explanations, witness plans or stats), and the wall seconds of each tree's runs.
# usage: bench/frontier-diff.sh OLD_TREE NEW_TREE [OUT_DIR]
#   e.g. git worktree add /tmp/old <commit>; bench/frontier-diff.sh /tmp/old "$PWD"
# Run from the repository root with the project's .venv; each tree's mega_sat is put first on
# the path (the runs start in OUT_DIR, so the current directory does not shadow it).
set -u
old=$(realpath "$1"); new=$(realpath "$2"); out=$(realpath -m "${3:-/tmp/frontier-diff}")
root=$PWD; py=$root/.venv/bin/python
run_tree() {  # TREE LABEL
  mkdir -p "$out/$2"; : > "$out/$2/times.txt"
  for d in "$root"/domains/*/delta/{2,7,10}/p*; do
    name=$(echo "${d#"$root"/}" | tr / _)
    s=$(date +%s.%N)
    (cd "$out" && timeout 600 "$root/bench/mega-sat-from.sh" "$1" \
      frontier --task "$d" --json --quiet > "$out/$2/$name.json" 2> "$out/$2/$name.err")
    echo "$name $(echo "$(date +%s.%N) - $s" | bc)" >> "$out/$2/times.txt"
  done
}
run_tree "$old" old
run_tree "$new" new
"$py" - "$out" <<'PY'
import json, re, sys
from pathlib import Path
out = Path(sys.argv[1])
def strip(o):
    if isinstance(o, dict):
        return {k: strip(v) for k, v in o.items() if not re.search(r"time|_s$|seconds", k)}
    return [strip(x) for x in o] if isinstance(o, list) else o
def times(label):
    return {n: float(t) for n, t in (l.split() for l in (out / label / "times.txt").open())}
old, new = times("old"), times("new")
same = [n for n in old if strip(json.load((out / "old" / f"{n}.json").open()))
        == strip(json.load((out / "new" / f"{n}.json").open()))]
print(f"identical frontiers (timings removed): {len(same)} of {len(old)}")
print(f"wall seconds: old {sum(old.values()):.1f}, new {sum(new.values()):.1f}")
def what_differs(a, b):
    """The coarsest difference: the (cost(E), robot cost) pairs (a wrong answer), then the
    explanations, the witness plans, other frontier fields, or the rest (stats, notes)."""
    fa, fb = a.get("frontier", []), b.get("frontier", [])
    def pairs(f):
        return [(len(p.get("explanation", [])), p.get("robot_cost")) for p in f]
    if pairs(fa) != pairs(fb) or a.get("exact") != b.get("exact"):
        return f"PAIRS {pairs(fa)} / {pairs(fb)}"
    for field in ("explanation", "plan"):
        if [p.get(field) for p in fa] != [p.get(field) for p in fb]:
            return f"{field}s"
    return "other frontier fields" if fa != fb else "stats or notes only"
for n in old:
    if n not in same:
        a = strip(json.load((out / "old" / f"{n}.json").open()))
        b = strip(json.load((out / "new" / f"{n}.json").open()))
        print(f"  {n}: {what_differs(a, b)}")
PY
