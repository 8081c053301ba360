"""The missing-schemas suite (domains/missing-schemas): hand-written IPC-style domains whose
human model lacks whole robot schemas.  Every instance parses with the documented shape of
Delta, the benchmark harness finds it (and only its own suite does), and the smallest instance's
frontier is checked against the brute-force oracle where 2^|Delta| allows it and against the
A* baseline and explicit-state checks where it does not."""

from __future__ import annotations

import itertools
from pathlib import Path

import pytest
from helpers.bruteforce import best_for_selection, brute_force_frontier

from mega_sat.api import MegaSolver
from mega_sat.bench.harness import (
    MISSING_SCHEMAS_DIR,
    discover,
    missing_schemas_summary,
    missing_schemas_table,
    plan_jobs,
    render_markdown,
)
from mega_sat.engines.verify import verify_pair
from mega_sat.model.features import SCHEMA
from mega_sat.model.task import TwoModelTask
from mega_sat.pddl.loading import load_task, resolve_task_dir

DOMAINS = Path(__file__).resolve().parent.parent / "domains"
SUITE = DOMAINS / MISSING_SCHEMAS_DIR
INSTANCES = sorted(
    p.relative_to(SUITE).as_posix()
    for p in SUITE.glob("*/p*")
    if (p / "robot-problem.pddl").is_file()
)
# the smallest instance (fewest ground atoms and actions, smallest Delta of the suite)
SMALLEST = "logistics/p2"


def _task(rel: str) -> TwoModelTask:
    return load_task(**resolve_task_dir(SUITE / rel))


def _points(fr) -> list[tuple[int, int]]:
    return [(p.size, p.robot_cost) for p in fr.points]


def test_suite_layout():
    doms = sorted(d.name for d in SUITE.iterdir() if d.is_dir())
    assert len(doms) >= 3
    assert (SUITE / "README.md").is_file()
    assert not (SUITE / "robot-domain.pddl").exists()  # keeps the other suites away
    for d in doms:
        assert (SUITE / d / "robot-domain.pddl").is_file()
        assert (SUITE / d / "human-domain.pddl").is_file()
        assert "## Frontier" in (SUITE / d / "README.md").read_text()
        assert len([i for i in INSTANCES if i.startswith(d + "/")]) >= 3


@pytest.mark.parametrize("rel", INSTANCES)
def test_instance_shape(rel):
    """|Delta| in [20, 50]; the human lacks at least one robot schema of >= 4 parameters,
    at most three in all, whose parameter types travel with their has-parameters update."""
    task = _task(rel)
    assert 20 <= len(task.delta) <= 50
    missing = set(task.robot.schemas) - set(task.human.schemas)
    assert 1 <= len(missing) <= 3
    assert max(len(task.robot.schemas[s].params) for s in missing) >= 4
    assert not set(task.human.schemas) - set(task.robot.schemas)
    exists = [u for u in task.delta if u.feature.kind == SCHEMA]
    assert {u.feature.action for u in exists} == missing and all(u.robot_has for u in exists)
    # the shared schemas differ only by static preconditions the human lacks
    shared = [u for u in task.delta if u.feature.action not in missing]
    assert shared and all(u.robot_has and u.feature.kind == "pre" for u in shared)


def test_some_missing_schema_has_eight_typed_parameters():
    widths = set()
    for rel in INSTANCES:
        task = _task(rel)
        for s in set(task.robot.schemas) - set(task.human.schemas):
            widths.add(len(task.robot.schemas[s].params))
    assert 8 in widths


# --------------------------------------------------------------------------- the harness


def test_discovery_keeps_the_suite_to_itself():
    found = discover(DOMAINS, "missing-schemas")
    assert sorted(f"{i.domain}/{i.problem}" for i in found) == INSTANCES
    assert all(i.delta is None and i.suite == "missing-schemas" for i in found)
    for suite in ("paper", "scaling", "sweep", "smoke"):
        assert not any(MISSING_SCHEMAS_DIR in i.task_dir for i in discover(DOMAINS, suite))
    only = discover(DOMAINS, "missing-schemas", ["tpp"])
    assert only and {i.domain for i in only} == {"tpp"}


def test_jobs_run_both_engines_with_sat_in_its_default_configuration():
    jobs = plan_jobs(DOMAINS, "missing-schemas", ["tpp/p1"], None, "fd")
    assert [(j.engine, j.planner, j.time_limit) for j in jobs] == [
        ("astar", "fd", 60.0),
        ("sat", None, 60.0),
    ]
    assert not any(
        j.instance.suite == "missing-schemas" for j in plan_jobs(DOMAINS, "all", (), None, "fd")
    )


def _rec(prob, engine, **kw):
    rec = {
        "suite": "missing-schemas",
        "domain": "tpp",
        "problem": prob,
        "delta": None,
        "engine": engine,
        "planner": "fd" if engine == "astar" else "sat",
        "status": "ok",
        "seconds": 2.0,
        "time_limit_s": 60.0,
        "delta_size": 22,
        "ground_actions": 178,
        "robot_optimal_cost": 6,
        "E_ropt": 5,
        "exact": engine == "sat",
        "frontier": [[1, 8], [5, 6]],
    }
    rec.update(kw)
    return rec


def test_table_and_summary_on_fabricated_records():
    recs = [
        _rec("p1", "astar", status="timeout", seconds=None, E_ropt=None),
        _rec("p1", "sat", robot_call_fd_s=0.25, ratio_sat_vs_fd_call=8.0),
        _rec("p2", "astar", seconds=30.0),
        _rec("p2", "sat", seconds=12.0, robot_call_fd_s=0.3, ratio_sat_vs_fd_call=40.0),
    ]
    table = missing_schemas_table(recs)
    rows = table.strip().splitlines()[2:]
    assert rows[0].startswith("| tpp | p1 | 22 | 178 | 6 | (1, 8) (5, 6) | 2.00 | yes | 0.25 |")
    assert rows[0].endswith("| 8.00 | timeout | — |")
    assert rows[1].endswith("| 40.0 | 30.0 | 5 |")
    summary = missing_schemas_summary(recs)
    assert summary[0] == "sat frontiers exact: 2 of 2; exact in under 10.0 s: 1 of 2."
    assert "24.0 (n = 2; target < 20.0)" in summary[1]
    assert summary[2] == "astar finished 1 of 2 within its limit."
    md = render_markdown(recs, {"cpu": "x", "cores": 1})
    assert "## Missing schemas" in md and "sat for the sat engine's OPT" in md


# --------------------------------------------------------------------------- frontiers


def _sub_task(task: TwoModelTask, actions: set[str]) -> TwoModelTask:
    """The task whose human already has every update of Delta except those of ``actions``:
    a missing-schemas task small enough for the brute-force oracle."""
    given = [i for i, u in enumerate(task.delta) if u.feature.action not in actions]
    sub = TwoModelTask.from_models(task.robot, task.updated_model(given))
    assert {u.name for u in sub.delta} == {
        u.name for u in task.delta if u.feature.action in actions
    }
    return sub


@pytest.mark.slow
@pytest.mark.parametrize(
    "rel,actions",
    [
        ("logistics/p2", {"plane-to-truck", "drive-truck"}),
        ("tpp/p2", {"drive-via", "drive"}),
    ],
)
def test_frontier_equals_brute_force_on_a_sub_delta(rel, actions):
    """2^|Delta| is out of reach at |Delta| >= 20, so the oracle runs on the instance with
    the human told everything but one missing schema and the static preconditions of a shared
    one (|Delta| 7-8): the frontier must equal the brute force's."""
    sub = _sub_task(_task(rel), actions)
    solver = MegaSolver(sub)
    fr = solver.frontier()
    c_r, pts, _ = brute_force_frontier(sub, solver.family)
    assert fr.exact and fr.robot_optimal_cost == c_r
    assert _points(fr) == [(p.size, p.robot_cost) for p in pts]


@pytest.mark.slow
def test_smallest_instance_frontier_cross_checked():
    """The full smallest instance: each point's explanation admits no cheaper robot plan that
    is optimal for the human (explicit-state search) and verifies; no smaller explanation than
    the first point's admits any solution; the A* baseline, stopped early, never beats the sat
    engine and agrees on the robot's optimum."""
    task = _task(SMALLEST)
    solver = MegaSolver(task)
    fr = solver.frontier()
    assert fr.exact and fr.points
    for p in fr.points:
        r = best_for_selection(solver.family, p.selection)
        assert (r.robot_cost, r.human_cost) == (p.robot_cost, p.human_cost)
        rep = verify_pair(
            task,
            solver.family,
            p.selection,
            p.plan,
            producer="sat",
            robot_cost=p.robot_cost,
            human_cost=p.human_cost,
        )
        assert rep.ok, rep.lines()
    assert fr.points[-1].robot_cost == fr.robot_optimal_cost
    for k in range(fr.points[0].size):
        for combo in itertools.combinations(range(len(task.delta)), k):
            assert best_for_selection(solver.family, frozenset(combo)).robot_cost is None, combo
    baseline = MegaSolver(task, engine="astar", planner="builtin", timeout=4.0).frontier()
    assert baseline.robot_optimal_cost == fr.robot_optimal_cost
    for size, cost in _points(baseline):
        assert any(s <= size and c <= cost for s, c in _points(fr)), (size, cost)


def test_apply_names_updates_of_schemas_it_cannot_write(tmp_path):
    """A precondition of a schema human + E still lacks has no place in PDDL: ``apply`` writes
    the model without it and says so, so a re-diff listing it again is no surprise."""
    from click.testing import CliRunner

    from mega_sat.cli.commands import main

    task = SUITE / "depots" / "p1"
    e = tmp_path / "e.txt"
    e.write_text(
        "add-lift-load-has-precondition-at ?c ?p\nadd-drive-has-precondition-road ?from ?to\n"
    )
    res = CliRunner().invoke(
        main, ["apply", "--task", str(task), "--explanation", str(e), "--out", str(tmp_path / "m")]
    )
    assert res.exit_code == 0, res.output
    assert "1 update(s) of the explanation belong to action(s) human + E lacks (lift-load)" in (
        res.output
    )
    written = (tmp_path / "m" / "domain.pddl").read_text()
    assert "lift-load" not in written and "(road ?from ?to)" in written
    e.write_text("add-drive-has-precondition-road ?from ?to\n")
    res = CliRunner().invoke(
        main, ["apply", "--task", str(task), "--explanation", str(e), "--out", str(tmp_path / "n")]
    )
    assert res.exit_code == 0 and "human + E lacks" not in res.output
