"""One measurement: an engine run on one instance in a worker process of its own.

The parent (:func:`run_job`) starts ``python -m mega_sat.bench.harness _run ...`` through
:func:`mega_sat.bench.common.run_worker`, so a time limit really stops the run (the whole process
group is killed, Fast Downward included) and its peak memory is its own.  The worker
(:func:`run_command`) measures with the engine's public interface only: a
:class:`mega_sat.api.MegaSolver` for the frontier and the alpha answers, and a
:class:`mega_sat.planners.node_planner.NodePlanner` for one optimal call on the robot model.
"""

from __future__ import annotations

import time
from collections.abc import Sequence
from dataclasses import asdict
from typing import Any

import click

from mega_sat.bench.common import failure_record, peak_rss_mb, run_worker, write_json
from mega_sat.bench.suites import ENGINES, Job

# the module whose ``_run`` command is the worker; ``python -m mega_sat.bench.harness _run``
# is the entry the documentation names
WORKER_MODULE = "mega_sat.bench.harness"

# --------------------------------------------------------------------------- worker (child)


def robot_end(fr) -> int | None:
    ends = [p.size for p in fr.points if p.robot_cost == fr.robot_optimal_cost]
    return min(ends) if ends else None


def run_engine(
    task_dir: str,
    engine: str,
    planner: str | None,
    time_limit: float,
    alphas: Sequence[float] = (),
    out: str | None = None,
) -> dict[str, Any]:
    """One engine run on one task (inside the worker process): frontier + alpha = 1 answer."""
    from mega_sat.api import MegaSolver, load_task_dir
    from mega_sat.deadline import TimeLimitReached
    from mega_sat.errors import UnsolvableError
    from mega_sat.results import choose

    rec: dict[str, Any] = {"engine": engine, "planner": planner}
    t0 = time.perf_counter()
    task = load_task_dir(task_dir)
    rec["load_s"] = round(time.perf_counter() - t0, 4)
    rec["delta_size"] = len(task.delta)
    solver = MegaSolver(task, engine=engine, planner=planner, timeout=time_limit)
    t1 = time.perf_counter()
    try:
        fam = solver.family  # grounding, counted in ``seconds`` (no engine runs without it)
        rec["ground_s"] = round(time.perf_counter() - t1, 4)
        rec["ground_atoms"], rec["ground_actions"] = len(fam.atoms), len(fam.actions)
        rec["planner_used"] = solver.planner  # the default configuration's choice when None
        if engine == "sat":
            fr = solver.frontier()
            if not fr.points:  # stopped by the limit before the first point
                rec["seconds"] = round(time.perf_counter() - t1, 4)
                rec.update(
                    status="timeout" if not fr.complete else "error",
                    error="no frontier point: " + "; ".join(fr.notes),
                    next_size_lower_bound=fr.next_size_lower_bound,
                    stats=fr.stats,
                )
                return rec
            sol = choose(fr, 1.0)
        else:
            sol = solver.solve(1.0)
    except TimeLimitReached as e:
        # the limit came before anything to report: for astar, before any node the robot can
        # execute; for sat, before the robot optimum (a later stop returns a partial frontier)
        rec["seconds"] = round(time.perf_counter() - t1, 4)
        rec.update(status="timeout", error=str(e))
        return rec
    except UnsolvableError as e:
        rec["seconds"] = round(time.perf_counter() - t1, 4)
        rec.update(status="error", error=str(e))
        return rec
    rec["seconds"] = round(time.perf_counter() - t1, 4)
    fr = sol.frontier
    rec.update(
        status="ok" if fr.complete else "timeout",
        engine_time_s=round(fr.time_s, 4),
        E_ropt=robot_end(fr),
        E_alpha1=sol.chosen.size,
        explanation_alpha1=list(sol.chosen.explanation),
        robot_cost_alpha1=sol.chosen.robot_cost,
        objective_alpha1=float(sol.objective),
        robot_optimal_cost=fr.robot_optimal_cost,
        frontier_points=len(fr.points),
        frontier=[[p.size, p.robot_cost] for p in fr.points],
        exact=fr.exact,
        complete=fr.complete,
        next_size_lower_bound=fr.next_size_lower_bound,
        notes=list(fr.notes),
        stats=fr.stats,
    )
    for k in (
        "nodes_expanded",
        "planner_calls",
        "planner_time_s",
        "iterations",
        "opt_calls",
        "joint_calls",
        "learned",
        "learned_literals",
    ):
        if k in fr.stats:
            rec[k] = fr.stats[k]
    if alphas and engine == "sat":
        rows = []
        for a in alphas:
            s = solver.solve(a)
            rows.append(
                {
                    "alpha": a,
                    "E": s.chosen.size,
                    "explicability_cost": s.chosen.robot_cost - fr.robot_optimal_cost,
                    "robot_cost": s.chosen.robot_cost,
                    "robot_optimal_cost": fr.robot_optimal_cost,
                    "objective": float(s.objective),
                    "exact": fr.exact,
                }
            )
        rec["sweep"] = rows
    if out:
        write_json(out, rec)
    return rec


def time_robot_calls(task_dir: str, planners: Sequence[str], time_limit: float) -> dict[str, Any]:
    """Seconds of one optimal planning call on the robot model alone, per planner (grounding
    excluded, encoding/solver set-up included, as a fresh engine would pay it)."""
    from mega_sat.api import MegaSolver, load_task_dir
    from mega_sat.planners.node_planner import NodePlanner

    task = load_task_dir(task_dir)
    fam = MegaSolver(task).family
    rec: dict[str, Any] = {}
    for kind in planners:
        t0 = time.perf_counter()
        r = NodePlanner(task, fam, kind, time_limit=time_limit).optimal(fam.robot_selection)
        dt = time.perf_counter() - t0
        rec[f"robot_call_{kind}_s"] = round(dt, 4) if r.status == "optimal" else None
        rec[f"robot_call_{kind}_status"] = r.status
        rec[f"robot_call_{kind}_cost"] = r.cost
    return rec


@click.command("_run", hidden=True)
@click.option("--task", "task_dir", required=True)
@click.option("--engine", type=click.Choice(ENGINES), default="sat")
@click.option("--planner", default=None)
@click.option("--time-limit", type=float, required=True)
@click.option("--alphas", default="", help="Comma-separated alphas (sat sweep).")
@click.option("--robot-calls", default="", help="Only time robot-model calls of these planners.")
@click.option("--out", "out", required=True, help="Result JSON file.")
def run_command(
    task_dir: str,
    engine: str,
    planner: str | None,
    time_limit: float,
    alphas: str,
    robot_calls: str,
    out: str,
) -> None:
    """Worker: one measurement, result written to ``--out`` (JSON)."""
    t0 = time.perf_counter()
    try:
        if robot_calls:
            rec = time_robot_calls(task_dir, robot_calls.split(","), time_limit)
        else:
            al = [float(a) for a in alphas.split(",") if a.strip()]
            rec = run_engine(task_dir, engine, planner, time_limit, al)
            rec.setdefault("status", "ok")
    except Exception as e:  # noqa: BLE001 - the parent records the failure
        rec = failure_record(e)
    rec["peak_rss_mb"], rec["peak_rss_children_mb"] = peak_rss_mb()
    rec["worker_s"] = round(time.perf_counter() - t0, 4)
    write_json(out, rec)


# --------------------------------------------------------------------------- parent side


def spawn(args: list[str], hard_limit: float) -> dict[str, Any]:
    """Run one worker; kill its process group at ``hard_limit`` seconds."""
    w = run_worker(WORKER_MODULE, args, hard_limit, watch_memory=True)
    rec = w.rec
    if w.killed:
        rec.update(
            status="timeout", killed=True, error=f"killed at the hard limit ({hard_limit:.0f}s)"
        )
        rec.setdefault("peak_rss_mb", w.peak_mb or None)
    elif not rec:
        rec = {"status": "error", "error": w.exit_error}
        rec["peak_rss_mb"] = w.peak_mb or None
    rec["process_s"] = round(w.seconds, 3)
    return rec


def hard_limit_for(limit: float) -> float:
    """Engines check their own limit between steps; a grace period lets them report the partial
    frontier, after which the process group is killed."""
    return limit + max(10.0, 0.2 * limit)


def run_job(job: Job, robot_call_planners: Sequence[str]) -> dict[str, Any]:
    """One (instance, engine) record; for ``sat`` also the robot-model call timings."""
    inst = job.instance
    args = ["--task", inst.task_dir, "--engine", job.engine, "--time-limit", repr(job.time_limit)]
    if job.planner:
        args += ["--planner", job.planner]
    if job.alphas:
        args += ["--alphas", ",".join(repr(float(a)) for a in job.alphas)]
    rec = spawn(args, hard_limit_for(job.time_limit))
    rec.update({k: v for k, v in asdict(inst).items()})
    rec["engine"] = job.engine
    rec["planner"] = job.planner or rec.get("planner_used") or "builtin"
    rec["time_limit_s"] = job.time_limit
    if rec.get("status") != "error":
        rec.pop("traceback", None)
    if job.engine == "sat" and robot_call_planners and rec.get("status") != "error":
        rc = spawn(
            [
                "--task",
                inst.task_dir,
                "--time-limit",
                repr(job.time_limit),
                "--robot-calls",
                ",".join(robot_call_planners),
            ],
            hard_limit_for(job.time_limit),
        )
        for kind in robot_call_planners:
            v = rc.get(f"robot_call_{kind}_s")
            rec[f"robot_call_{kind}_s"] = v
            rec[f"robot_call_{kind}_status"] = rc.get(f"robot_call_{kind}_status", rc.get("status"))
            s = rec.get("seconds")
            rec[f"ratio_sat_vs_{kind}_call"] = (
                round(s / v, 2) if s and v and rec.get("status") == "ok" else None
            )
    return rec


__all__ = [
    "WORKER_MODULE",
    "hard_limit_for",
    "robot_end",
    "run_command",
    "run_engine",
    "run_job",
    "spawn",
    "time_robot_calls",
]
