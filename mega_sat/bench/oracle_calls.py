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
import statistics
import time
from collections.abc import Callable, Iterator, Sequence
from concurrent.futures import ThreadPoolExecutor, as_completed
from pathlib import Path
from typing import Any

import click

from mega_sat.bench.common import dispatch as _dispatch
from mega_sat.bench.common import domains_option as _domains_option
from mega_sat.bench.common import echo_files as _echo_files
from mega_sat.bench.common import errors_section as _errors_section
from mega_sat.bench.common import failure_record as _failure
from mega_sat.bench.common import fresh_option as _fresh_option
from mega_sat.bench.common import output_files as _output_files
from mega_sat.bench.common import peak_rss_mb as _rss_mb
from mega_sat.bench.common import previous_results as _previous
from mega_sat.bench.common import problem_key as _pkey
from mega_sat.bench.common import run_machine_info as _run_machine
from mega_sat.bench.common import run_worker as _run_worker
from mega_sat.bench.common import write_csv
from mega_sat.bench.common import write_json as _write_json
from mega_sat.bench.suites import discover

DEFAULT_TARGET = 0.5
DEFAULT_CALL_LIMIT = 60.0
DEFAULT_TIME_LIMIT = 600.0
# a call's ``status``: OPT's and JOINT's own answers (mega_sat.status), the call limit, or an
# exception
CALL_STATUSES = ("optimal", "unsolvable", "limit", "plan", "infeasible", "timeout", "error")
# opt_vars, opt_clauses, opt_horizon, joint_vars, ...
SIZE_KEYS = tuple(f"{e}_{x}" for e in ("opt", "joint") for x in ("vars", "clauses", "horizon"))

CALL_FIELDS = (
    "domain",
    "problem",
    "group",
    "seq",
    "kind",
    "selection",
    "lits",
    "robot_bound",
    "human_bound",
    "status",
    "cost",
    "human_cost",
    "horizon",
    "max_horizon_asked",
    "sat_calls",
    "conflicts",
    "seconds",
    "solve_s",
    "grow_s",
    "search_s",
    "counting_s",
    "seconds_runs",
    "cached",
    "exact",
    "reason",
    *SIZE_KEYS,
)


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


WORK_KEYS = ("solve_s", "grow_s", "search_s", "counting_s")
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


def call_key(c: dict[str, Any]) -> tuple:
    """What a call asked (group, kind, model or literals, bounds): the same question in two
    runs of one instance, whatever its position in the run."""
    lits = c.get("lits")
    return (
        c.get("group"),
        c.get("kind"),
        tuple(c["selection"]) if c.get("selection") is not None else None,
        tuple(map(tuple, lits)) if lits is not None else None,
        c.get("robot_bound"),
        c.get("human_bound"),
    )


def merge_repeats(runs: Sequence[dict[str, Any]]) -> dict[str, Any]:
    """One record from several runs of one instance: the first run's record, each of its calls
    timed by the median over the runs that asked the same question (``seconds_runs`` lists
    them).  The runs need not ask the same questions in the same order (the engine picks
    between ways of settling a trial by their measured speed), so calls are matched by
    :func:`call_key` and occurrence; calls of later runs with no match in the first are
    counted in ``repeat_unmatched``."""
    base = dict(runs[0])
    if len(runs) == 1:
        return base

    def indexed(calls):
        seen: dict[tuple, int] = {}
        out = {}
        for c in calls:
            k = call_key(c)
            seen[k] = seen.get(k, 0) + 1
            out[(k, seen[k])] = c
        return out

    others = [indexed(r.get("calls", [])) for r in runs[1:]]
    merged = []
    matched: set[tuple] = set()
    for key, c in indexed(base.get("calls", [])).items():
        same = [c] + [o[key] for o in others if key in o]
        if len(same) > 1:
            matched.add(key)
        secs = [float(x.get("seconds") or 0.0) for x in same]
        m = {**c, "seconds": round(statistics.median(secs), 6), "seconds_runs": secs}
        for k in WORK_KEYS:  # the parts too, each by its own median
            if all(x.get(k) is not None for x in same):
                m[k] = round(statistics.median(float(x[k]) for x in same), 6)
        merged.append(m)
    base["calls"] = merged
    base["repeats"] = len(runs)
    base["repeat_statuses"] = [r.get("status") for r in runs]
    # an instance that did not finish in some run did not finish
    worst = next((r for r in runs if r.get("status") != "ok"), None)
    if worst is not None:
        for k in ("status", "error", "killed"):
            if k in worst:
                base[k] = worst[k]
    base["repeat_unmatched"] = sum(1 for o in others for k in o if k not in matched)
    return base


# --------------------------------------------------------------------------- statistics


def timed(calls: Sequence[dict[str, Any]], kind: str, group: str | None = None) -> list[dict]:
    """Calls that did work (cached OPT answers excluded) of one kind (and group)."""
    return [
        c
        for c in calls
        if c.get("kind") == kind
        and not c.get("cached")
        and (group is None or c.get("group") == group)
    ]


def over_target(c: dict[str, Any], target: float) -> bool:
    """A call that missed the target: at least ``target`` seconds, or stopped by a limit."""
    if c.get("cached"):
        return False
    return c.get("status") == "timeout" or float(c.get("seconds") or 0.0) >= target


def all_calls(records: Sequence[dict[str, Any]]) -> list[tuple[dict, dict]]:
    return [(r, c) for r in records for c in r.get("calls", [])]


def final_sizes(rec: dict[str, Any], kind: str) -> tuple[Any, Any, Any]:
    """Largest ``kind`` encoding reached (vars, clauses, horizon).  Encodings only grow, so this
    is the final size of the larger oracle object (the loop's, or the direct-OPT one)."""
    cands = [rec.get(k) or {} for k in ("encoding_initial", "encoding_final_loop")]
    cands.append(rec.get("encoding_final_direct") or {})
    cands += rec.get("calls", [])
    best: tuple[Any, Any, Any] = (None, None, None)
    for c in cands:
        v = c.get(f"{kind}_vars")
        if v is not None and (best[0] is None or v > best[0]):
            best = (v, c.get(f"{kind}_clauses"), c.get(f"{kind}_horizon"))
    return best


def _fmt_s(x: float | None) -> str:
    """Seconds with 3 significant digits (no exponents)."""
    if x is None:
        return "—"
    if x >= 100:
        return f"{x:.0f}"
    if x >= 10:
        return f"{x:.1f}"
    if x >= 1e-4:
        return f"{x:.3g}"
    return "0" if x == 0 else "< 0.0001"


def _stats(calls: Sequence[dict[str, Any]]) -> tuple[str, str, str]:
    secs = [float(c.get("seconds") or 0.0) for c in calls]
    if not secs:
        return "0", "—", "—"
    mx = _fmt_s(max(secs))
    if any(c.get("status") == "timeout" for c in calls):
        mx = f"≥ {mx} (timeout)"
    return str(len(secs)), _fmt_s(statistics.median(secs)), mx


TIERS = ("relaxed", "pairs", "cached", "quick_search")


def tiered_count(r: dict[str, Any]) -> str:
    """Loop OPT answers proven before the SAT oracle (:mod:`mega_sat.planners.tiered_opt`)."""
    st = r.get("loop_stats") or {}
    got = [st[f"opt_by_{t}"] for t in TIERS if f"opt_by_{t}" in st]
    return str(sum(got)) if got else "—"


def _size_cell(s: tuple[Any, Any, Any]) -> str:
    return " / ".join("—" if v is None else str(v) for v in s)


def _bounds(c: dict[str, Any]) -> str:
    if c.get("kind") != "joint":
        return "—"
    rb = c.get("robot_bound")
    return f"K={'∞' if rb is None else rb}, c={c.get('human_bound')}"


def _selection(c: dict[str, Any]) -> str:
    if c.get("selection") is not None:
        return "{" + ",".join(str(i) for i in c["selection"]) + "}"
    if c.get("lits") is not None:
        return " ".join(f"{'' if v else '¬'}e{i}" for i, v in c["lits"])
    return "—"


def _instance_status(r: dict[str, Any]) -> str:
    st = str(r.get("status"))
    if r.get("killed"):
        return "timeout (killed)"
    if st == "timeout":
        if any(c.get("status") == "timeout" for c in r.get("calls", [])):
            return "timeout (call)"
        return "timeout (instance)"
    return st


TABLE_HEADER = (
    "domain",
    "problem",
    "status",
    "atoms",
    "ground actions",
    "\\|Δ\\|",
    "build s",
    "loop OPT by cheaper proofs",
    "OPT vars / clauses / h",
    "JOINT vars / clauses / h",
    "loop OPT n",
    "loop OPT med s",
    "loop OPT max s",
    "direct OPT n",
    "direct OPT med s",
    "direct OPT max s",
    "JOINT n",
    "JOINT med s",
    "JOINT max s",
    "calls ≥ {target} s",
)


def instance_row(r: dict[str, Any], target: float) -> list[str]:
    calls = r.get("calls", [])
    n_cached = sum(1 for c in calls if c.get("kind") == "opt" and c.get("cached"))
    lo = _stats(timed(calls, "opt", "loop"))
    di = _stats(timed(calls, "opt", "direct"))
    jo = _stats(timed(calls, "joint"))
    lo_n = lo[0] + (f" (+{n_cached} cached)" if n_cached else "")

    def cell(k: str) -> str:
        v = r.get(k)
        return "—" if v is None else str(v)

    return [
        str(r.get("domain")),
        str(r.get("problem")),
        _instance_status(r),
        cell("atoms"),
        cell("ground_actions"),
        cell("delta"),
        _fmt_s(r.get("build_s")),
        tiered_count(r),
        _size_cell(final_sizes(r, "opt")),
        _size_cell(final_sizes(r, "joint")),
        lo_n,
        lo[1],
        lo[2],
        *di,
        *jo,
        str(sum(1 for c in calls if over_target(c, target))),
    ]


def summary(records: Sequence[dict[str, Any]], target: float) -> dict[str, Any]:
    """Everything the summary says, computed from the records."""
    pairs = all_calls(records)
    work = [(r, c) for r, c in pairs if not c.get("cached")]
    calls = [c for _, c in pairs]
    over = [(r, c) for r, c in work if over_target(c, target)]
    unfinished = [r for r in records if r.get("status") != "ok"]
    if over:
        verdict = "missed"
    elif unfinished:
        verdict = "not established"
    else:
        verdict = "met"
    reencoded = [r for r in records if (r.get("encodings_built_in_loop") or 0) > 0]
    unknown_enc = [r for r in records if r.get("encodings_built_in_loop") is None]
    slowest = sorted(work, key=lambda rc: -float(rc[1].get("seconds") or 0.0))[:10]
    return {
        "instances": len(records),
        "instances_by_status": {
            s: sum(1 for r in records if r.get("status") == s)
            for s in sorted({str(r.get("status")) for r in records})
        },
        "calls": len(work),
        "calls_loop_opt": len(timed(calls, "opt", "loop")),
        "calls_direct_opt": len(timed(calls, "opt", "direct")),
        "calls_joint": len(timed(calls, "joint")),
        "cached_opt": len(pairs) - len(work),
        "over_target": len(over),
        "timeouts": sum(1 for _, c in work if c.get("status") == "timeout"),
        "target": target,
        "verdict": verdict,
        "unfinished": [f"{r.get('domain')}/{r.get('problem')}" for r in unfinished],
        "reencoded": [f"{r.get('domain')}/{r.get('problem')}" for r in reencoded],
        "encoding_count_unknown": len(unknown_enc),
        "slowest": slowest,
    }


def _or_dash(v: Any) -> str:
    return "—" if v is None else str(v)


def _repeat_phrase(records: Sequence[dict[str, Any]]) -> str:
    ns = sorted({int(r.get("repeats") or 1) for r in records})
    if ns == [1] or not ns:
        return ""
    if len(ns) == 1:
        return f", the median over {ns[0]} runs of each instance"
    return ", the median over the runs of each instance (`repeats` in results.json)"


def render_table(records: Sequence[dict[str, Any]], machine: dict[str, Any], target: float) -> str:
    """``table.md``: one row per instance, then the summary and the slowest calls."""
    limits = sorted({r.get("call_limit_s") for r in records if r.get("call_limit_s")})
    ilimits = sorted({r.get("time_limit_s") for r in records if r.get("time_limit_s")})
    parts = ["# mega-sat per-call oracle times (issue #3)", ""]
    parts.append(
        f"Machine: {machine.get('cpu')}, {machine.get('cores')} cores, "
        f"{machine.get('ram_gb')} GB RAM, Python {machine.get('python')}; {machine.get('date')}."
    )
    parts.append(
        "One SatOracles per task (built once: `build s`); every OPT / JOINT call the `sat` "
        "engine makes with SAT oracles only (`loop`), plus direct SAT OPT calls on a fresh "
        "oracle object (robot model, human model, each single update: `direct`).  The engine "
        "proves most OPT answers before the SAT oracle (`loop OPT by cheaper proofs`, "
        "mega_sat/planners/tiered_opt.py); `loop OPT n` counts only those that reached it.  Seconds are "
        f"wall seconds per call{_repeat_phrase(records)}; cached OPT answers are excluded; "
        "`conflicts` are the SAT conflicts a call spent (they do not depend on the machine); "
        "of its seconds, `solve s` were spent inside the SAT solver, `grow s` growing the "
        "encodings (new steps, invariants, goal and cost clauses) and `search s` in OPT's "
        "lowered-cost search.  "
        "Sizes are the largest "
        "encodings reached (variables / clauses / horizon).  Per-call limit: "
        f"{', '.join(_fmt_s(x) for x in limits) or 'n/a'} s; per-instance limit: "
        f"{', '.join(_fmt_s(x) for x in ilimits) or 'n/a'} s."
    )
    parts.append("")
    head = [h.format(target=_fmt_s(target)) for h in TABLE_HEADER]
    parts.append("| " + " | ".join(head) + " |")
    parts.append("|" + "|".join("---" for _ in head) + "|")
    for r in records:
        parts.append("| " + " | ".join(instance_row(r, target)) + " |")
    parts.append("")

    s = summary(records, target)
    by = ", ".join(f"{k} {v}" for k, v in s["instances_by_status"].items())
    parts += ["## Summary", ""]
    parts.append(f"- instances: {s['instances']} ({by or 'none'})")
    parts.append(
        f"- calls timed: {s['calls']} (loop OPT {s['calls_loop_opt']}, direct OPT "
        f"{s['calls_direct_opt']}, JOINT {s['calls_joint']}); cached OPT answers excluded: "
        f"{s['cached_opt']}"
    )
    parts.append(
        f"- calls ≥ {_fmt_s(target)} s: {s['over_target']} (of them stopped at the per-call "
        f"limit: {s['timeouts']})"
    )
    why = ""
    if s["verdict"] == "not established":
        why = f" (no call ≥ {_fmt_s(target)} s, but unfinished: {', '.join(s['unfinished'])})"
    parts.append(f"- target (every call < {_fmt_s(target)} s): {s['verdict']}{why}")
    if s["reencoded"]:
        enc = f"no — encodings built during the loop on {', '.join(s['reencoded'])}"
    elif s["encoding_count_unknown"]:
        enc = f"not checked on {s['encoding_count_unknown']} instance(s)"
    else:
        enc = "yes (no encoding built during any loop)"
    parts.append(f"- encoding built once per task: {enc}")
    parts.append("")
    parts += ["### Slowest calls", ""]
    if s["slowest"]:
        parts.append(
            f"| instance | group | kind | selection | bounds | status | s | horizon | SAT calls "
            f"| conflicts | solve s | grow s | search s | ≥ {_fmt_s(target)} s |"
        )
        parts.append("|---|---|---|---|---|---|---|---|---|---|---|---|---|---|")
        for r, c in s["slowest"]:
            parts.append(
                f"| {r.get('domain')}/{r.get('problem')} | {c.get('group')} | {c.get('kind')} "
                f"| {_selection(c)} | {_bounds(c)} | {c.get('status')} "
                f"| {_fmt_s(c.get('seconds'))} | {c.get('horizon', '—')} "
                f"| {c.get('sat_calls', '—')} | {_or_dash(c.get('conflicts'))} "
                f"| {_fmt_s(c.get('solve_s'))} | {_fmt_s(c.get('grow_s'))} "
                f"| {_fmt_s(c.get('search_s'))} | {'yes' if over_target(c, target) else 'no'} |"
            )
    else:
        parts.append("No calls recorded.")
    parts.append("")
    parts += _errors_section(records, lambda r: f"{r.get('domain')}/{r.get('problem')}")
    return "\n".join(parts)


def call_rows(records: Sequence[dict[str, Any]]) -> list[dict[str, Any]]:
    rows = []
    for r, c in all_calls(records):
        row = {"domain": r.get("domain"), "problem": r.get("problem"), **c}
        if c.get("selection") is not None:  # "{}" is the human model, "" no selection
            row["selection"] = _selection(c)
        if c.get("lits") is not None:
            row["lits"] = " ".join(f"{i}={int(v)}" for i, v in c["lits"])
        if c.get("seconds_runs") is not None:
            row["seconds_runs"] = " ".join(f"{x:g}" for x in c["seconds_runs"])
        rows.append(row)
    return rows


def write_outputs(
    out_dir: Path, records: Sequence[dict[str, Any]], machine: dict[str, Any], target: float
) -> dict[str, Path]:
    files = _output_files(out_dir)
    s = summary(records, target)
    s["slowest"] = [
        {"domain": r.get("domain"), "problem": r.get("problem"), **c} for r, c in s["slowest"]
    ]
    data = {"machine": machine, "target_s": target, "summary": s, "records": list(records)}
    files["json"].write_text(json.dumps(data, indent=1, default=str))
    write_csv(files["csv"], call_rows(records), CALL_FIELDS)
    files["md"].write_text(render_table(records, machine, target))
    return files


# --------------------------------------------------------------------------- the command


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
