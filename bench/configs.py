"""Every configuration of the ``sat`` engine, and the ``astar`` engine at its defaults, as
whole ``mega-sat frontier`` processes side by side: is the default ever the wrong choice?

For each task folder, each configuration (planner x JOINT method x hitting-set solver; the
default is the one without options) runs once (see ``--repeat``), one process at a time,
under ``--timeout``.  The table gives the default's wall seconds, the best configuration's,
their ratio, the ``astar`` engine's (its defaults: the built-in planner) and the speedup of
the default over it.  A configuration that does not finish exactly within the limit counts
as the limit.  Every configuration that finishes must give the same frontier pairs (|E|,
robot cost); a disagreement is printed and recorded, as it would be a bug.

    python bench/configs.py --out bench/results/configs --time-limit 60 \\
        'domains/*/delta/2/p*' 'domains/*/delta/7/p*' 'domains/*/delta/10/p*'

Records are merged into ``OUT/results.json`` (re-running a task replaces its records), and
``OUT/table.md`` is written from all of them.

``--cutoff``: every other configuration gets the default's wall seconds as its limit instead
of ``--time-limit`` (when the default finished exactly).  The target is "the default takes at
most 1.5x the best configuration", and a configuration stopped at the default's time cannot
be 1.5x faster than it, so the verdict is the same at a fraction of the machine time; the
table marks such a best time with ``>``.  Used for the scaling suite, whose slow
configurations would otherwise run to the limit on every task.

``--repeat N``: a run that takes under ``--repeat-below`` seconds (5) is run N times in all
and its fastest run counts (every run's wall seconds are kept in ``walls_s``).  Short runs
are mostly start-up and vary from run to run, by as much as the target allows between
configurations; the fastest of a few is the usual estimate of what the code itself costs
(the spread is measured in bench/README.md).
"""

from __future__ import annotations

import argparse
import glob
import itertools
import json
import os
import statistics
import subprocess
import sys
import time
from pathlib import Path

PLANNERS = ("portfolio", "sat", "builtin", "fd")
JOINTS = ("sat", "portfolio", "search")
HITTING = ("rc2", "ilp")


def configs(planners, product: bool):
    """``(label, extra CLI arguments)``: the default first, then the product of the choices
    (or, without ``product``, one choice changed at a time)."""
    out = [("default", [])]
    if product:
        for p, j, h in itertools.product(planners, JOINTS, HITTING):
            out.append((f"{p}/{j}/{h}", ["--planner", p, "--joint", j, "--hitting-set", h]))
    else:
        # the defaults' own values (portfolio, sat, rc2) are the default run itself
        out += [(f"planner {p}", ["--planner", p]) for p in planners[1:]]
        out += [(f"joint {j}", ["--joint", j]) for j in JOINTS[1:]]
        out += [(f"hitting-set {h}", ["--hitting-set", h]) for h in HITTING[1:]]
    return out


def run(task: str, args: list[str], limit: float, engine: str = "sat") -> dict:
    cmd = [sys.executable, "-m", "mega_sat.cli.commands", "frontier", "--task", task]
    cmd += ["--engine", engine, "--timeout", str(limit), "--json", "--quiet", *args]
    t0 = time.perf_counter()
    p = subprocess.run(cmd, capture_output=True, text=True, timeout=limit + 60)
    wall = time.perf_counter() - t0
    rec = {"wall_s": round(wall, 3), "exit": p.returncode}
    try:
        d = json.loads(p.stdout)
    except json.JSONDecodeError:
        rec["error"] = (p.stderr.strip().splitlines() or ["no output"])[-1]
        return rec
    rec["exact"] = bool(d.get("exact"))
    rec["complete"] = bool(d.get("complete"))
    rec["pairs"] = [[len(x["explanation"]), x["robot_cost"]] for x in d.get("frontier", [])]
    return rec


def run_best(
    task: str, args: list[str], limit: float, repeat: int, below: float, engine: str = "sat"
) -> dict:
    """:func:`run`, repeated up to ``repeat`` times in all while its runs take under
    ``below`` seconds: the record of the fastest, with every run's wall seconds."""
    recs = [run(task, args, limit, engine)]
    while len(recs) < repeat and max(r["wall_s"] for r in recs) < below:
        recs.append(run(task, args, limit, engine))
    done = "exact" if engine == "sat" else "complete"
    best = min(recs, key=lambda r: (not r.get(done), r["wall_s"]))
    if len(recs) > 1:
        best = {**best, "walls_s": [r["wall_s"] for r in recs]}
    return best


def fd_installed() -> bool:
    try:
        from mega_sat.planners.fast_downward import fd_available
    except ImportError:
        return False
    return fd_available()


def main() -> None:
    ap = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    ap.add_argument("tasks", nargs="+", help="task folders or shell patterns")
    ap.add_argument("--out", default="bench/results/configs")
    ap.add_argument("--time-limit", type=float, default=60.0)
    ap.add_argument("--product", action="store_true", help="every planner x JOINT x hitting set")
    ap.add_argument("--no-astar", action="store_true")
    ap.add_argument(
        "--cutoff",
        action="store_true",
        help="limit every other configuration to the default's wall seconds",
    )
    ap.add_argument(
        "--repeat",
        type=int,
        default=1,
        help="runs in all of each configuration that takes under --repeat-below seconds; "
        "the fastest counts",
    )
    ap.add_argument("--repeat-below", type=float, default=5.0)
    a = ap.parse_args()
    if a.repeat < 1:
        ap.error("--repeat must be at least 1")
    # bytecode first, as an installed package has it: where PYTHONDONTWRITEBYTECODE is set,
    # every process would otherwise compile each module it imports from source (the engine
    # that imports more pays more), which is not what a user's run pays
    import compileall

    import mega_sat

    compileall.compile_dir(Path(mega_sat.__file__).parent, quiet=1)
    planners = [p for p in PLANNERS if p != "fd" or fd_installed()]
    tasks = sorted({t for pat in a.tasks for t in (glob.glob(pat) or [pat]) if os.path.isdir(t)})
    out = Path(a.out)
    out.mkdir(parents=True, exist_ok=True)
    store = out / "results.json"
    records = json.loads(store.read_text()) if store.exists() else {}
    for task in tasks:
        rows = {}
        limit = a.time_limit
        for label, args in configs(planners, a.product):
            rows[label] = run_best(task, args, limit, a.repeat, a.repeat_below)
            rows[label]["limit_s"] = limit
            print(task, label, rows[label].get("wall_s"), rows[label].get("exact"), flush=True)
            if label == "default" and a.cutoff and rows[label].get("exact"):
                limit = min(a.time_limit, rows[label]["wall_s"])
        if not a.no_astar:
            rows["astar default"] = run_best(
                task, [], a.time_limit, a.repeat, a.repeat_below, engine="astar"
            )
            print(task, "astar", rows["astar default"].get("wall_s"), flush=True)
        records[task] = {"time_limit": a.time_limit, "runs": rows}
        store.write_text(json.dumps(records, indent=1))
    (out / "table.md").write_text(table(records))
    print(table(records))


def _seconds(r: dict, limit: float) -> float:
    return r["wall_s"] if r.get("exact") else max(r.get("limit_s", limit), r["wall_s"])


def table(records: dict) -> str:
    lines = [
        "| task | default s | best configuration | best s | default / best | astar s | "
        "astar / default |",
        "|---|---|---|---|---|---|---|",
    ]
    ratios, speedups, bad = [], [], []
    for task, rec in sorted(records.items()):
        runs, limit = rec["runs"], rec["time_limit"]
        sat = {k: v for k, v in runs.items() if k != "astar default"}
        pairs = {json.dumps(v["pairs"]) for v in sat.values() if v.get("exact")}
        if len(pairs) > 1:
            bad.append(task)
        d = _seconds(sat["default"], limit)
        best_label = min(sat, key=lambda k: _seconds(sat[k], limit))
        b = _seconds(sat[best_label], limit)
        ratio = d / b if b > 0 else 1.0
        ratios.append(ratio)
        a_cell, s_cell = "-", "-"
        if "astar default" in runs:
            ar = runs["astar default"]
            a = ar["wall_s"] if ar.get("complete") else max(limit, ar["wall_s"])
            sp = a / d
            speedups.append(sp)
            mark = "" if ar.get("complete") else "> "
            a_cell, s_cell = f"{mark}{a:.2f}", f"{mark}{sp:.2f}"
        dmark = "" if sat["default"].get("exact") else "> "
        bmark = "" if sat[best_label].get("exact") else "> "
        lines.append(
            f"| {task} | {dmark}{d:.2f} | {best_label} | {bmark}{b:.2f} | {ratio:.2f} | {a_cell} | "
            f"{s_cell} |"
        )
    lines.append("")
    if ratios:
        lines.append(
            f"default within 1.5x of the best on {sum(r <= 1.5 for r in ratios)} of "
            f"{len(ratios)} tasks; worst ratio {max(ratios):.2f}, median "
            f"{statistics.median(ratios):.2f}"
        )
    if speedups:
        lines.append(
            f"astar (defaults) / sat (default), whole processes: >= 1 on "
            f"{sum(s >= 1 for s in speedups)} of {len(speedups)}; min {min(speedups):.2f}, "
            f"median {statistics.median(speedups):.2f}"
        )
    if bad:
        lines.append("configurations disagree on the frontier: " + ", ".join(bad))
    return "\n".join(lines) + "\n"


if __name__ == "__main__":
    main()
