"""Per-call times of the SAT oracles OPT and JOINT on the shipped domains (issue #3).

The engine's totals (``mega-sat bench``) do not show whether a run is slow because of one slow
oracle call or many fast ones.  Issue #3 asks for every single OPT or JOINT call on a shipped
problem to take under 0.5 s, with the encoding built once per task.  This harness builds one
:class:`mega_sat.sat.oracles.SatOracles` per task, records every OPT and JOINT call the ``sat``
engine makes with SAT oracles only (``planner="sat"``, ``joint="sat"``), and also times direct
SAT OPT calls (robot model, human model, each single update), because the engine answers most
OPT questions with cheaper proofs (:mod:`mega_sat.planners.tiered_opt`) that never reach the SAT oracle.

Each instance runs in its own subprocess (``python -m mega_sat.bench.oracle_calls _run ...``) so the
per-instance limit really stops it; calls are streamed to a file so a killed run keeps the calls
it made.  Outputs (``--out``): ``results.json``, ``results.csv`` (one row per call), ``table.md``.
"""

from __future__ import annotations

import contextlib
import json
import time
from collections.abc import Callable, Iterator, Sequence
from concurrent.futures import ThreadPoolExecutor, as_completed
from pathlib import Path
from typing import Any

import click

from mega_sat.bench.call_tables import (
    SIZE_KEYS,
    WORK_KEYS,
    call_key,
    merge_repeats,
    over_target,
    render_table,
    summary,
    write_outputs,
)
from mega_sat.bench.common import dispatch as _dispatch
from mega_sat.bench.common import domains_option as _domains_option
from mega_sat.bench.common import echo_files as _echo_files
from mega_sat.bench.common import failure_record as _failure
from mega_sat.bench.common import fresh_option as _fresh_option
from mega_sat.bench.common import peak_rss_mb as _rss_mb
from mega_sat.bench.common import previous_results as _previous
from mega_sat.bench.common import problem_key as _pkey
from mega_sat.bench.common import run_machine_info as _run_machine
from mega_sat.bench.common import run_worker as _run_worker
from mega_sat.bench.common import write_json as _write_json
from mega_sat.bench.suites import discover

DEFAULT_TARGET = 0.5
DEFAULT_CALL_LIMIT = 60.0
DEFAULT_TIME_LIMIT = 600.0
# a call's ``status``: OPT's and JOINT's own answers (mega_sat.status), the call limit, or an
# exception
CALL_STATUSES = ("optimal", "unsolvable", "limit", "plan", "infeasible", "timeout", "error")
# opt_vars, opt_clauses, opt_horizon, joint_vars, ...


# --------------------------------------------------------------------------- worker (child)


def _sizes(orc) -> dict[str, int | None]:
    """Encoding sizes now (the oracle stats are refreshed after every oracle call)."""
    stats = orc.stats
    return {k: getattr(stats, k) for k in SIZE_KEYS}


@contextlib.contextmanager
def count_encodings() -> Iterator[list[int]]:
    """Count :class:`FamilyEncoding` constructions inside the block (``counter[0]``), to check
    that the encoding is built once per task and never per call."""
    from mega_sat.sat.encoding import FamilyEncoding

    before = FamilyEncoding.built
    counter = [0]
    try:
        yield counter
    finally:
        counter[0] = FamilyEncoding.built - before


"""Seconds of one call: inside SAT solver calls; growing the encodings (new steps with their
invariants, goal and cost clauses); explicit searches; the operator-counting integer programs
(the fields of :class:`mega_sat.sat.observer.OracleCall` of the same names)."""


class CallRecorder:
    """An observer of one oracle object (``SatOracles(..., observer=recorder)``): every call
    gets a deadline (``call_limit`` seconds, never past ``deadline``) and is recorded by
    ``sink``."""

    def __init__(
        self,
        group: str,
        call_limit: float,
        deadline: float | None,
        sink: Callable[[dict[str, Any]], None],
    ):
        self.group = group
        self.call_limit = call_limit
        self.deadline = deadline
        self.sink = sink
        self.timed_out = False
        self.seq = 0
        self.orc = None  # the oracles observed, for their encoding sizes

    def begin(self, call):
        from mega_sat.deadline import Deadline

        limit = time.perf_counter() + self.call_limit
        at = limit if self.deadline is None else min(limit, self.deadline)
        return Deadline(at, self.call_limit)

    def end(self, call) -> None:
        from mega_sat.sat.oracles import OracleInterrupted

        self.seq += 1
        kind = call.kind
        rec: dict[str, Any] = {"group": self.group, "seq": self.seq, "kind": kind}
        if kind == "opt":
            rec["selection"] = sorted(call.selection)
        else:
            rec.update(robot_bound=call.robot_bound, human_bound=call.human_bound)
            if call.selection is not None:
                rec["selection"] = sorted(call.selection)
            else:  # a partial assignment: keep the literals themselves
                rec["lits"] = [[int(i), bool(v)] for i, v in call.lits]
        res = call.result
        if res is None:
            timeout = isinstance(call.error, OracleInterrupted)
            if timeout:
                self.timed_out = True
                late = self.deadline is not None and time.perf_counter() >= self.deadline
                failure = "instance time limit" if late else f"call limit {self.call_limit}s"
            else:
                failure = f"error: {type(call.error).__name__}: {call.error}"
            rec.update(status="timeout" if timeout else "error", reason=failure)
        else:
            rec.update(
                status=str(res.status),
                cost=res.cost if kind == "opt" else res.robot_cost,
                human_cost=None if kind == "opt" else res.human_cost,
                horizon=call.max_horizon_asked if kind == "opt" else res.horizon,
                sat_calls=res.calls,
                exact=res.exact,
                reason=res.reason,
            )
        rec["max_horizon_asked"] = call.max_horizon_asked
        rec["conflicts"] = call.conflicts
        rec["seconds"] = round(call.seconds, 6)
        for key in WORK_KEYS:
            rec[key] = round(getattr(call, key), 6)
        # a cached OPT answer comes back without a new oracle computation
        rec["cached"] = kind == "opt" and res is not None and call.cached
        if self.orc is not None:
            rec.update(_sizes(self.orc))
        self.sink(rec)


def direct_selections(n_updates: int, robot: frozenset[int]) -> list[frozenset[int]]:
    """Robot model, human model, then each single update; duplicates dropped (|Delta| = 1)."""
    sels = [robot, frozenset(), *(frozenset({i}) for i in range(n_updates))]
    return list(dict.fromkeys(sels))


def measure(
    task_dir: str,
    call_limit: float = DEFAULT_CALL_LIMIT,
    time_limit: float = DEFAULT_TIME_LIMIT,
    *,
    calls_path: str | None = None,
    info_path: str | None = None,
) -> dict[str, Any]:
    """All measurements of one task (inside the worker process).  Calls are appended to
    ``calls_path`` (JSON lines) as they finish; ``info_path`` gets the record so far after
    set-up, so a killed worker still leaves its instance facts and calls behind."""
    from mega_sat.deadline import TimeLimitReached
    from mega_sat.engines.sat_loop import sat_frontier
    from mega_sat.ground.grounding import ground
    from mega_sat.pddl.loading import load_task, resolve_task_dir
    from mega_sat.sat.oracles import OracleInterrupted, SatOracles

    t_start = time.perf_counter()
    deadline = t_start + time_limit
    calls: list[dict[str, Any]] = []
    fh = open(calls_path, "a") if calls_path else None  # noqa: SIM115 - closed below

    def sink(c: dict[str, Any]) -> None:
        calls.append(c)
        if fh is not None:
            fh.write(json.dumps(c) + "\n")
            fh.flush()

    try:
        rec: dict[str, Any] = {"call_limit_s": call_limit, "time_limit_s": time_limit}
        t0 = time.perf_counter()
        task = load_task(**resolve_task_dir(task_dir))
        rec["load_s"] = round(time.perf_counter() - t0, 4)
        t0 = time.perf_counter()
        family = ground(task)
        rec["ground_s"] = round(time.perf_counter() - t0, 4)
        rec.update(
            atoms=len(family.atoms), ground_actions=len(family.actions), delta=family.n_updates
        )

        # 1. one oracle object for the whole task; its construction is the encoding build
        loop = CallRecorder("loop", call_limit, deadline, sink)
        with count_encodings() as built:
            t0 = time.perf_counter()
            orc = loop.orc = SatOracles(family, observer=loop)
            rec["build_s"] = round(time.perf_counter() - t0, 6)
        rec["encodings_at_build"] = built[0]
        rec["encoding_initial"] = _sizes(orc)
        if info_path:
            _write_json(info_path, rec)

        # 2. every OPT / JOINT call of the engine, SAT oracles only
        t0 = time.perf_counter()
        with count_encodings() as during:
            try:
                fr = sat_frontier(
                    task,
                    family,
                    oracles=orc,
                    planner="sat",
                    joint="sat",
                    timeout=max(deadline - time.perf_counter(), 0.001),
                )
                rec.update(
                    loop_status="complete" if fr.complete else "timeout",
                    frontier=[[p.size, p.robot_cost] for p in fr.points],
                    exact=fr.exact,
                    notes=list(fr.notes),
                    loop_stats={
                        k: v for k, v in fr.stats.items() if isinstance(v, int | float | str)
                    },
                )
            except (Exception, TimeLimitReached) as e:  # noqa: BLE001 - robot OPT cut by the limit
                timed_out = loop.timed_out or time.perf_counter() >= deadline
                rec["loop_status"] = "timeout" if timed_out else "error"
                rec["loop_error"] = f"{type(e).__name__}: {e}"
        if loop.timed_out:
            rec["loop_stop"] = "a call was stopped by the time limit (see its reason)"
        rec["loop_s"] = round(time.perf_counter() - t0, 4)
        rec["encodings_built_in_loop"] = during[0]
        rec["encoding_final_loop"] = _sizes(orc)
        orc.close()

        # 3. direct SAT OPT calls on a fresh oracle object (no answers cached by the loop)
        direct = CallRecorder("direct", call_limit, deadline, sink)
        t0 = time.perf_counter()
        orc2 = direct.orc = SatOracles(family, observer=direct)
        rec["direct_build_s"] = round(time.perf_counter() - t0, 6)
        skipped = []
        for sel in direct_selections(family.n_updates, family.robot_selection):
            if time.perf_counter() >= deadline:
                skipped.append(sorted(sel))
                continue
            with contextlib.suppress(OracleInterrupted):  # recorded as a timeout
                orc2.opt(sel)  # recorded by the observer
        rec["direct_skipped"] = skipped
        rec["encoding_final_direct"] = _sizes(orc2)
        orc2.close()

        timeouts = any(c["status"] == "timeout" for c in calls)
        if rec["loop_status"] == "error":
            rec["status"] = "error"
            rec["error"] = rec["loop_error"]
        elif timeouts or skipped or rec["loop_status"] != "complete":
            rec["status"] = "timeout"
        else:
            rec["status"] = "ok"
    finally:
        if fh is not None:
            fh.close()
    rec["calls"] = calls
    rec["worker_s"] = round(time.perf_counter() - t_start, 4)
    return rec


@click.command("_run", hidden=True)
@click.option("--task", "task_dir", required=True)
@click.option("--call-limit", type=float, required=True)
@click.option("--time-limit", type=float, required=True)
@click.option("--out", "out", required=True, help="Result JSON file.")
def run_command(task_dir: str, call_limit: float, time_limit: float, out: str) -> None:
    """Worker: one instance; record to ``--out``, calls streamed to ``--out``.calls.jsonl."""
    try:
        rec = measure(
            task_dir, call_limit, time_limit, calls_path=out + ".calls.jsonl", info_path=out
        )
    except Exception as e:  # noqa: BLE001 - the parent records the failure
        rec = json.loads(Path(out).read_text()) if Path(out).is_file() else {}
        rec.update(_failure(e))
    rec["peak_rss_mb"] = _rss_mb()[0]
    _write_json(out, rec)


# --------------------------------------------------------------------------- parent side


def hard_limit(time_limit: float) -> float:
    """The worker stops its own SAT calls at the instance limit; anything else (explicit
    searches) gets a grace period, then the process group is killed."""
    return time_limit + max(5.0, 0.1 * time_limit)


def _streamed_calls(out: str, rec: dict[str, Any]) -> None:
    """A worker killed (or crashed) before the end: the calls it streamed to the side file."""
    if "calls" not in rec:
        lines = Path(out + ".calls.jsonl")
        text = lines.read_text() if lines.is_file() else ""
        rec["calls"] = [json.loads(x) for x in text.splitlines() if x.strip()]


def run_instance(
    task_dir: str, call_limit: float, time_limit: float, domain: str, problem: str
) -> dict[str, Any]:
    """One instance in its own process; killed (and recorded as a time-out) on overrun."""
    args = ["--task", task_dir, "--call-limit", repr(call_limit), "--time-limit", repr(time_limit)]
    limit = hard_limit(time_limit)
    w = _run_worker(
        "mega_sat.bench.oracle_calls", args, limit, prefix="mega-calls-", collect=_streamed_calls
    )
    rec = w.rec
    if w.killed:
        rec.update(status="timeout", killed=True, error=f"killed at {limit:.0f}s")
    elif "status" not in rec:
        rec.update(status="error", error=w.exit_error)
    rec["process_s"] = round(w.seconds, 3)
    rec.update(domain=domain, problem=problem, task_dir=task_dir)
    rec.setdefault("call_limit_s", call_limit)
    rec.setdefault("time_limit_s", time_limit)
    return rec


def run_calls_bench(
    root: Path,
    out_dir: Path,
    *,
    only: Sequence[str] = (),
    call_limit: float = DEFAULT_CALL_LIMIT,
    time_limit: float = DEFAULT_TIME_LIMIT,
    target: float = DEFAULT_TARGET,
    jobs: int = 1,
    repeat: int = 1,
    fresh: bool = False,
    echo: Callable[[str], None] | None = None,
) -> dict[str, Path]:
    """Measure every base problem ``root/<domain>/pN`` matching ``only``; write the outputs.
    Each instance runs ``repeat`` times (its calls timed by the median, :func:`merge_repeats`).
    Records already in ``out_dir`` for other instances are kept unless ``fresh``."""
    if repeat < 1:
        raise click.UsageError("--repeat must be >= 1")
    if not root.is_dir():
        raise click.UsageError(f"domains folder not found: {root}")
    insts = discover(root, "sweep", only)  # the base problems, same --only rules as bench
    if not insts:
        raise click.UsageError("no instance matches --only")
    prev = _previous(out_dir, fresh)
    records = {(r.get("domain"), r.get("problem")): r for r in prev.get("records", [])}
    t0 = time.perf_counter()
    with ThreadPoolExecutor(max_workers=max(1, jobs)) as ex:
        futs = {
            ex.submit(_repeated, repeat, i.task_dir, call_limit, time_limit, i.domain, i.problem): i
            for i in insts
        }
        for n, fut in enumerate(as_completed(futs), 1):
            i = futs[fut]
            rec = fut.result()
            records[(i.domain, i.problem)] = rec
            if echo is not None:
                work = [c for c in rec.get("calls", []) if not c.get("cached")]
                mx = max((float(c.get("seconds") or 0) for c in work), default=0.0)
                echo(
                    f"[{n}/{len(insts)}] {i.domain}/{i.problem}: {rec.get('status')}, "
                    f"{len(work)} calls, slowest {mx:.3f}s"
                )
    machine = _run_machine(
        jobs,
        {
            "instances": len(insts),
            "wall_s": round(time.perf_counter() - t0, 1),
            "call_limit_s": call_limit,
            "time_limit_s": time_limit,
            "repeat": repeat,
        },
    )
    ordered = sorted(records.values(), key=lambda r: (r.get("domain"), _pkey(r.get("problem"))))
    return write_outputs(out_dir, ordered, machine, target)


def _repeated(repeat: int, *args) -> dict[str, Any]:
    return merge_repeats([run_instance(*args) for _ in range(repeat)])


@click.command("bench-calls")
@_domains_option
@click.option(
    "--only",
    multiple=True,
    help="Keep domains or domain/problem matching this pattern (repeatable).",
)
@click.option(
    "--call-limit",
    type=float,
    default=DEFAULT_CALL_LIMIT,
    show_default=True,
    help="Seconds per oracle call; a loop call that reaches it ends that instance's loop.",
)
@click.option(
    "--time-limit",
    type=float,
    default=DEFAULT_TIME_LIMIT,
    show_default=True,
    help="Seconds per instance (its own process, killed on overrun).",
)
@click.option(
    "--target",
    type=float,
    default=DEFAULT_TARGET,
    show_default=True,
    help="Seconds every call should stay under.",
)
@click.option(
    "--out", "out_dir", type=click.Path(), default="bench/results/calls", show_default=True
)
@click.option(
    "--jobs",
    type=int,
    default=1,
    show_default=True,
    help="Instances in parallel (>1 skews timings).",
)
@click.option(
    "--repeat",
    type=int,
    default=1,
    show_default=True,
    help="Runs per instance; each call is timed by the median over the runs.",
)
@_fresh_option
def bench_calls_command(
    domains_dir: str,
    only: tuple[str, ...],
    call_limit: float,
    time_limit: float,
    target: float,
    out_dir: str,
    jobs: int,
    repeat: int,
    fresh: bool,
) -> None:
    """Time every SAT OPT and JOINT call on the base problems (encoding size, seconds)."""
    for name, v in (("--call-limit", call_limit), ("--time-limit", time_limit)):
        if not v > 0:
            raise click.UsageError(f"{name} must be > 0")
    if not target > 0:
        raise click.UsageError("--target must be > 0")
    t0 = time.perf_counter()
    files = run_calls_bench(
        Path(domains_dir),
        Path(out_dir),
        only=only,
        call_limit=call_limit,
        time_limit=time_limit,
        target=target,
        jobs=jobs,
        repeat=repeat,
        fresh=fresh,
        echo=lambda s: click.echo(s, err=True),
    )
    _echo_files(files, t0)


def _main(argv: list[str] | None = None) -> None:
    _dispatch(argv, run_command, bench_calls_command, "mega_sat.bench.oracle_calls")


if __name__ == "__main__":
    _main()

__all__ = [
    "CALL_STATUSES",
    "WORK_KEYS",
    "CallRecorder",
    "bench_calls_command",
    "call_key",
    "count_encodings",
    "direct_selections",
    "measure",
    "merge_repeats",
    "over_target",
    "render_table",
    "run_calls_bench",
    "run_instance",
    "summary",
    "write_outputs",
]
