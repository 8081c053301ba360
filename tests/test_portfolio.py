"""The OPT portfolio (``planner="portfolio"``, mega_sat/planners/node_planner.py): uniform-cost
search and the SAT OPT oracle race, forked or in turns; either way the answer is the optimum
that brute force finds, and the answer names the method that gave it."""

from __future__ import annotations

import os

import pytest
from helpers.sat_families import dijkstra, families, plan_cost, selections
from hypothesis import given, settings
from hypothesis import strategies as st

from mega_sat.deadline import Deadline
from mega_sat.ground.family import GroundFamily
from mega_sat.options import Options
from mega_sat.planners.node_planner import ForkedSearch, NodePlanner
from mega_sat.planners.tiered_opt import TieredOpt
from mega_sat.search.astar import _uniform_cost, uniform_cost_steps


@pytest.mark.parametrize("forked", [True, False])
@settings(max_examples=40, deadline=None)
@given(fam=families(), data=st.data())
def test_portfolio_gives_the_optimum(forked: bool, fam: GroundFamily, data):
    if forked and not hasattr(os, "fork"):
        pytest.skip("no fork here")
    opts = Options(race_processes=forked, race_first_conflicts=1)
    planner = NodePlanner(None, fam, "portfolio", options=opts)
    for _ in range(3):
        sel = data.draw(selections(fam.n_updates))
        r = planner.optimal(sel)
        task = fam.specialize(sel)
        c = dijkstra(task)
        # "portfolio" itself answers only where the goal holds initially (no race needed)
        assert r.exact and (r.planner in ("builtin", "sat") or r.plan == ())
        if c is None:
            assert r.status == "unsolvable"
        else:
            assert r.status == "optimal" and r.cost == c and plan_cost(task, r.plan) == c


@settings(max_examples=30, deadline=None)
@given(fam=families(), data=st.data())
def test_tiered_stats_name_the_method_that_answered(fam: GroundFamily, data):
    tiers = TieredOpt(fam, NodePlanner(None, fam, "portfolio"))
    for _ in range(3):
        tiers.optimal(data.draw(selections(fam.n_updates)))
    keys = ("opt_planner_builtin", "opt_planner_sat", "opt_planner_portfolio")
    assert sum(tiers.stats.get(k, 0) for k in keys) == tiers.stats["opt_by_planner"]


@settings(max_examples=40, deadline=None)
@given(fam=families(), data=st.data())
def test_paused_search_answers_like_the_search_run_through(fam: GroundFamily, data):
    task = fam.specialize(data.draw(selections(fam.n_updates)))
    init = sum(1 << p for p in task.init)
    goal = sum(1 << p for p in task.goal)
    steps = uniform_cost_steps(task, init, goal)
    try:
        while True:
            next(steps)
    except StopIteration as done:
        paused = done.value
    assert paused == _uniform_cost(task, init, goal, None, None)


def test_forked_search_answers_and_stops():
    from helpers.minitasks import usar_like

    from mega_sat.ground.grounding import ground

    fam = ground(usar_like())
    task = fam.specialize(frozenset())
    child = ForkedSearch(task)
    try:
        status, plan, cost = child.result(30.0)
        done, expanded = child.progress(1 << 40, Deadline.after(30.0))
    finally:
        child.stop()
    assert status == "optimal" and cost == dijkstra(task) and plan_cost(task, plan) == cost
    assert done and expanded == _uniform_cost(task, *_ends(task), None, None)[3]


def _ends(task):
    return sum(1 << p for p in task.init), sum(1 << p for p in task.goal)


def test_the_portfolio_answers_alike_run_after_run():
    """The referee counts work, not seconds: the same calls give the same plans and the same
    winners, whatever the machine's load."""
    from mega_sat import api
    from mega_sat.pddl.loading import resolve_task_dir

    root = os.path.join(os.path.dirname(__file__), "..", "domains", "rover-martian", "delta")
    task = api.load_task(**resolve_task_dir(os.path.join(root, "10", "p3")))
    from mega_sat.ground.grounding import ground

    fam = ground(task)
    sels = [frozenset(range(0, len(task.delta), k)) for k in (1, 2, 3, 5)]
    runs = []
    for _ in range(2):
        planner = NodePlanner(task, fam, "portfolio")
        runs.append([(r.planner, r.cost, r.plan) for r in map(planner.optimal, sels)])
    assert runs[0] == runs[1]


def test_portfolio_past_its_deadline_says_timeout_not_an_answer():
    from helpers.minitasks import usar_like

    from mega_sat.deadline import TimeLimitReached
    from mega_sat.ground.grounding import ground

    fam = ground(usar_like())
    planner = NodePlanner(None, fam, "portfolio", deadline=Deadline.after(1e-9))
    with pytest.raises(TimeLimitReached):
        planner.optimal(frozenset())
