"""``bench-calls`` results: repeated runs merged per call, the summary and the markdown table,
the files written."""

from __future__ import annotations

import json
import statistics
from collections.abc import Sequence
from pathlib import Path
from typing import Any

from mega_sat.bench.common import errors_section as _errors_section
from mega_sat.bench.common import output_files as _output_files
from mega_sat.bench.common import write_csv

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

WORK_KEYS = ("solve_s", "grow_s", "search_s", "counting_s")


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
