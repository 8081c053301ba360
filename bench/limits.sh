#!/usr/bin/env bash
# Run-level limits on every shipped task (see bench/README.md, "Run-level limits"): each task's
# frontier under an address-space limit and a time limit, one line per task with its exit code,
# wall seconds, peak resident memory (KB) and the number of traceback / MemoryError lines.
#
#   bench/limits.sh [LIMIT_SECONDS [ADDRESS_SPACE_KB]]      (defaults: 10 s, 4 GB)
set -uo pipefail
cd "$(dirname "$0")/.."
limit=${1:-10}
vmem=${2:-4194304}
for d in $(find domains -name robot-problem.pddl | sed 's|/[^/]*$||' | sort); do
  err=$( (ulimit -v "$vmem"; /usr/bin/time -f "TIME %e %M" mega-sat frontier --task "$d" \
    --timeout "$limit" --json) 2>&1 >/dev/null)
  rc=$?
  echo "$d rc=$rc $(echo "$err" | grep '^TIME') $(echo "$err" | grep -ci 'traceback\|memoryerror')"
done
