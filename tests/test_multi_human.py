"""Several human models: the enumeration engine against the brute-force oracle.

The oracle (helpers.multi_bruteforce) enumerates every subset of the union Delta and explores
every human model's whole state space, following only transitions on optimal plans; the engine
uses the OPT tiers (SAT or the built-in planner) and a product A* with Pareto labels.
"""

from __future__ import annotations

import itertools
import time

import pytest
from helpers.bruteforce import brute_force_frontier
from helpers.fuzzing import oracle_settings
from helpers.minitasks import usar_like
from helpers.multi_bruteforce import multi_brute_force_frontier
from helpers.multi_randomtasks import multi_human_tasks, multi_tradeoff_tasks
from helpers.randomtasks import two_model_tasks
from helpers.tradeoff_tasks import tradeoff_tasks
from hypothesis import HealthCheck, given
from hypothesis import strategies as st

from mega_sat.deadline import Deadline
from mega_sat.engines.multi_human import (
    MultiHumanSolver,
    multi_frontier,
    selections_by_cost,
    verify_multi,
)
from mega_sat.engines.sat_loop import sat_frontier
from mega_sat.errors import UnsolvableError, UsageError
from mega_sat.ground.grounding import ground
from mega_sat.model.task import TwoModelTask
from mega_sat.pddl.multi_task import MultiHumanTask
from mega_sat.results import choose

SETTINGS = oracle_settings(
    120, suppress_health_check=[HealthCheck.too_slow, HealthCheck.filter_too_much]
)

TASKS = st.one_of(multi_human_tasks(), multi_tradeoff_tasks())


def _pairs(points):
    return [(p.explanation_cost, p.robot_cost) for p in points]


def _oracle(task, fams, **kw):
    try:
        return multi_brute_force_frontier(task, fams, state_limit=20_000, **kw)
    except ValueError:
        return None


@SETTINGS
@given(TASKS, st.sampled_from([None, "builtin", "sat"]))
def test_frontier_equals_brute_force(task, planner):
    fams = [ground(t) for t in task.tasks]
    got = _oracle(task, fams)
    if got is None:
        with pytest.raises(UnsolvableError):
            multi_frontier(task, fams, planner=planner)
        return
    c_r, pts, results = got
    fr = multi_frontier(task, fams, planner=planner)
    assert fr.robot_optimal_cost == c_r
    assert _pairs(fr.points) == _pairs(pts)
    assert fr.complete and fr.exact
    for p in fr.points:
        r = results[p.selection]
        assert r.robot_cost is not None and r.robot_cost <= p.robot_cost
        assert p.human_costs == r.human_costs
        rep = verify_multi(
            task,
            fams,
            p.selection,
            p.plan,
            producers=["fd"] * len(fams),  # the built-in planner re-derives each optimum
            robot_cost=p.robot_cost,
            human_costs=p.human_costs,
            use_val=False,
        )
        assert rep.ok, rep.lines()


@SETTINGS
@given(multi_human_tasks(allow_zero_cost=True, max_delta=4))
def test_zero_cost_actions_equal_brute_force(task):
    # the default planner is the built-in one here and the product search has no horizon,
    # so the answer is exact even with zero-cost actions
    fams = [ground(t) for t in task.tasks]
    got = _oracle(task, fams)
    if got is None:
        return
    fr = multi_frontier(task, fams)
    assert _pairs(fr.points) == _pairs(got[1])
    assert fr.exact


@SETTINGS
@given(TASKS, st.data())
def test_update_costs_equal_brute_force(task, data):
    fams = [ground(t) for t in task.tasks]
    costs = tuple(data.draw(st.integers(1, 4)) for _ in task.delta)
    got = _oracle(task, fams, update_costs=costs)
    if got is None:
        return
    fr = multi_frontier(task, fams, update_costs=costs)
    assert _pairs(fr.points) == _pairs(got[1])
    assert all(p.weighted_cost == sum(costs[i] for i in p.selection) for p in fr.points)


@oracle_settings(60, suppress_health_check=())
@given(st.one_of(two_model_tasks(max_delta=5), tradeoff_tasks()))
def test_one_human_twice_is_one_human(task):
    # the same human model twice is one human model: both oracles and both engines agree
    fam = ground(task)
    try:
        c_r, pts, _ = brute_force_frontier(task, fam, state_limit=20_000)
    except ValueError:
        return
    twice = MultiHumanTask.from_tasks([task, task])
    assert twice.delta == task.delta
    fams = [fam, fam]
    mc, mpts, _ = multi_brute_force_frontier(twice, fams, state_limit=20_000)
    assert (mc, [(p.size, p.robot_cost) for p in mpts]) == (
        c_r,
        [(p.size, p.robot_cost) for p in pts],
    )
    fr = multi_frontier(twice, fams)
    assert _pairs(fr.points) == _pairs(sat_frontier(task, fam).points)


def test_selections_by_cost_enumerates_every_subset_in_cost_order():
    for costs in [(), (1,), (1, 1, 1), (3, 1, 2, 1), (2, 2, 5, 1, 1)]:
        got = list(selections_by_cost(costs))
        n = len(costs)
        assert len(got) == 2**n and len(set(got)) == 2**n
        totals = [sum(costs[i] for i in s) for s in got]
        assert totals == sorted(totals)


def _usar_pair() -> MultiHumanTask:
    """usar_like's robot with two commanders: one believes a blocked corridor open, the
    other lacks a new passage (so each update is a no-op for one of them)."""
    base = usar_like()
    robot = base.robot
    ups = list(base.delta)
    h1 = base.updated_model([i for i, u in enumerate(ups) if u.robot_has])
    h2 = base.updated_model([i for i, u in enumerate(ups) if not u.robot_has])
    return MultiHumanTask.from_models(robot, [h1, h2])


def test_updates_a_human_agrees_with_are_no_ops():
    task = _usar_pair()
    names = [u.name for u in task.delta]
    assert sorted(names) == sorted(u.name for u in usar_like().delta)
    for i, t in enumerate(task.tasks):
        own = {u.name for u in t.delta}
        for j, u in enumerate(task.delta):
            projected = task.project({j}, i)
            assert (len(projected) == 1) == (u.name in own)
        # human_i + (all of Delta) is the robot model whatever human_i agreed with
        assert task.updated_model(task.all_updates, i) == t.updated_model(t.all_updates)


def test_solver_answers_every_alpha_and_verifies():
    task = _usar_pair()
    s = MultiHumanSolver(task)
    fr = s.frontier()
    fams = s.families
    c_r, pts, _ = multi_brute_force_frontier(task, fams)
    assert _pairs(fr.points) == _pairs(pts)
    assert fr.exact
    for alpha in (0, 0.5, 1, 10):
        sol = s.solve(alpha)
        assert sol.chosen == choose(fr, alpha).chosen
    for p in fr.points:
        assert s.verify(p, use_val=False).ok
    # a plan that is not optimal for every human model fails verification
    worst = max(fr.points, key=lambda p: p.robot_cost)
    best = min(fr.points, key=lambda p: p.robot_cost)
    if worst.robot_cost != best.robot_cost:
        rep = s.verify(explanation=worst.explanation, plan=best.plan, use_val=False)
        assert not rep.ok


def test_json_gives_each_human_models_cost():
    task = _usar_pair()
    fr = MultiHumanSolver(task).frontier()
    d = fr.to_dict()
    assert d["engine"] == "multi-human"
    assert [h["model_difference"] for h in d["human_models"]] == [
        [u.name for u in t.delta] for t in task.tasks
    ]
    for p, q in zip(d["frontier"], fr.points, strict=True):
        assert "human_cost" not in p
        assert p["human_costs"] == list(q.human_costs) and len(q.human_costs) == 2
    sol = choose(fr, 1.0).to_dict()
    assert sol["chosen"]["human_costs"] == list(choose(fr, 1.0).chosen.human_costs)


def test_refuses_what_it_does_not_implement():
    task = _usar_pair()
    for kw in ({"engine": "astar"}, {"joint": "sat"}, {"hitting_set": "ilp"}):
        with pytest.raises(UsageError):
            MultiHumanSolver(task, **kw)
    with pytest.raises(UsageError):
        MultiHumanTask.from_tasks([task.tasks[0]])


def test_time_limit_returns_what_was_proven():
    task = _usar_pair()
    s = MultiHumanSolver(task, deadline=Deadline(time.perf_counter() + 3600, 3600))
    fams = s.families
    fr = multi_frontier(task, fams, deadline=Deadline(time.perf_counter() - 1, 0.0))
    assert not fr.complete and not fr.exact
    assert fr.next_size_lower_bound == 0
    assert any("time limit" in n for n in fr.notes)


def test_robot_model_must_be_shared():
    a, b = usar_like(), next(iter([usar_like()]))
    other = TwoModelTask.from_models(a.human, a.robot)
    with pytest.raises(UsageError):
        MultiHumanTask.from_tasks([a, other])
    assert MultiHumanTask.from_tasks([a, b]).robot == a.robot


def test_every_selection_checked_once_at_most_per_projection():
    # the caches make the work per projection, not per selection of the union
    task = _usar_pair()
    fams = [ground(t) for t in task.tasks]
    fr = multi_frontier(task, fams)
    n = len(task.delta)
    assert fr.stats["candidates"] <= 2**n
    projections = {
        tuple(task.project(set(c), i) for i in range(2))
        for k in range(n + 1)
        for c in itertools.combinations(range(n), k)
    }
    assert fr.stats["joint_searches"] <= len(projections)


def test_an_unproven_optimum_clears_exact(monkeypatch):
    # the horizon argument is the OPT oracle's, per human model: an optimum it cannot prove
    # (zero-cost actions under --planner sat, the horizon cap) must surface as exact: no
    from dataclasses import replace

    from mega_sat.planners.tiered_opt import TieredOpt

    task = _usar_pair()
    fams = [ground(t) for t in task.tasks]
    proven = multi_frontier(task, fams)
    assert proven.exact and not proven.notes
    original = TieredOpt.optimal

    def unproven(self, sel):
        r = original(self, sel)
        if self.family is fams[1] and sel:
            return replace(r, exact=False, reason="horizon cap 200 < 300 steps needed")
        return r

    monkeypatch.setattr(TieredOpt, "optimal", unproven)
    fr = multi_frontier(task, fams)
    assert _pairs(fr.points) == _pairs(proven.points)
    assert not fr.exact and fr.complete
    assert any("OPT not proven optimal for human model 2" in n for n in fr.notes)


@oracle_settings(80, suppress_health_check=())
@given(multi_tradeoff_tasks(), st.sampled_from([None, "builtin"]))
def test_route_maps_with_trade_offs_equal_brute_force(task, planner):
    # the commanders' maps on their own: these are the tasks with several frontier points
    fams = [ground(t) for t in task.tasks]
    got = _oracle(task, fams)
    assert got is not None  # the detour is open for the robot
    fr = multi_frontier(task, fams, planner=planner)
    assert (fr.robot_optimal_cost, _pairs(fr.points)) == (got[0], _pairs(got[1]))
    assert fr.exact


def test_building_a_multi_human_task_checks_its_arguments():
    """from_tasks / from_models refuse what is not a task or a model in one UsageError (an
    AttributeError from deep inside before; found by an API sweep)."""
    task = usar_like()
    with pytest.raises(UsageError, match="takes a list of TwoModelTask"):
        MultiHumanTask.from_tasks(None)
    with pytest.raises(UsageError, match="task 2 is not a TwoModelTask: int"):
        MultiHumanTask.from_tasks([task, 5])
    with pytest.raises(UsageError, match="takes the robot's Model"):
        MultiHumanTask.from_models(None, [task.human, task.human])
    with pytest.raises(UsageError, match="human model 2 is not a Model"):
        MultiHumanTask.from_models(task.robot, [task.human, None])
    with pytest.raises(UsageError, match="sources names 1 human model"):
        MultiHumanTask.from_models(task.robot, [task.human, task.human], sources=[{}])
    assert len(MultiHumanTask.from_models(task.robot, [task.human, task.human]).tasks) == 2


def test_an_exact_alpha_keeps_its_ties():
    """At alpha = 1/3 the two commanders' points (2, 8) and (3, 5) tie (objective 10/3) and
    the lower robot cost wins; a Fraction(1, 3) was rounded to a float first, which is just
    below 1/3, and picked (2, 8)."""
    from fractions import Fraction
    from pathlib import Path

    from mega_sat import api

    root = Path(__file__).resolve().parent.parent
    solver = MultiHumanSolver(api.load_multi_task_dir(root / "domains" / "usar-two-commanders"))
    pairs = [(p.size, p.robot_cost) for p in solver.frontier().points]
    assert (2, 8) in pairs and (3, 5) in pairs
    assert solver.solve(Fraction(1, 3)).chosen.robot_cost == 5
    assert solver.solve(1 / 3).chosen.robot_cost == 8  # the float is below 1/3
    with pytest.raises(UsageError, match="timeout must be a number of seconds"):
        api.MegaSolver(api.load_task_dir(root / "domains/usar-fetch/p1"), timeout=True)
