"""The per-call oracle benchmark (issue #3): a real run on usar p1 through the CLI and its
subprocess worker, the kill path, and the table/summary on fabricated records."""

from __future__ import annotations

import csv
import json
import re
from pathlib import Path

from click.testing import CliRunner

from mega_sat.bench import oracle_calls as oracle_bench
from mega_sat.bench.oracle_calls import (
    CALL_STATUSES,
    direct_selections,
    merge_repeats,
    over_target,
    render_table,
    run_instance,
    summary,
)
from mega_sat.cli.commands import main

DOMAINS = Path(__file__).resolve().parent.parent / "domains"


def _cells(line: str) -> list[str]:
    return [c.strip() for c in re.split(r"(?<!\\)\|", line.strip().strip("|"))]


def test_bench_calls_on_usar_p1(tmp_path):
    out = tmp_path / "calls"
    res = CliRunner().invoke(
        main,
        [
            "bench-calls",
            "--domains",
            str(DOMAINS),
            "--only",
            "usar-fetch/p1",
            "--out",
            str(out),
            "--call-limit",
            "30",
            "--time-limit",
            "60",
        ],
    )
    assert res.exit_code == 0, res.output
    for name in ("results.json", "results.csv", "table.md"):
        assert (out / name).is_file()

    data = json.loads((out / "results.json").read_text())
    assert data["machine"]["cores"]
    (rec,) = data["records"]
    assert (rec["domain"], rec["problem"], rec["status"]) == ("usar-fetch", "p1", "ok")
    assert rec["delta"] == 3 and rec["atoms"] > 0 and rec["ground_actions"] > 0
    assert rec["build_s"] >= 0
    assert rec["encodings_built_in_loop"] == 0  # the encoding is built once per task
    calls = rec["calls"]
    assert calls
    assert {c["group"] for c in calls} == {"loop", "direct"}
    assert any(c["kind"] == "joint" for c in calls)
    # direct OPT: robot model, human model and each of the 3 single updates, all real SAT calls
    direct = [c for c in calls if c["group"] == "direct"]
    assert sorted(map(tuple, (c["selection"] for c in direct))) == sorted(
        [(0, 1, 2), (), (0,), (1,), (2,)]
    )
    for c in calls:
        assert c["status"] in CALL_STATUSES and c["status"] not in ("timeout", "error")
        assert c["kind"] in ("opt", "joint")
        assert c["seconds"] >= 0 and c["sat_calls"] >= 0
        # conflicts are counted from the solvers themselves: no SAT call, no conflict
        assert isinstance(c["conflicts"], int) and c["conflicts"] >= 0
        if c["sat_calls"] == 0:
            assert c["conflicts"] == 0
        # the parts of a call are disjoint pieces of its wall time
        parts = [c[k] for k in oracle_bench.WORK_KEYS]
        assert all(x >= 0 for x in parts) and sum(parts) <= c["seconds"] + 1e-4
        if c["sat_calls"] == 0:
            assert c["solve_s"] == 0
        assert c["opt_vars"] > 0 and c["joint_vars"] > 0 and c["joint_clauses"] > 0
        if c["kind"] == "joint":
            assert c["human_bound"] is not None and c["horizon"] >= 0
    assert all(c["status"] == "optimal" and c["cost"] > 0 for c in direct)

    with (out / "results.csv").open() as f:
        rows = list(csv.DictReader(f))
    assert len(rows) == len(calls)

    table = (out / "table.md").read_text()
    usar = [ln for ln in table.splitlines() if ln.startswith("| usar-fetch | p1 |")]
    assert len(usar) == 1
    cells = _cells(usar[0])
    assert cells[2] == "ok" and cells[5] == "3"
    target = data["target_s"]
    n_over = sum(1 for c in calls if over_target(c, target))
    m = re.search(r"^- calls ≥ [0-9.]+ s: (\d+)", table, re.M)
    assert m and int(m.group(1)) == n_over == data["summary"]["over_target"]
    assert int(cells[-1]) == n_over
    m = re.search(r"^- calls timed: (\d+)", table, re.M)
    assert m and int(m.group(1)) == sum(1 for c in calls if not c["cached"])
    assert "target (every call < 0.5 s): " in table


def test_killed_instance_is_a_timeout(monkeypatch):
    monkeypatch.setattr(oracle_bench, "hard_limit", lambda t: 0.05)
    rec = run_instance(str(DOMAINS / "usar-fetch" / "p1"), 30.0, 60.0, "usar-fetch", "p1")
    assert rec["status"] == "timeout" and rec["killed"]
    assert rec["calls"] == []


def test_repeat_must_be_positive(tmp_path):
    res = CliRunner().invoke(
        main, ["bench-calls", "--domains", str(DOMAINS), "--repeat", "0", "--out", str(tmp_path)]
    )
    assert res.exit_code == 2 and "--repeat must be >= 1" in res.output
    assert not any(tmp_path.iterdir())


def test_merge_repeats_takes_the_median_of_the_same_question():
    a = {"group": "loop", "kind": "opt", "selection": [0]}
    b = {"group": "loop", "kind": "joint", "selection": [0], "robot_bound": 5, "human_bound": 6}
    lit = {"group": "loop", "kind": "joint", "lits": [[1, True]], "human_bound": 6}
    run1 = {"status": "ok", "calls": [{**a, "seconds": 1.0, "solve_s": 0.5}, {**b, "seconds": 0.1}]}
    # the second run asks the same questions in another order, the same JOINT twice, and one more
    run2 = {
        "status": "ok",
        "calls": [
            {**b, "seconds": 0.3},
            {**a, "seconds": 3.0, "solve_s": 2.5},
            {**b, "seconds": 9.0},
            {**lit, "seconds": 0.2},
        ],
    }
    run3 = {"status": "timeout", "killed": True, "calls": [{**a, "seconds": 2.0, "solve_s": 0.1}]}
    m = merge_repeats([run1, run2, run3])
    opt, joint = m["calls"]
    assert opt["seconds"] == 2.0 and opt["seconds_runs"] == [1.0, 3.0, 2.0]
    assert opt["solve_s"] == 0.5  # each part by its own median
    # the first occurrence matches the first occurrence: 0.1 and 0.3, not 9.0
    assert joint["seconds"] == 0.2 and joint["seconds_runs"] == [0.1, 0.3]
    assert m["repeats"] == 3 and m["repeat_unmatched"] == 2
    assert m["status"] == "timeout" and m["killed"]  # one unfinished run: not finished
    assert merge_repeats([run1]) == run1


def test_direct_selections_dedupe():
    assert direct_selections(1, frozenset({0})) == [frozenset({0}), frozenset()]
    assert len(direct_selections(3, frozenset({0, 1, 2}))) == 5


# --------------------------------------------------------------------------- rendering


def _call(kind="joint", seconds=0.01, status="plan", group="loop", cached=False, **kw):
    c = {
        "group": group,
        "seq": 1,
        "kind": kind,
        "selection": [0],
        "robot_bound": 7 if kind == "joint" else None,
        "human_bound": 8 if kind == "joint" else None,
        "status": status,
        "horizon": 7,
        "sat_calls": 1,
        "seconds": seconds,
        "cached": cached,
        "opt_vars": 10,
        "opt_clauses": 20,
        "opt_horizon": 3,
        "joint_vars": 30,
        "joint_clauses": 40,
        "joint_horizon": 7,
    }
    c.update(kw)
    return c


def _rec(dom, prob, calls, status="ok"):
    return {
        "domain": dom,
        "problem": prob,
        "status": status,
        "atoms": 5,
        "ground_actions": 6,
        "delta": 2,
        "build_s": 0.01,
        "call_limit_s": 60.0,
        "time_limit_s": 600.0,
        "encodings_built_in_loop": 0,
        "loop_stats": {"opt_by_cached": 2, "opt_by_quick_search": 1},
        "calls": calls,
    }


MACHINE = {"cpu": "test cpu", "cores": 1, "ram_gb": 1, "python": "3", "date": "today"}


def test_table_reports_a_slow_call_as_missed():
    fast = _rec("d", "p1", [_call(), _call("opt", 0.2, "optimal", "direct", cost=3)])
    slow = _rec(
        "d",
        "p2",
        [
            _call(seconds=0.01),
            _call(seconds=2.5, status="infeasible", horizon=19),
            _call("opt", 0.0, "optimal", cached=True),
            _call("opt", 0.7, "optimal", group="direct"),
        ],
    )
    md = render_table([fast, slow], MACHINE, 0.5)
    rows = {_cells(ln)[1]: _cells(ln) for ln in md.splitlines() if ln.startswith("| d |")}
    assert rows["p1"][-1] == "0" and rows["p2"][-1] == "2"
    assert rows["p2"][7] == "3"  # loop OPT answered by cheaper proofs
    assert rows["p2"][10] == "0 (+1 cached)"  # the cached answer is not a timed call
    assert "- calls ≥ 0.5 s: 2" in md
    assert (
        "- calls timed: 5 (loop OPT 0, direct OPT 2, JOINT 3); cached OPT answers excluded: 1" in md
    )
    assert "target (every call < 0.5 s): missed" in md
    slowest = md.split("### Slowest calls")[1].splitlines()
    first = _cells(next(ln for ln in slowest if ln.startswith("| d/")))
    assert first[:3] == ["d/p2", "loop", "joint"] and first[4] == "K=7, c=8" and first[6] == "2.5"
    assert summary([fast, slow], 0.5)["over_target"] == 2
    # the same records against a looser target
    assert "target (every call < 5 s): met" in render_table([fast, slow], MACHINE, 5.0)


def test_table_timeouts_and_unfinished_instances():
    timed_out = _rec("d", "p1", [_call(seconds=0.3, status="timeout")], status="timeout")
    md = render_table([timed_out], MACHINE, 0.5)
    assert "target (every call < 0.5 s): missed" in md  # a call stopped by its limit missed
    assert "timeout (call)" in md
    killed = _rec("d", "p2", [_call(seconds=0.01)], status="timeout")
    killed["killed"] = True
    md = render_table([killed], MACHINE, 0.5)
    assert "target (every call < 0.5 s): not established" in md
    assert "timeout (killed)" in md
