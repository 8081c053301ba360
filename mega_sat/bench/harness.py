"""Benchmark harness: the A* baseline against the SAT engine, side by side (bench/README.md).

Suites:

* ``paper``   — the paper's Table "times" grid: every ``domains/<name>/delta/<K>/<pN>`` at
  Delta = 2, 7, 10, both engines;
* ``scaling`` — the same at Delta = 15, 20, 30 (beyond the paper), where A* MEGA runs out of time;
* ``sweep``   — one ``sat`` frontier per base problem ``domains/<name>/<pN>``, re-scored for a grid
  of alpha values (paper property 4), reproducing the paper's trade-off figure;
* ``smoke``   — one small base problem, both engines (what the tests run);
* ``missing-schemas`` — the hand-written problems ``domains/missing-schemas/<name>/<pN>``, whose
  human models lack whole robot schemas (|Delta| 20-50): both engines, the ``sat`` engine in its
  default configuration, plus one Fast Downward call on the robot model to read the frontier
  time as a multiple of "just planning";
* ``all``     — paper + scaling + sweep.

Every engine run is a separate subprocess (``python -m mega_sat.bench.harness _run ...``) so that a
time limit really stops it (the whole process group is killed, Fast Downward included) and its
peak memory is its own.  Outputs (``--out``): ``results.json`` (records + machine), ``results.csv``,
``table.md`` and, for sweeps, ``sweep.csv`` and ``sweep-<domain>.png``.  Re-running into the same
folder replaces the records of the instances run again and keeps the others (``--fresh`` drops
them), so suites can be run one at a time.

Which |E| is which:

* ``E_ropt``   — the frontier's robot-optimal end: the smallest explanation found for a
  robot-optimal plan.  For ``astar`` this is the stopping node of Algorithm 1 (Property 1), for
  ``sat`` the last frontier point.  This is the ``|E|`` column of ``table.md``.
* ``E_alpha1`` — the explanation of the pair chosen for alpha = 1 (``astar``: the minimum node
  of Algorithm 1 run with alpha = 1; ``sat``: the frontier point minimising the objective).

``seconds`` is the wall time of grounding plus the engine (parsing and interpreter start-up
excluded; ``process_s`` includes them).  For ``sat`` runs a second subprocess times one optimal
planning call on the robot model alone (builtin A*, SAT OPT, and Fast Downward when installed),
so the engine time can be read as a multiple of "just planning".

This module is the ``bench`` command; the work is done in :mod:`~mega_sat.bench.suites` (which
instances and runs, generating absent ones), :mod:`~mega_sat.bench.runner` (one run in a worker
process), :mod:`~mega_sat.bench.tables` (the text of ``table.md``) and
:mod:`~mega_sat.bench.outputs` (the files), with :mod:`~mega_sat.bench.common` shared with
``bench-calls``.
"""

from __future__ import annotations

import sys
import time
from collections.abc import Sequence
from pathlib import Path
from typing import Any

import click

from mega_sat.bench.common import (
    dispatch,
    domains_option,
    echo_files,
    fresh_option,
    machine_info,
    previous_results,
    problem_key,
    run_machine_info,
)
from mega_sat.bench.outputs import plot_sweeps, write_outputs
from mega_sat.bench.runner import run_command, run_job
from mega_sat.bench.suites import (
    ALPHA_GRID,
    MISSING_SCHEMAS_DIR,
    SUITES,
    Instance,
    Job,
    discover,
    expected_but_missing,
    generate_missing,
    plan_jobs,
    suite_deltas,
)
from mega_sat.bench.tables import (
    disagreements,
    fmt_seconds,
    fmt_speedup,
    missing_schemas_summary,
    missing_schemas_table,
    paper_table,
    record_key,
    render_markdown,
    scaling_table,
    speedup,
    summary,
)
from mega_sat.executor import completed


def run_bench(
    root: Path,
    suite: str,
    out_dir: Path,
    *,
    only: Sequence[str] = (),
    time_limit: float | None = None,
    baseline: str | None = None,
    jobs: int = 1,
    fresh: bool = False,
    generate: bool = False,
    seed: int = 0,
    progress: bool = True,
    scheduler: str | None = None,
) -> dict[str, Path]:
    """Run a suite and write every output; returns the written files.  The runs go through
    :func:`mega_sat.executor.completed`: ``jobs`` threads here, or a Dask ``scheduler``."""
    from mega_sat.planners.fast_downward import fd_available

    if suite not in SUITES:
        raise click.UsageError(f"unknown suite {suite!r}")
    if not root.is_dir():
        raise click.UsageError(f"domains folder not found: {root}")
    fd = fd_available()
    if baseline is None:
        baseline = "fd" if fd else "builtin"
    if baseline == "fd" and not fd:
        raise click.UsageError(
            "--baseline-planner fd needs Fast Downward (pip install 'mega-sat[fd]')"
        )
    gen_log: list[dict[str, Any]] = []
    if generate:
        gen_log = generate_missing(root, suite_deltas(suite), seed, only)
    todo = plan_jobs(root, suite, only, time_limit, baseline)
    if not todo:  # refused before any file is written: empty tables would look like results
        raise click.UsageError(
            f"nothing to run: suite '{suite}' has no instance in {root}"
            + (f" matching --only {' --only '.join(only)}" if only else "")
        )
    robot_planners = ["builtin", "sat"] + (["fd"] if fd else [])

    prev = previous_results(out_dir, fresh)
    records: dict[tuple, dict[str, Any]] = {record_key(r): r for r in prev.get("records", [])}
    sweep_rows = [r for r in prev.get("sweep", [])]
    generation = {(g["domain"], g["problem"], g["delta"]): g for g in prev.get("generation", [])}
    for g in gen_log:
        generation[(g["domain"], g["problem"], g["delta"])] = g
    suites_run = ("paper", "scaling", "sweep") if suite == "all" else (suite,)
    for s in suites_run:
        for inst in expected_but_missing(root, s, only):
            generation.setdefault(
                (inst.domain, inst.problem, inst.delta),
                {
                    "domain": inst.domain,
                    "problem": inst.problem,
                    "delta": inst.delta,
                    "status": "missing",
                    "error": "instance folder absent (not generated)",
                },
            )

    from tqdm import tqdm

    from mega_sat.engines.progress import SHOW_AFTER, progress_wanted

    bar = tqdm(
        total=len(todo),
        desc=f"bench {suite}",
        unit="run",
        file=sys.stderr,
        disable=not (progress and progress_wanted()),  # a terminal only, as for solve
        delay=SHOW_AFTER,
    )
    t0 = time.perf_counter()
    try:
        calls = [(j, robot_planners if j.engine == "sat" and not j.alphas else ()) for j in todo]
        for outcome in completed(run_job, calls, jobs=jobs, scheduler=scheduler):
            j = todo[outcome.index]
            if outcome.error is not None:
                raise outcome.error
            rec = outcome.value
            bar.set_postfix_str(f"{j.instance.label} {j.engine}: {rec.get('status')}")
            bar.update(1)
            rows = rec.pop("sweep", None)
            records[record_key(rec)] = rec
            if rows is not None:
                sweep_rows = [
                    r
                    for r in sweep_rows
                    if (r["domain"], r["problem"]) != (j.instance.domain, j.instance.problem)
                ]
                sweep_rows += [
                    {"domain": j.instance.domain, "problem": j.instance.problem, **r} for r in rows
                ]
    finally:
        bar.close()
    machine = run_machine_info(
        jobs,
        {
            "suite": suite,
            "wall_s": round(time.perf_counter() - t0, 1),
            "baseline_planner": baseline,
            "runs": len(todo),
        },
    )
    ordered = sorted(
        records.values(),
        key=lambda r: (
            str(r.get("suite")),
            r.get("domain"),
            problem_key(r.get("problem", "")),
            r.get("delta") if r.get("delta") is not None else -1,
            r.get("engine"),
        ),
    )
    sweep_rows.sort(key=lambda r: (r["domain"], problem_key(r["problem"]), r["alpha"]))
    return write_outputs(out_dir, ordered, machine, sweep_rows, list(generation.values()))


@click.command("bench")
@click.option(
    "--suite",
    type=click.Choice(SUITES),
    default="smoke",
    show_default=True,
    help="paper: Δ=2/7/10 grid; scaling: Δ=15/20/30; sweep: alpha sweeps on the "
    "base problems; smoke: one small instance; missing-schemas: the hand-written "
    "problems with robot-only schemas, both engines and one FD robot call; all: "
    "paper+scaling+sweep.",
)
@domains_option
@click.option(
    "--only",
    multiple=True,
    help="Keep domains, domain/problem or domain/delta/K/problem matching this "
    "pattern (repeatable).",
)
@click.option(
    "--time-limit",
    type=float,
    default=None,
    help="Seconds per engine run (default: 300 paper and sweep, 60 scaling, smoke and "
    "missing-schemas).",
)
@click.option(
    "--baseline-planner",
    type=click.Choice(["fd", "builtin"]),
    default=None,
    help="Per-node planner of the astar baseline, also the sat engine's OPT planner "
    "except in missing-schemas (default: fd if installed).",
)
@click.option("--out", "out_dir", type=click.Path(), default="bench/results", show_default=True)
@click.option(
    "--jobs",
    type=int,
    default=1,
    show_default=True,
    help="Parallel runs (>1 skews timings; use 1 for published numbers).",
)
@fresh_option
@click.option(
    "--generate",
    is_flag=True,
    help="First generate absent Δ-k instances (same seeds as generate-suite), "
    "skipping draws that fail.",
)
@click.option("--seed", type=int, default=0, show_default=True, help="Seed for --generate.")
@click.option(
    "--quiet",
    is_flag=True,
    help="No progress bar on stderr (otherwise shown on a terminal after 1 s).",
)
@click.option("--no-progress", is_flag=True, hidden=True, help="The same as --quiet.")
@click.option(
    "--scheduler",
    default=None,
    metavar="ADDRESS",
    help="Run on a Dask cluster (tcp://HOST:PORT); workers need this folder at the same path.",
)
def bench_command(
    suite: str,
    domains_dir: str,
    only: tuple[str, ...],
    time_limit: float | None,
    baseline_planner: str | None,
    out_dir: str,
    jobs: int,
    fresh: bool,
    generate: bool,
    seed: int,
    quiet: bool,
    no_progress: bool,
    scheduler: str | None,
) -> None:
    """Benchmark the astar baseline against the sat engine (paper Table "times" layout)."""
    if time_limit is not None and not time_limit > 0:
        raise click.UsageError("--time-limit must be > 0")
    t0 = time.perf_counter()
    files = run_bench(
        Path(domains_dir),
        suite,
        Path(out_dir),
        only=only,
        time_limit=time_limit,
        baseline=baseline_planner,
        jobs=jobs,
        fresh=fresh,
        generate=generate,
        seed=seed,
        progress=not (quiet or no_progress),
        scheduler=scheduler,
    )
    echo_files(files, t0)


def _main(argv: list[str] | None = None) -> None:
    dispatch(argv, run_command, bench_command, "mega_sat.bench.harness")


if __name__ == "__main__":
    _main()

# the names this module has always offered (``mega_sat.benchmark`` is its old path)
__all__ = [
    "ALPHA_GRID",
    "MISSING_SCHEMAS_DIR",
    "Instance",
    "Job",
    "bench_command",
    "discover",
    "disagreements",
    "fmt_seconds",
    "fmt_speedup",
    "generate_missing",
    "machine_info",
    "missing_schemas_summary",
    "missing_schemas_table",
    "paper_table",
    "plan_jobs",
    "plot_sweeps",
    "render_markdown",
    "run_bench",
    "scaling_table",
    "speedup",
    "summary",
    "write_outputs",
]
