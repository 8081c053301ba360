#!/bin/bash
# Two source trees on the same tasks, task by task in turns (old, then new), so that a drift
# of the machine's speed during the run hits both alike: bench/frontier-runs.sh's line per
# task and JSON for each, in OUT/old and OUT/new.
# usage: bench/frontier-ab.sh OLD_TREE NEW_TREE OUT TIMEOUT 'domains/*/delta/20/p*' [options]
#   e.g. git worktree add /tmp/old <commit>; bench/frontier-ab.sh /tmp/old "$PWD" /tmp/ab 60 ...
# Run from the repository root with the project's .venv.
set -u
old=$1; new=$2; out=$3; limit=$4; pattern=$5; shift 5
for t in $pattern; do
  for side in old new; do
    tree=$old; [ "$side" = new ] && tree=$new
    printf '%-4s ' "$side"
    TREE=$tree bench/frontier-runs.sh "$out/$side" "$limit" "$t" "$@"
  done
done
