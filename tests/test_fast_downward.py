"""Fast Downward wrapper: plan parsing, exit codes, and optimal costs equal the built-in's."""

from __future__ import annotations

from pathlib import Path

import pytest
from helpers.fuzzing import oracle_settings
from helpers.pddl_tasks import pigeonhole
from helpers.randomtasks import models
from hypothesis import HealthCheck, given

from mega_sat.errors import PlannerError
from mega_sat.ground.grounding import ground_model
from mega_sat.ground.simulate import simulate
from mega_sat.planners.fast_downward import fd_available, fd_plan, parse_plan_text
from mega_sat.search.astar import astar

needs_fd = pytest.mark.skipif(not fd_available(), reason="Fast Downward not installed")

DOMAIN = """(define (domain t) (:requirements :strips :action-costs)
 (:predicates (at ?x) (conn ?x ?y))
 (:functions (total-cost) - number)
 (:action move :parameters (?x ?y) :precondition (and (at ?x) (conn ?x ?y))
  :effect (and (not (at ?x)) (at ?y) (increase (total-cost) 2))))
"""
PROBLEM = """(define (problem p) (:domain t) (:objects a b c)
 (:init (at a) (conn a b) (conn b c) {extra} (= (total-cost) 0))
 (:goal (at c)) (:metric minimize (total-cost)))
"""


def test_parse_plan_text():
    steps, cost = parse_plan_text("(MOVE a b)\n(move b c)\n; cost = 4 (general cost)\n")
    assert steps == (("move", "a", "b"), ("move", "b", "c")) and cost == 4
    assert parse_plan_text("; cost = 0 (unit cost)\n") == ((), 0)
    assert parse_plan_text("(noop)\n")[1] is None


@needs_fd
def test_solved_and_unsolvable():
    r = fd_plan(DOMAIN, PROBLEM.format(extra=""))
    assert r.status == "optimal" and r.cost == 4 and r.planner == "fd"
    assert r.plan == (("move", "a", "b"), ("move", "b", "c"))
    r = fd_plan(DOMAIN, PROBLEM.format(extra="").replace("(conn a b)", ""))
    assert r.status == "unsolvable" and r.plan is None
    # reachable in the relaxation, unsolvable for real: the search has to prove it
    both = PROBLEM.format(extra="").replace("(:goal (at c))", "(:goal (and (at b) (at c)))")
    r = fd_plan(DOMAIN, both)
    assert r.status == "unsolvable"


@needs_fd
def test_errors_raise_planner_error():
    with pytest.raises(PlannerError, match="Fast Downward failed") as e:
        fd_plan(
            DOMAIN.replace("(at ?x) (conn ?x ?y))", "(at ?x) ((conn ?x ?y)))", 1),
            PROBLEM.format(extra=""),
        )
    assert "Predicate name is expected to be a word" in str(e.value)
    with pytest.raises(PlannerError, match="no_such_search"):
        fd_plan(DOMAIN, PROBLEM.format(extra=""), search="no_such_search()")


@needs_fd
@oracle_settings(12, suppress_health_check=[HealthCheck.too_slow])
@given(models(allow_zero_cost=True))
def test_fd_optimal_cost_equals_builtin(model):
    from mega_sat.pddl.writer import domain_to_pddl, problem_to_pddl

    builtin = astar(ground_model(model))
    fd = fd_plan(domain_to_pddl(model), problem_to_pddl(model))
    assert fd.status == builtin.status
    assert fd.cost == builtin.cost
    if fd.plan is not None:
        sim = simulate(model, fd.plan)
        assert sim.valid and sim.cost == fd.cost


@needs_fd
def test_time_limit_gives_timeout():
    r = fd_plan(*pigeonhole(14), time_limit=1)
    assert r.status == "timeout" and r.plan is None
    assert fd_plan(*pigeonhole(3)).status == "unsolvable"


def _costly_usar(tmp_path, cost: int) -> Path:
    """usar-fetch/p1 with ``move`` costing ``cost`` in both models."""
    src = Path(__file__).resolve().parent.parent / "domains" / "usar-fetch"
    for name in ("robot-domain.pddl", "human-domain.pddl"):
        old = "(robot_at ?to) (increase (total-cost) 1)"
        text = (
            (src / name).read_text().replace(old, f"(robot_at ?to) (increase (total-cost) {cost})")
        )
        (tmp_path / name).write_text(text)
    for name in ("robot-problem.pddl", "human-problem.pddl"):
        (tmp_path / name).write_text((src / "p1" / name).read_text())
    return tmp_path


def test_costs_fd_cannot_sum_are_kept_from_it(tmp_path):
    """Fast Downward (and VAL) add costs in 32-bit integers: a chosen --planner fd is refused
    up front (it failed with exit 4, or could overflow silently), the verify checker falls back
    to the built-in planner, and VAL's wrapped-around cost is not compared."""
    from click.testing import CliRunner

    from mega_sat import api
    from mega_sat.cli.commands import main
    from mega_sat.engines.verify import checker_for
    from mega_sat.errors import UsageError
    from mega_sat.planners.fast_downward import FD_INT_LIMIT, fd_cost_problem

    assert fd_cost_problem(1000, 1000) is None and fd_cost_problem(FD_INT_LIMIT, 0) is not None
    task = _costly_usar(tmp_path, 3_000_000_000)
    solver = api.MegaSolver(api.load_task_dir(task))
    assert solver.family.max_cost == 3_000_000_000
    assert checker_for("portfolio", solver.family) != "fd"
    if fd_available():
        with pytest.raises(UsageError, match="may overflow Fast Downward's 32-bit cost sums"):
            api.MegaSolver(api.load_task_dir(task), planner="fd").frontier()
    res = CliRunner().invoke(main, ["solve", "--task", str(task), "--alpha", "0", "--verify"])
    assert res.exit_code == 0, res.output
    assert "verify: passed" in res.output and "by fd" not in res.output
    from mega_sat.planners.val import val_available

    if val_available():
        assert "is beyond VAL's range" in res.output  # the plan's 3 moves wrap VAL's sum
    small = api.MegaSolver(
        api.load_task_dir(Path(__file__).resolve().parent.parent / "domains/usar-fetch/p1")
    )
    if fd_available():
        assert checker_for("portfolio", small.family) == "fd"


@needs_fd
def test_the_builtin_planner_hands_fd_what_its_blind_search_did_not_settle(monkeypatch):
    """With ``builtin_fd_after_blind`` a call whose blind search passes ``blind_nodes`` is
    answered by FD's A* with LM-cut (the same optimum as the built-in LM-cut); a failing FD
    leaves the call to the built-in planner."""
    from mega_sat.api import load_task_dir
    from mega_sat.ground.grounding import ground
    from mega_sat.options import Options
    from mega_sat.planners.node_planner import NodePlanner

    root = Path(__file__).resolve().parents[1]
    task = load_task_dir(root / "domains/blocksworld/delta/7/p3")
    fam = ground(task)
    handed = []
    real_fd = NodePlanner._fd

    def fd(self, *a):
        handed.append(a[0])
        return real_fd(self, *a)

    monkeypatch.setattr(NodePlanner, "_fd", fd)
    sels = [frozenset(), fam.robot_selection]
    optimum = {}
    for n in (10, 1_000_000):
        for sel in sels:
            for on in (True, False):
                options = Options(blind_nodes=n, builtin_fd_after_blind=on)
                r = NodePlanner(task, fam, "builtin", options=options).optimal(sel)
                assert r.status.decided
                assert optimum.setdefault(sel, r.cost) == r.cost
    assert handed == sels  # only blind searches cut short at 10 nodes, and only when on

    def broken(self, *a):
        raise PlannerError("Fast Downward failed")

    monkeypatch.setattr(NodePlanner, "_fd", broken)
    options = Options(blind_nodes=10)
    r = NodePlanner(task, fam, "builtin", options=options).optimal(frozenset())
    assert r.status.decided and r.cost == optimum[frozenset()]
