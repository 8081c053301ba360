#!/usr/bin/env bash
# docs/mmp.md, "Time against the old search": `mega-sat mmp -s EE` (mega-sat's default engine)
# against the paper's A* search in model space with Fast Downward astar(lmcut()) per node
# (`solve --engine astar --planner fd`), whole processes, one at a time, EE at alpha 1.
#   bench/mmp-times.sh [LIMIT_SECONDS]      (default 300: A* runs past it are "> LIMIT")
set -uo pipefail
cd "$(dirname "$0")/.."
limit=${1:-300}
work=$(mktemp -d)
trap 'rm -rf "$work"' EXIT
echo "| task | \|Δ\| | mmp -s EE s | \|E\| | A* (FD per node) s | \|E\| |"
echo "|---|---|---|---|---|---|"
for t in usar-fetch/p1 usar-fetch/p3 rover-martian/p1 barman-bar/p1 blocksworld/p3 \
         rover-martian/delta/7/p1 usar-fetch/delta/10/p1 blocksworld/delta/10/p2; do
  d=domains/$t
  dom=$(dirname "$d"); [ -f "$d/robot-domain.pddl" ] && dom=$d
  [ -f "$dom/robot-domain.pddl" ] || dom=$(dirname "$dom")
  hp=$d/human-problem.pddl; [ -f "$hp" ] || hp=$d/robot-problem.pddl
  n=$(mega-sat diff --task "$d" | wc -l)
  s0=$(date +%s.%N)
  (cd "$work" && mega-sat mmp -s EE -a 1 -m "$OLDPWD/$dom/robot-domain.pddl" \
    -n "$OLDPWD/$dom/human-domain.pddl" -p "$OLDPWD/$d/robot-problem.pddl" -q "$OLDPWD/$hp" \
    > out.txt 2>/dev/null)
  s1=$(date +%s.%N)
  e_sat=$(grep -c '^Explanation >>' "$work/out.txt")
  a0=$(date +%s.%N)
  out=$(mega-sat solve --task "$d" --alpha 1 --engine astar --planner fd --timeout "$limit" --json)
  a1=$(date +%s.%N)
  e_astar=$(echo "$out" | python3 -c 'import json,sys; d=json.load(sys.stdin); print(len(d["chosen"]["explanation"]) if d.get("complete", True) and "chosen" in d else "—")' 2>/dev/null || echo "—")
  t_astar=$(printf '%.2f' "$(echo "$a1 - $a0" | bc)")
  complete=$(echo "$out" | python3 -c 'import json,sys; print(json.load(sys.stdin).get("complete"))' 2>/dev/null)
  [ "$complete" = "True" ] || t_astar="> $limit"
  printf '| %s | %s | %.2f | %s | %s | %s |\n' "$t" "$n" "$(echo "$s1 - $s0" | bc)" "$e_sat" "$t_astar" "$e_astar"
done
