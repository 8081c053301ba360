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
"""

from __future__ import annotations

import contextlib
import csv
import datetime as _dt
import fnmatch
import json
import os
import platform
import signal
import statistics
import subprocess
import sys
import tempfile
import time
from collections.abc import Callable, Iterable, Sequence
from dataclasses import asdict, dataclass
from pathlib import Path
from typing import Any

import click

from mega_sat.executor import completed

SUITES = ("paper", "scaling", "sweep", "smoke", "missing-schemas", "all")
PAPER_DELTAS = (2, 7, 10)
SCALING_DELTAS = (15, 20, 30)
ALPHA_GRID = (0, 0.05, 0.1, 0.2, 0.3, 0.5, 0.75, 1, 1.5, 2, 3, 5, 10)
DEFAULT_LIMITS = {
    "paper": 300.0,
    "scaling": 60.0,
    "sweep": 300.0,
    "smoke": 60.0,
    "missing-schemas": 60.0,
}
# the folder under the domains root that holds the missing-schemas suite's domains; it has no
# robot-domain.pddl itself, so the other suites' discovery (and generate-suite) skip it
MISSING_SCHEMAS_DIR = "missing-schemas"
# what the missing-schemas suite is read against: every frontier exact within this many
# seconds, and the median frontier time within this multiple of one FD call on the robot model
MISSING_SCHEMAS_TARGET_S = 10.0
MISSING_SCHEMAS_TARGET_RATIO = 20.0
SMOKE_INSTANCE = ("usar-fetch", "p1")
ENGINES = ("astar", "sat")

CSV_FIELDS = (
    "suite",
    "domain",
    "problem",
    "delta",
    "engine",
    "planner",
    "status",
    "error",
    "time_limit_s",
    "seconds",
    "engine_time_s",
    "ground_s",
    "load_s",
    "process_s",
    "delta_size",
    "ground_atoms",
    "ground_actions",
    "E_ropt",
    "E_alpha1",
    "robot_cost_alpha1",
    "objective_alpha1",
    "robot_optimal_cost",
    "frontier_points",
    "exact",
    "complete",
    "next_size_lower_bound",
    "peak_rss_mb",
    "peak_rss_children_mb",
    "nodes_expanded",
    "planner_calls",
    "planner_time_s",
    "iterations",
    "opt_calls",
    "joint_calls",
    "learned",
    "learned_literals",
    "robot_call_builtin_s",
    "robot_call_sat_s",
    "robot_call_fd_s",
    "ratio_sat_vs_builtin_call",
    "ratio_sat_vs_sat_call",
    "ratio_sat_vs_fd_call",
    "task_dir",
)
SWEEP_FIELDS = (
    "domain",
    "problem",
    "alpha",
    "E",
    "explicability_cost",
    "robot_cost",
    "robot_optimal_cost",
    "objective",
    "exact",
)


# --------------------------------------------------------------------------- instances


@dataclass(frozen=True)
class Instance:
    """One task folder in one suite; ``delta`` is None for base problems."""

    suite: str
    domain: str
    problem: str
    delta: int | None
    task_dir: str

    @property
    def label(self) -> str:
        d = "" if self.delta is None else f"/delta{self.delta}"
        return f"{self.domain}{d}/{self.problem}"


def _is_task_dir(p: Path) -> bool:
    return (p / "robot-problem.pddl").is_file()


def _domain_dirs(root: Path) -> list[Path]:
    return sorted(d for d in root.iterdir() if (d / "robot-domain.pddl").is_file())


def _matches(domain: str, problem: str, only: Sequence[str], delta: int | None = None) -> bool:
    """``--only`` patterns (fnmatch) match the domain name, ``domain/problem`` or, for a
    generated instance, ``domain/delta/K/problem``."""
    if not only:
        return True
    names = [domain, f"{domain}/{problem}"]
    if delta is not None:
        names.append(f"{domain}/delta/{delta}/{problem}")
    return any(fnmatch.fnmatch(n, o) for n in names for o in only)


def discover(root: Path, suite: str, only: Sequence[str] = ()) -> list[Instance]:
    """The instances of one suite found on disk (generated Delta-k folders only)."""
    out: list[Instance] = []
    if suite == "missing-schemas":
        base = root / MISSING_SCHEMAS_DIR
        for d in _domain_dirs(base) if base.is_dir() else []:
            for p in sorted(
                (p for p in d.iterdir() if _is_task_dir(p)), key=lambda p: _pkey(p.name)
            ):
                if _matches(d.name, p.name, only):
                    out.append(Instance(suite, d.name, p.name, None, str(p)))
        return out
    for d in _domain_dirs(root):
        if suite in ("sweep", "smoke"):
            for p in sorted(p for p in d.iterdir() if _is_task_dir(p)):
                if _matches(d.name, p.name, only):
                    out.append(Instance(suite, d.name, p.name, None, str(p)))
            continue
        deltas = PAPER_DELTAS if suite == "paper" else SCALING_DELTAS
        for k in deltas:
            kd = d / "delta" / str(k)
            if not kd.is_dir():
                continue
            for p in sorted(p for p in kd.iterdir() if _is_task_dir(p)):
                if _matches(d.name, p.name, only, k):
                    out.append(Instance(suite, d.name, p.name, k, str(p)))
    if suite == "smoke":
        want = [i for i in out if (i.domain, i.problem) == SMOKE_INSTANCE]
        out = want or out[:1]
    return out


def expected_but_missing(root: Path, suite: str, only: Sequence[str] = ()) -> list[Instance]:
    """Delta-k instances the grid calls for whose folder is absent (not generated / failed)."""
    if suite not in ("paper", "scaling"):
        return []
    deltas = PAPER_DELTAS if suite == "paper" else SCALING_DELTAS
    missing = []
    for d in _domain_dirs(root):
        for p in sorted(p for p in d.iterdir() if _is_task_dir(p)):
            for k in deltas:
                target = d / "delta" / str(k) / p.name
                if _matches(d.name, p.name, only, k) and not _is_task_dir(target):
                    missing.append(Instance(suite, d.name, p.name, k, str(target)))
    return missing


def generate_missing(
    root: Path, deltas: Iterable[int], seed: int = 0, only: Sequence[str] = ()
) -> list[dict[str, Any]]:
    """Generate the absent ``delta/<K>/<pN>`` folders exactly as ``mega-sat generate-suite``
    does (same per-instance seeds), but keep going when one draw fails, so one unsolvable
    instance does not leave the rest of the grid empty.  Returns one entry per attempt."""
    from mega_sat.bench.generate import instance_seed, write_instance

    log = []
    for d in _domain_dirs(root):
        for p in sorted(p for p in d.iterdir() if _is_task_dir(p)):
            if not _matches(d.name, p.name, only):
                continue
            for k in deltas:
                out = d / "delta" / str(k) / p.name
                if _is_task_dir(out) and (out / "human-domain.pddl").is_file():
                    continue
                t0 = time.perf_counter()
                entry: dict[str, Any] = {"domain": d.name, "problem": p.name, "delta": k}
                try:
                    g = write_instance(
                        d / "robot-domain.pddl",
                        p / "robot-problem.pddl",
                        k,
                        instance_seed(seed, d.name, p.name, k),
                        out,
                    )
                    entry.update(status="ok", attempts=g.attempts)
                except Exception as e:  # noqa: BLE001 - recorded and skipped, by design
                    entry.update(status="failed", error=f"{type(e).__name__}: {e}")
                entry["seconds"] = round(time.perf_counter() - t0, 3)
                log.append(entry)
    return log


# --------------------------------------------------------------------------- worker (child)


def _rss_mb() -> tuple[float, float]:
    import resource

    self_kb = resource.getrusage(resource.RUSAGE_SELF).ru_maxrss
    child_kb = resource.getrusage(resource.RUSAGE_CHILDREN).ru_maxrss
    return round(self_kb / 1024, 1), round(child_kb / 1024, 1)


def _write_json(path: str, data: dict[str, Any]) -> None:
    tmp = path + ".tmp"
    Path(tmp).write_text(json.dumps(data, indent=1, default=str))
    os.replace(tmp, path)


def _failure(e: Exception) -> dict[str, Any]:
    """The record of a worker whose measurement raised ``e`` (call it in the ``except``)."""
    import traceback

    return {
        "status": "error",
        "error": f"{type(e).__name__}: {e}",
        "traceback": traceback.format_exc(limit=8),
    }


def _robot_end(fr) -> int | None:
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
    from mega_sat.api import MegaSolver
    from mega_sat.errors import UnsolvableError
    from mega_sat.pddl.loading import load_task, resolve_task_dir
    from mega_sat.results import choose

    rec: dict[str, Any] = {"engine": engine, "planner": planner}
    t0 = time.perf_counter()
    paths = resolve_task_dir(task_dir)
    task = load_task(
        paths["robot_domain"], paths["robot_problem"], paths["human_domain"], paths["human_problem"]
    )
    rec["load_s"] = round(time.perf_counter() - t0, 4)
    rec["delta_size"] = len(task.delta)
    solver = MegaSolver(task, engine=engine, planner=planner, timeout=time_limit)
    t1 = time.perf_counter()
    fam = solver.family  # grounding, counted in ``seconds`` (the engine cannot run without it)
    rec["ground_s"] = round(time.perf_counter() - t1, 4)
    rec["ground_atoms"], rec["ground_actions"] = len(fam.atoms), len(fam.actions)
    rec["planner_used"] = solver.planner  # the default configuration's choice when None
    try:
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
    except UnsolvableError as e:
        # the astar engine raises when its time limit hit before any robot-executable node
        rec["seconds"] = round(time.perf_counter() - t1, 4)
        timed_out = "time limit" in str(e)
        rec.update(status="timeout" if timed_out else "error", error=str(e))
        return rec
    rec["seconds"] = round(time.perf_counter() - t1, 4)
    fr = sol.frontier
    rec.update(
        status="ok" if fr.complete else "timeout",
        engine_time_s=round(fr.time_s, 4),
        E_ropt=_robot_end(fr),
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
        _write_json(out, rec)
    return rec


def time_robot_calls(task_dir: str, planners: Sequence[str], time_limit: float) -> dict[str, Any]:
    """Seconds of one optimal planning call on the robot model alone, per planner (grounding
    excluded, encoding/solver set-up included, as a fresh engine would pay it)."""
    from mega_sat.ground.grounding import ground
    from mega_sat.pddl.loading import load_task, resolve_task_dir
    from mega_sat.planners.node_planner import NodePlanner

    paths = resolve_task_dir(task_dir)
    task = load_task(
        paths["robot_domain"], paths["robot_problem"], paths["human_domain"], paths["human_problem"]
    )
    fam = ground(task)
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
        rec = _failure(e)
    rec["peak_rss_mb"], rec["peak_rss_children_mb"] = _rss_mb()
    rec["worker_s"] = round(time.perf_counter() - t0, 4)
    _write_json(out, rec)


# --------------------------------------------------------------------------- parent side


def _vm_hwm_mb(pid: int) -> float | None:
    try:
        for line in Path(f"/proc/{pid}/status").read_text().splitlines():
            if line.startswith("VmHWM:"):
                return round(int(line.split()[1]) / 1024, 1)
    except (OSError, ValueError, IndexError):
        return None
    return None


@dataclass(frozen=True)
class _Worker:
    """What one worker process left behind (:func:`_run_worker`)."""

    rec: dict[str, Any]  # the JSON it wrote to ``--out``; {} if none
    killed: bool  # killed at the hard limit
    seconds: float
    peak_mb: float  # largest VmHWM seen; 0.0 unless watched
    exit_error: str  # "worker exited <code>: <stderr tail>"


def _run_worker(
    module: str,
    args: Sequence[str],
    hard_limit: float,
    *,
    prefix: str = "mega-bench-",
    watch_memory: bool = False,
    collect: Callable[[str, dict[str, Any]], None] | None = None,
) -> _Worker:
    """Run ``python -m <module> _run <args> --out FILE`` in its own session and a temporary
    folder; kill its process group at ``hard_limit`` seconds.  ``watch_memory`` polls its
    VmHWM every 0.05 s; ``collect(FILE, rec)`` runs before the folder is removed."""
    with tempfile.TemporaryDirectory(prefix=prefix) as tmp:
        out = os.path.join(tmp, "result.json")
        err_path = os.path.join(tmp, "stderr.txt")
        cmd = [sys.executable, "-m", module, "_run", *args, "--out", out]
        t0 = time.perf_counter()
        peak = 0.0
        killed = False
        with open(err_path, "w") as err:
            proc = subprocess.Popen(
                cmd, stdout=subprocess.DEVNULL, stderr=err, start_new_session=True
            )
            try:
                if not watch_memory:
                    try:
                        proc.wait(timeout=hard_limit)
                    except subprocess.TimeoutExpired:
                        killed = True
                while watch_memory and proc.poll() is None:
                    hwm = _vm_hwm_mb(proc.pid)
                    if hwm is not None:
                        peak = max(peak, hwm)
                    if time.perf_counter() - t0 > hard_limit:
                        killed = True
                        break
                    time.sleep(0.05)
            finally:
                # time limit, or the harness itself interrupted: never leave the group behind
                if proc.poll() is None:
                    with contextlib.suppress(ProcessLookupError):
                        os.killpg(proc.pid, signal.SIGKILL)
                    proc.wait()
        elapsed = time.perf_counter() - t0
        rec: dict[str, Any] = {}
        if Path(out).is_file():
            rec = json.loads(Path(out).read_text())
        if collect is not None:
            collect(out, rec)
        tail = Path(err_path).read_text()[-2000:]
        return _Worker(rec, killed, elapsed, peak, f"worker exited {proc.returncode}: {tail}")


def _spawn(args: list[str], hard_limit: float) -> dict[str, Any]:
    """Run one worker; kill its process group at ``hard_limit`` seconds."""
    w = _run_worker("mega_sat.bench.harness", args, hard_limit, watch_memory=True)
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


def _hard_limit(limit: float) -> float:
    """Engines check their own limit between steps; a grace period lets them report the partial
    frontier, after which the process group is killed."""
    return limit + max(10.0, 0.2 * limit)


@dataclass(frozen=True)
class Job:
    instance: Instance
    engine: str
    planner: str | None
    time_limit: float
    alphas: tuple[float, ...] = ()


def run_job(job: Job, robot_call_planners: Sequence[str]) -> dict[str, Any]:
    """One (instance, engine) record; for ``sat`` also the robot-model call timings."""
    inst = job.instance
    args = ["--task", inst.task_dir, "--engine", job.engine, "--time-limit", repr(job.time_limit)]
    if job.planner:
        args += ["--planner", job.planner]
    if job.alphas:
        args += ["--alphas", ",".join(repr(float(a)) for a in job.alphas)]
    rec = _spawn(args, _hard_limit(job.time_limit))
    rec.update({k: v for k, v in asdict(inst).items()})
    rec["engine"] = job.engine
    rec["planner"] = job.planner or rec.get("planner_used") or "builtin"
    rec["time_limit_s"] = job.time_limit
    if rec.get("status") != "error":
        rec.pop("traceback", None)
    if job.engine == "sat" and robot_call_planners and rec.get("status") != "error":
        rc = _spawn(
            [
                "--task",
                inst.task_dir,
                "--time-limit",
                repr(job.time_limit),
                "--robot-calls",
                ",".join(robot_call_planners),
            ],
            _hard_limit(job.time_limit),
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


def record_key(r: dict[str, Any]) -> tuple:
    return (r.get("suite"), r.get("domain"), r.get("problem"), r.get("delta"), r.get("engine"))


def machine_info() -> dict[str, Any]:
    """Where the numbers were measured (they only compare within one machine)."""
    from importlib import metadata

    from mega_sat.planners.fast_downward import fd_available

    cpu = platform.processor() or "unknown"
    try:
        for line in Path("/proc/cpuinfo").read_text().splitlines():
            if line.startswith("model name"):
                cpu = line.split(":", 1)[1].strip()
                break
    except OSError:
        pass
    ram_gb = None
    try:
        for line in Path("/proc/meminfo").read_text().splitlines():
            if line.startswith("MemTotal:"):
                ram_gb = round(int(line.split()[1]) / 1024 / 1024, 1)
    except OSError:
        pass

    def ver(name: str) -> str | None:
        try:
            return metadata.version(name)
        except metadata.PackageNotFoundError:
            return None

    return {
        "cpu": cpu,
        "cores": os.cpu_count(),
        "ram_gb": ram_gb,
        "python": platform.python_version(),
        "platform": platform.platform(),
        "packages": {
            n: ver(n)
            for n in ("mega-sat", "python-sat", "PuLP", "up_fast_downward", "click", "numpy")
        },
        "fast_downward": fd_available(),
        "date": _dt.datetime.now().astimezone().isoformat(timespec="seconds"),
    }


def _run_machine(jobs: int, last_run: dict[str, Any]) -> dict[str, Any]:
    """:func:`machine_info` plus how the last run was made."""
    machine = machine_info()
    machine["jobs"] = jobs
    machine["last_run"] = last_run
    return machine


# --------------------------------------------------------------------------- formatting


def _num(x: float) -> str:
    if x >= 100:
        return f"{x:.0f}"
    if x >= 10:
        return f"{x:.1f}"
    return f"{x:.2f}"


def fmt_seconds(r: dict[str, Any] | None) -> str:
    """Seconds as in the paper; ``> limit`` for a time-out, ``err`` for a failed run."""
    if r is None:
        return "—"
    st = r.get("status")
    if st == "ok" and r.get("seconds") is not None:
        return _num(r["seconds"])
    if st == "timeout":
        return f"> {_num(r['time_limit_s'])}"
    return "err"


def fmt_size(r: dict[str, Any] | None, key: str = "E_ropt") -> str:
    if r is None or r.get(key) is None:
        return "—"
    return str(r[key])


def speedup(astar: dict[str, Any] | None, sat: dict[str, Any] | None) -> tuple[float | None, str]:
    """``astar_s / sat_s`` and its kind: ``exact``; ``lower`` when A* timed out (its time is
    the limit, so the true ratio is larger); ``upper`` when only SAT timed out; ``none``."""
    if astar is None or sat is None:
        return None, "none"
    a_ok, s_ok = astar.get("status") == "ok", sat.get("status") == "ok"
    a_to, s_to = astar.get("status") == "timeout", sat.get("status") == "timeout"
    a = astar.get("seconds") if a_ok else (astar.get("time_limit_s") if a_to else None)
    s = sat.get("seconds") if s_ok else (sat.get("time_limit_s") if s_to else None)
    if a is None or s is None or s <= 0:
        return None, "none"
    if a_ok and s_ok:
        return a / s, "exact"
    if a_to and s_ok:
        return a / s, "lower"
    if a_ok and s_to:
        return a / s, "upper"
    return None, "none"


def fmt_speedup(astar: dict[str, Any] | None, sat: dict[str, Any] | None) -> str:
    v, kind = speedup(astar, sat)
    if v is None:
        return "—"
    return {"exact": "", "lower": "> ", "upper": "< "}[kind] + _num(v)


def _index(records: Iterable[dict[str, Any]], suite: str) -> dict[tuple, dict[str, Any]]:
    return {
        (r["domain"], r["problem"], r["delta"], r["engine"]): r
        for r in records
        if r.get("suite") == suite
    }


def _rows(idx: dict[tuple, dict[str, Any]]) -> list[tuple[str, str]]:
    return sorted({(d, p) for d, p, _, _ in idx}, key=lambda x: (x[0], _pkey(x[1])))


def _pkey(p: str) -> tuple:
    digits = "".join(c for c in p if c.isdigit())
    return (int(digits) if digits else 0, p)


def disagreements(records: Iterable[dict[str, Any]]) -> list[dict[str, Any]]:
    """Instances where both engines finished and differ.

    ``astar`` larger |E| (or objective) than ``sat`` is the baseline's known tie weakness (it
    judges a model by one optimal plan); ``astar`` *smaller* than ``sat`` contradicts the SAT
    engine's minimality and is a bug.
    """
    by: dict[tuple, dict[str, dict[str, Any]]] = {}
    for r in records:
        if r.get("suite") in ("paper", "scaling", "smoke", "missing-schemas"):
            by.setdefault(record_key(r)[:4], {})[r["engine"]] = r
    out = []
    for key, pair in sorted(by.items(), key=lambda kv: str(kv[0])):
        a, s = pair.get("astar"), pair.get("sat")
        if not a or not s or a.get("status") != "ok" or s.get("status") != "ok":
            continue
        for col in ("E_ropt", "objective_alpha1", "robot_optimal_cost"):
            av, sv = a.get(col), s.get(col)
            if av is None or sv is None or av == sv:
                continue
            bug = col == "robot_optimal_cost" or av < sv
            out.append(
                {
                    "suite": key[0],
                    "domain": key[1],
                    "problem": key[2],
                    "delta": key[3],
                    "column": col,
                    "astar": av,
                    "sat": sv,
                    "kind": "BUG (sat not minimal or costs differ)"
                    if bug
                    else "astar tie weakness (expected: docs/benchmarks.md)",
                }
            )
    return out


def paper_table(
    records: Sequence[dict[str, Any]], suite: str = "paper", deltas: Sequence[int] = PAPER_DELTAS
) -> str:
    """The paper's Table "times" layout with both engines and the speedup per Delta."""
    idx = _index(records, suite)
    if not idx:
        return f"_no {suite} records_\n"
    head = ["Domain", "Problem"]
    for k in deltas:
        head += [
            f"Δ={k} \\|E\\| astar",
            f"Δ={k} s astar",
            f"Δ={k} \\|E\\| sat",
            f"Δ={k} s sat",
            f"Δ={k} speedup",
        ]
    lines = ["| " + " | ".join(head) + " |", "|" + "---|" * len(head)]
    for dom, prob in _rows(idx):
        cells = [dom, prob]
        for k in deltas:
            a, s = idx.get((dom, prob, k, "astar")), idx.get((dom, prob, k, "sat"))
            ea, es = fmt_size(a), fmt_size(s)
            if (
                a
                and s
                and a.get("E_ropt") is not None
                and s.get("E_ropt") is not None
                and a["E_ropt"] != s["E_ropt"]
            ):
                ea += " †"
            cells += [ea, fmt_seconds(a), es, fmt_seconds(s), fmt_speedup(a, s)]
        lines.append("| " + " | ".join(cells) + " |")
    return "\n".join(lines) + "\n"


def summary(records: Sequence[dict[str, Any]]) -> list[str]:
    """Median speedup over the Delta = 10 grid, max SAT time on the paper grid and at 20."""
    out = []
    paper = _index(records, "paper")
    vals, lower = [], 0
    for (dom, prob, k, eng), r in paper.items():
        if k == 10 and eng == "sat":
            v, kind = speedup(paper.get((dom, prob, k, "astar")), r)
            if v is not None:
                vals.append(v)
                lower += kind == "lower"
    if vals:
        note = (
            f"; {lower} A* time-out(s) counted at the time limit, so a lower bound" if lower else ""
        )
        out.append(
            f"Median speedup (astar s / sat s) over the Δ = 10 grid: "
            f"{_num(statistics.median(vals))} (n = {len(vals)}{note})."
        )
    else:
        out.append("Median speedup over the Δ = 10 grid: n/a (no Δ = 10 pairs).")

    def max_sat(recs: Iterable[dict[str, Any]], what: str) -> str:
        rs = [r for r in recs if r["engine"] == "sat"]
        if not rs:
            return f"Max sat time {what}: n/a (not run)."
        tos = [r for r in rs if r.get("status") != "ok"]
        oks = [r for r in rs if r.get("status") == "ok"]
        m = max((r["seconds"] for r in oks), default=None)
        txt = f"Max sat time {what}: " + (f"{_num(m)} s" if m is not None else "n/a")
        if tos:
            txt += (
                f" ({len(tos)} sat run(s) not ok: "
                + ", ".join(
                    f"{r['domain']}/Δ{r['delta']}/{r['problem']} {r.get('status')}" for r in tos
                )
                + ")"
            )
        return txt + "."

    out.append(max_sat(paper.values(), "on the paper grid"))
    scal = [r for r in _index(records, "scaling").values() if r["delta"] == 20]
    out.append(max_sat(scal, "at Δ = 20"))
    return out


def _frontier_str(r: dict[str, Any] | None) -> str:
    pts = (r or {}).get("frontier") or []
    return " ".join(f"({e}, {c})" for e, c in pts) or "—"


def _fd_call(r: dict[str, Any] | None) -> str:
    v = (r or {}).get("robot_call_fd_s")
    return _num(v) if v is not None else "—"


def missing_schemas_table(records: Sequence[dict[str, Any]]) -> str:
    """One row per missing-schemas instance: sizes, the sat frontier and its time, the FD
    robot-model call and the ratio, and the A* baseline's time."""
    idx = _index(records, "missing-schemas")
    if not idx:
        return "_no missing-schemas records_\n"
    head = [
        "Domain",
        "Problem",
        "\\|Δ\\|",
        "ground actions",
        "robot opt",
        "frontier (\\|E\\|, robot cost)",
        "sat s",
        "exact",
        "FD robot call s",
        "sat / FD call",
        "astar s",
        "astar \\|E\\|",
    ]
    lines = ["| " + " | ".join(head) + " |", "|" + "---|" * len(head)]
    for dom, prob in _rows(idx):
        a, s = idx.get((dom, prob, None, "astar")), idx.get((dom, prob, None, "sat"))
        any_rec = s or a or {}
        ratio = (s or {}).get("ratio_sat_vs_fd_call")
        exact = (
            "—" if s is None else ("yes" if s.get("exact") and s.get("status") == "ok" else "no")
        )
        a_time = "timeout" if a and a.get("status") == "timeout" else fmt_seconds(a)
        lines.append(
            "| "
            + " | ".join(
                [
                    dom,
                    prob,
                    str(any_rec.get("delta_size", "—")),
                    str(any_rec.get("ground_actions", "—")),
                    str(any_rec.get("robot_optimal_cost", "—")),
                    _frontier_str(s),
                    fmt_seconds(s),
                    exact,
                    _fd_call(s),
                    _num(ratio) if ratio is not None else "—",
                    a_time,
                    fmt_size(a),
                ]
            )
            + " |"
        )
    return "\n".join(lines) + "\n"


def missing_schemas_summary(records: Sequence[dict[str, Any]]) -> list[str]:
    """How the missing-schemas suite meets its targets: every frontier exact within
    ``MISSING_SCHEMAS_TARGET_S`` and the median sat / FD-call ratio within
    ``MISSING_SCHEMAS_TARGET_RATIO``."""
    idx = _index(records, "missing-schemas")
    sats = [r for (_, _, _, eng), r in idx.items() if eng == "sat"]
    if not sats:
        return ["No sat runs."]
    ok = [r for r in sats if r.get("status") == "ok" and r.get("exact")]
    fast = [
        r for r in ok if r.get("seconds") is not None and r["seconds"] < MISSING_SCHEMAS_TARGET_S
    ]
    out = [
        f"sat frontiers exact: {len(ok)} of {len(sats)}; exact in under "
        f"{_num(MISSING_SCHEMAS_TARGET_S)} s: {len(fast)} of {len(sats)}."
    ]
    ratios = [r["ratio_sat_vs_fd_call"] for r in sats if r.get("ratio_sat_vs_fd_call") is not None]
    if ratios:
        out.append(
            f"Median sat frontier time / one FD call on the robot model: "
            f"{_num(statistics.median(ratios))} (n = {len(ratios)}; target < "
            f"{_num(MISSING_SCHEMAS_TARGET_RATIO)})."
        )
    else:
        out.append("Median sat / FD robot call: n/a (no FD call timed).")
    astars = [r for (_, _, _, eng), r in idx.items() if eng == "astar"]
    if astars:
        done = sum(1 for r in astars if r.get("status") == "ok")
        out.append(f"astar finished {done} of {len(astars)} within its limit.")
    return out


def scaling_table(records: Sequence[dict[str, Any]]) -> str:
    """Delta = 15/20/30: the table plus, per Delta, how many A* runs hit the limit."""
    idx = _index(records, "scaling")
    if not idx:
        return "_no scaling records_\n"
    text = paper_table(records, "scaling", SCALING_DELTAS)
    lines = [
        "",
        "| Δ | instances | astar ok | astar out of time | sat ok | sat out of time |",
        "|---|---|---|---|---|---|",
    ]
    for k in SCALING_DELTAS:
        rs = [r for (_, _, d, _), r in idx.items() if d == k]
        if not rs:
            continue
        n = len({(r["domain"], r["problem"]) for r in rs})

        def cnt(eng: str, st: str, rs: list[dict[str, Any]] = rs) -> int:
            return sum(1 for r in rs if r["engine"] == eng and r.get("status") == st)

        lines.append(
            f"| {k} | {n} | {cnt('astar', 'ok')} | {cnt('astar', 'timeout')} | "
            f"{cnt('sat', 'ok')} | {cnt('sat', 'timeout')} |"
        )
    first = {}
    for (dom, prob, k, eng), r in sorted(idx.items(), key=lambda kv: kv[0][2]):
        if eng == "astar" and r.get("status") == "timeout":
            first.setdefault((dom, prob), k)
    if first:
        lines += [
            "",
            "A* ran out of its time limit first at: "
            + ", ".join(f"{d}/{p} Δ={k}" for (d, p), k in sorted(first.items()))
            + ".",
        ]
    return text + "\n".join(lines) + "\n"


def render_markdown(
    records: Sequence[dict[str, Any]],
    machine: dict[str, Any],
    sweep_rows: Sequence[dict[str, Any]] = (),
    generation: Sequence[dict[str, Any]] = (),
) -> str:
    """``table.md``: paper table, summary, scaling, disagreements, sweep files, machine."""
    suites = {r.get("suite") for r in records}
    limits = sorted({r.get("time_limit_s") for r in records if r.get("time_limit_s")})
    parts = ["# mega-sat benchmark results", ""]
    parts.append(
        f"Machine: {machine.get('cpu')}, {machine.get('cores')} cores, "
        f"{machine.get('ram_gb')} GB RAM, Python {machine.get('python')}; "
        f"Fast Downward {'available' if machine.get('fast_downward') else 'absent'}; "
        f"{machine.get('date')}."
    )
    parts.append(
        f"Time limit(s) per engine run: {', '.join(_num(x) for x in limits) or 'n/a'}"
        " s.  |E| = the frontier's robot-optimal end (A*: Algorithm 1's stopping node);"
        " s = wall seconds of grounding + engine; speedup = astar s / sat s "
        '("> X": A* timed out, so at least X).  † = the engines\' |E| differ.'
    )
    planners = sorted({str(r.get("planner")) for r in records if r.get("engine") == "astar"})
    if planners:
        ways = {"sat": "SAT", "portfolio": "SAT, then explicit search", "search": "explicit search"}
        joints = sorted(
            {
                ways.get(str(j), str(j))
                for r in records
                if r.get("engine") == "sat" and (j := (r.get("stats") or {}).get("joint"))
            }
        )
        sat_planners = sorted({str(r.get("planner")) for r in records if r.get("engine") == "sat"})
        joint_txt = f"; JOINT by {' / '.join(joints)}" if joints else ""
        if sat_planners in ([], planners):
            parts.append(
                f"Optimal planner on candidate models: {', '.join(planners)} for both engines "
                f"(A*: per node; sat: OPT, after its cheaper proofs{joint_txt})."
            )
        else:  # the missing-schemas suite runs sat in its default configuration
            parts.append(
                f"Optimal planner on candidate models: {', '.join(planners)} per node for A*; "
                f"{', '.join(sat_planners)} for the sat engine's OPT, after its cheaper "
                f"proofs{joint_txt}."
            )
    parts.append("")
    if "paper" in suites:
        parts += [
            '## Paper grid (Table "times" layout, Δ = 2 / 7 / 10)',
            "",
            paper_table(records, "paper"),
        ]
        parts += ["- " + s for s in summary(records)] + [""]
    if "scaling" in suites:
        parts += ["## Scaling (Δ = 15 / 20 / 30)", "", scaling_table(records)]
    if "missing-schemas" in suites:
        parts += [
            "## Missing schemas (hand-written, robot-only schemas)",
            "",
            missing_schemas_table(records),
        ]
        parts += ["- " + s for s in missing_schemas_summary(records)] + [""]
    if "smoke" in suites:
        idx = _index(records, "smoke")
        parts += ["## Smoke", ""]
        for (d, p, _, eng), r in sorted(idx.items()):
            parts.append(
                f"- {d}/{p} {eng} ({r.get('planner')}): {r.get('status')}, "
                f"|E| = {fmt_size(r)}, {fmt_seconds(r)} s"
            )
        parts.append("")
    dis = disagreements(records)
    parts += ["## Engine disagreements", ""]
    if dis:
        parts += [
            f"- {d['suite']} {d['domain']}/Δ{d['delta']}/{d['problem']}: {d['column']} "
            f"astar {d['astar']} vs sat {d['sat']} — {d['kind']}"
            for d in dis
        ]
    else:
        parts.append("None where both engines finished.")
    parts.append("")
    if sweep_rows:
        doms = sorted({r["domain"] for r in sweep_rows})
        parts += [
            "## Alpha sweeps",
            "",
            "`sweep.csv`; plots: " + ", ".join(f"`sweep-{d}.png`" for d in doms),
            "",
        ]
        for (d, p, _, _), r in sorted(_index(records, "sweep").items()):
            pts = " ".join(f"({e}, {c})" for e, c in r.get("frontier", []))
            parts.append(
                f"- {d}/{p}: {r.get('status')}, {fmt_seconds(r)} s, frontier (|E|, robot "
                f"cost): {pts or '—'}, exact {r.get('exact')}"
            )
        parts.append("")
    failed = [g for g in generation if g.get("status") != "ok"]
    if failed:
        parts += ["## Instances not generated", ""]
        parts += [f"- {g['domain']}/Δ{g['delta']}/{g['problem']}: {g.get('error')}" for g in failed]
        parts.append("")
    parts += _errors_section(
        records, lambda r: f"{r['suite']} {r['domain']}/Δ{r['delta']}/{r['problem']} {r['engine']}"
    )
    return "\n".join(parts)


def _errors_section(
    records: Iterable[dict[str, Any]], name: Callable[[dict[str, Any]], str]
) -> list[str]:
    """``## Errors``: one line per record with status ``error`` (none: no section)."""
    errors = [r for r in records if r.get("status") == "error"]
    if not errors:
        return []
    lines = [f"- {name(r)}: {str(r.get('error', ''))[:300]}" for r in errors]
    return ["## Errors", "", *lines, ""]


def write_csv(path: Path, rows: Sequence[dict[str, Any]], fields: Sequence[str]) -> None:
    with path.open("w", newline="") as f:
        w = csv.DictWriter(f, fieldnames=list(fields), extrasaction="ignore")
        w.writeheader()
        for r in rows:
            w.writerow({k: ("" if r.get(k) is None else r.get(k)) for k in fields})


def plot_sweeps(rows: Sequence[dict[str, Any]], out_dir: Path) -> list[Path]:
    """One PNG per domain, one subplot per problem: |E| and explicability cost vs alpha."""
    import matplotlib

    matplotlib.use("Agg")
    import matplotlib.pyplot as plt

    written = []
    for dom in sorted({r["domain"] for r in rows}):
        probs = sorted({r["problem"] for r in rows if r["domain"] == dom}, key=_pkey)
        fig, axes = plt.subplots(1, len(probs), figsize=(4.2 * len(probs), 3.4), squeeze=False)
        for ax, prob in zip(axes[0], probs, strict=True):
            rs = sorted(
                (r for r in rows if r["domain"] == dom and r["problem"] == prob),
                key=lambda r: r["alpha"],
            )
            xs = [r["alpha"] for r in rs]
            ax.plot(xs, [r["E"] for r in rs], "o-", label="explanation cost |E|")
            ax.plot(xs, [r["explicability_cost"] for r in rs], "s--", label="explicability cost")
            # linear up to 0.1: 0, 0.05 and 0.1 get as much room as a factor 3 above it
            # (with linthresh=0.05 the labels "0.05" and "0.1" overlapped)
            ax.set_xscale("symlog", linthresh=0.1, linscale=1.0)
            ticks = [t for t in (0, 0.05, 0.1, 0.3, 1, 3, 10) if t <= max(xs)]
            ax.set_xticks(ticks, [f"{t:g}" for t in ticks])
            ax.yaxis.get_major_locator().set_params(integer=True)
            ax.set_xlabel("alpha")
            ax.set_title(f"{dom} {prob}")
            ax.grid(True, alpha=0.3)
        axes[0][0].set_ylabel("cost")
        axes[0][-1].legend(fontsize=8)
        fig.tight_layout()
        p = out_dir / f"sweep-{dom}.png"
        fig.savefig(p, dpi=120)
        plt.close(fig)
        written.append(p)
    return written


def _output_files(out_dir: Path) -> dict[str, Path]:
    """``results.json``, ``results.csv`` and ``table.md`` in ``out_dir`` (created)."""
    out_dir.mkdir(parents=True, exist_ok=True)
    return {
        "json": out_dir / "results.json",
        "csv": out_dir / "results.csv",
        "md": out_dir / "table.md",
    }


def write_outputs(
    out_dir: Path,
    records: Sequence[dict[str, Any]],
    machine: dict[str, Any],
    sweep_rows: Sequence[dict[str, Any]],
    generation: Sequence[dict[str, Any]] = (),
) -> dict[str, Path]:
    files = _output_files(out_dir)
    data = {
        "machine": machine,
        "records": list(records),
        "sweep": list(sweep_rows),
        "generation": list(generation),
        "disagreements": disagreements(records),
    }
    files["json"].write_text(json.dumps(data, indent=1, default=str))
    write_csv(files["csv"], records, CSV_FIELDS)
    files["md"].write_text(render_markdown(records, machine, sweep_rows, generation))
    if sweep_rows:
        files["sweep_csv"] = out_dir / "sweep.csv"
        write_csv(files["sweep_csv"], sweep_rows, SWEEP_FIELDS)
        for p in plot_sweeps(sweep_rows, out_dir):
            files[p.stem] = p
    return files


# --------------------------------------------------------------------------- the command


def _previous(out_dir: Path, fresh: bool) -> dict[str, Any]:
    """The earlier ``results.json`` in ``out_dir``; {} if ``fresh``, absent or unreadable."""
    pj = out_dir / "results.json"
    if pj.is_file() and not fresh:
        with contextlib.suppress(OSError, json.JSONDecodeError):
            return json.loads(pj.read_text())
    return {}


def plan_jobs(
    root: Path, suite: str, only: Sequence[str], time_limit: float | None, baseline: str
) -> list[Job]:
    suites = ("paper", "scaling", "sweep") if suite == "all" else (suite,)
    jobs: list[Job] = []
    for s in suites:
        limit = time_limit if time_limit is not None else DEFAULT_LIMITS[s]
        for inst in discover(root, s, only):
            if s == "sweep":
                jobs.append(Job(inst, "sat", None, limit, tuple(ALPHA_GRID)))
            elif s == "missing-schemas":
                # the baseline as in the paper grid; the sat engine as a user runs it
                jobs.append(Job(inst, "astar", baseline, limit))
                jobs.append(Job(inst, "sat", None, limit))
            else:
                # same kind of optimal planner on candidate models for both engines: the
                # baseline's per-node planner is the sat engine's OPT planner (JOINT is SAT)
                jobs.append(Job(inst, "astar", baseline, limit))
                jobs.append(Job(inst, "sat", baseline, limit))
    return jobs


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
        ks = []
        if suite in ("paper", "all"):
            ks += list(PAPER_DELTAS)
        if suite in ("scaling", "all"):
            ks += list(SCALING_DELTAS)
        gen_log = generate_missing(root, ks, seed, only)
    todo = plan_jobs(root, suite, only, time_limit, baseline)
    if not todo:  # refused before any file is written: empty tables would look like results
        raise click.UsageError(
            f"nothing to run: suite '{suite}' has no instance in {root}"
            + (f" matching --only {' --only '.join(only)}" if only else "")
        )
    robot_planners = ["builtin", "sat"] + (["fd"] if fd else [])

    prev = _previous(out_dir, fresh)
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
    machine = _run_machine(
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
            _pkey(r.get("problem", "")),
            r.get("delta") if r.get("delta") is not None else -1,
            r.get("engine"),
        ),
    )
    sweep_rows.sort(key=lambda r: (r["domain"], _pkey(r["problem"]), r["alpha"]))
    return write_outputs(out_dir, ordered, machine, sweep_rows, list(generation.values()))


# options of both benchmark commands (``bench`` here, ``bench-calls`` in mega_sat.bench.oracle_calls)
_domains_option = click.option(
    "--domains", "domains_dir", type=click.Path(), default="domains", show_default=True
)
_fresh_option = click.option("--fresh", is_flag=True, help="Discard earlier records in --out.")


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
@_domains_option
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
@_fresh_option
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
    _echo_files(files, t0)


def _echo_files(files: dict[str, Path], t0: float) -> None:
    """The written files, then the wall time since ``t0``."""
    for name, p in files.items():
        click.echo(f"{name}: {p}")
    click.echo(f"wall time {time.perf_counter() - t0:.1f}s")


def _dispatch(
    argv: list[str] | None, worker: click.Command, command: click.Command, prog: str
) -> None:
    """``python -m <prog> _run ...`` runs the hidden worker, anything else the command."""
    argv = sys.argv[1:] if argv is None else argv
    if argv[:1] == ["_run"]:
        worker.main(argv[1:], prog_name=f"{prog} _run")
    else:
        command.main(argv, prog_name=prog)


def _main(argv: list[str] | None = None) -> None:
    _dispatch(argv, run_command, bench_command, "mega_sat.bench.harness")


if __name__ == "__main__":
    _main()

__all__ = [
    "ALPHA_GRID",
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
    "render_markdown",
    "run_bench",
    "scaling_table",
    "speedup",
    "summary",
    "write_outputs",
]
