"""The OPT portfolio (``planner="portfolio"``, mega_sat/planners/node_planner.py): uniform-cost
search and the SAT OPT oracle race, forked or in turns; either way the answer is the optimum
that brute force finds, and the answer names the method that gave it."""

from __future__ import annotations

import os
from dataclasses import replace

import pytest
from helpers.fuzzing import oracle_settings
from helpers.sat_families import assert_optimum, dijkstra, families, plan_cost, selections
from hypothesis import given
from hypothesis import strategies as st

from mega_sat.deadline import Deadline
from mega_sat.ground.family import GroundFamily
from mega_sat.options import Options
from mega_sat.planners.node_planner import (
    ForkedSearch,
    NodePlanner,
    explicit_side,
    explicit_steps,
)
from mega_sat.planners.tiered_opt import TieredOpt
from mega_sat.search.astar import (
    _uniform_cost,
    astar,
    astar_steps,
    blind_and_lmcut_steps,
    uniform_cost_steps,
)


@pytest.mark.parametrize("forked", [True, False])
@pytest.mark.parametrize("search", ["whole", "relevant-vector"])
@oracle_settings(40, suppress_health_check=())
@given(fam=families(), data=st.data())
def test_portfolio_gives_the_optimum(forked: bool, search: str, fam: GroundFamily, data):
    if forked and not hasattr(os, "fork"):
        pytest.skip("no fork here")
    opts = Options(race_processes=forked, race_first_conflicts=1)
    if search == "relevant-vector":
        opts = replace(opts, race_search_relevant_part=True, race_search_vector_work=0.0005)
    planner = NodePlanner(None, fam, "portfolio", options=opts)
    for _ in range(3):
        sel = data.draw(selections(fam.n_updates))
        r = planner.optimal(sel)
        # "portfolio" itself answers only where the goal holds initially (no race needed)
        assert r.exact and (r.planner in ("builtin", "sat") or r.plan == ())
        assert_optimum(fam.specialize(sel), r.status, r.cost, r.plan)


@oracle_settings(30, suppress_health_check=())
@given(fam=families(), data=st.data())
def test_tiered_stats_name_the_method_that_answered(fam: GroundFamily, data):
    tiers = TieredOpt(fam, NodePlanner(None, fam, "portfolio"))
    for _ in range(3):
        tiers.optimal(data.draw(selections(fam.n_updates)))
    keys = ("opt_planner_builtin", "opt_planner_sat", "opt_planner_portfolio")
    assert sum(tiers.stats.get(k, 0) for k in keys) == tiers.stats["opt_by_planner"]


@oracle_settings(40, suppress_health_check=())
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
    child = ForkedSearch(task, 7.0)
    try:
        status, plan, cost, method = child.result(30.0)
        done, work = child.progress(1 << 40, Deadline.after(30.0))
    finally:
        child.stop()
    assert status == "optimal" and cost == dijkstra(task) and plan_cost(task, plan) == cost
    steps = explicit_steps(task, 7.0)
    try:
        while True:
            next(steps)
    except StopIteration as end:
        here = end.value
    assert done and (work, method) == (int(here[3]), here[4])


@oracle_settings(40, suppress_health_check=())
@given(fam=families(), data=st.data())
def test_paused_astar_answers_like_astar(fam: GroundFamily, data):
    task = fam.specialize(data.draw(selections(fam.n_updates)))
    h = data.draw(st.sampled_from(["lmcut", "hmax"]))
    steps = astar_steps(task, *_ends(task), h, every=1)
    try:
        while True:
            next(steps)
    except StopIteration as done:
        status, plan, cost, expanded, _ = done.value
    r = astar(task, heuristic=h)
    assert (status, plan, cost, expanded) == (r.status, r.plan, r.cost, r.expanded)


@oracle_settings(60, suppress_health_check=())
@given(fam=families(), data=st.data())
def test_blind_and_lmcut_by_turns_give_the_optimum(fam: GroundFamily, data):
    """Whichever of the two searches ends first, its answer is the optimum (or a proof that
    there is no plan); the turns follow work alone, so a second run ends the same way."""
    task = fam.specialize(data.draw(selections(fam.n_updates)))
    weight = data.draw(st.sampled_from([0.01, 1.0, 5.0, 1000.0]))
    ends = []
    for _ in range(2):
        steps = blind_and_lmcut_steps(task, *_ends(task), weight)
        try:
            while True:
                next(steps)
        except StopIteration as done:
            ends.append(done.value)
    status, plan, cost, _, method = ends[0]
    assert ends[0] == ends[1]
    assert method in ("uniform-cost search", "A* with LM-cut")
    assert_optimum(task, status, cost, plan)


def test_lmcut_answers_where_blind_search_is_hopeless():
    """A chain of 14 switches, each free to toggle, and a goal at the far end: blind search
    meets 2^14 states, A* with LM-cut walks straight to the goal."""
    from mega_sat.ground.family import GroundTask, StripsAction

    n, f = 14, frozenset
    atoms = tuple(("at", str(i)) for i in range(n + 1)) + tuple(("on", str(i)) for i in range(n))
    acts = [StripsAction(i, "go", (str(i),), f({i}), f(), f({i + 1}), f({i}), 5) for i in range(n)]
    acts += [
        StripsAction(n + i, "flip", (str(i),), f(), f(), f({n + 1 + i}), f(), 1) for i in range(n)
    ]
    task = GroundTask(atoms, tuple(acts), f({0}), f({n}))
    steps = blind_and_lmcut_steps(task, *_ends(task), 5.0)
    try:
        while True:
            next(steps)
    except StopIteration as done:
        status, plan, cost, _, method = done.value
    assert (status, cost, method) == ("optimal", 5 * n, "A* with LM-cut")


def _ends(task):
    return sum(1 << p for p in task.init), sum(1 << p for p in task.goal)


def _switches(n: int):
    """``n`` switches, each turned on once at cost 1, and a goal of all on: uniform-cost
    search expands the 2^n - 1 states short of the goal."""
    from mega_sat.ground.family import GroundTask, StripsAction

    f = frozenset
    acts = tuple(StripsAction(i, "on", (str(i),), f(), f({i}), f({i}), f(), 1) for i in range(n))
    return GroundTask(tuple(("on", str(i)) for i in range(n)), acts, f(), f(range(n)))


def test_the_explicit_side_searches_the_relevant_part():
    """A walk along a corridor that marks each cell visited, a mark nothing reads: with
    ``race_search_relevant_part`` the explicit side searches the corridor alone (states:
    positions, not positions times marks), and its plan runs in the task at the optimal
    cost."""
    from mega_sat.ground.family import GroundTask, StripsAction
    from mega_sat.ground.relevance import relevant_part

    n, f = 30, frozenset
    at, seen = list(range(n)), list(range(n, 2 * n))
    acts = []
    for i in range(n - 1):
        for a, b in ((i, i + 1), (i + 1, i)):
            acts.append(StripsAction(len(acts), "go", (str(a), str(b)), f({at[a]}), f(),
                                     f({at[b], seen[b]}), f({at[a]}), 1))  # fmt: skip
    atoms = tuple(("at", str(i)) for i in range(n)) + tuple(("seen", str(i)) for i in range(n))
    task = GroundTask(atoms, tuple(acts), f({at[0]}), f({at[n - 1]}))
    part = relevant_part(task)
    assert part.goal == task.goal and len(part.actions) == len(task.actions)

    def run(steps):
        try:
            while True:
                next(steps)
        except StopIteration as done:
            return done.value

    searched, _, _ = explicit_side(task, Options(race_search_relevant_part=True))
    assert explicit_side(task, Options())[0] is task  # the default: the whole model
    ours = run(explicit_steps(searched, 1e9))
    whole = run(blind_and_lmcut_steps(task, *_ends(task), 1e9))
    assert ours == run(blind_and_lmcut_steps(part, *_ends(part), 1e9))
    assert ours[3] < whole[3]  # fewer states than the search on the whole task
    assert ours[2] == whole[2] == n - 1 == plan_cost(task, ours[1])


@pytest.mark.parametrize("forked", [True, False])
def test_the_explicit_side_options_reach_its_search(monkeypatch, forked: bool):
    """``race_search_vector_work`` and ``race_search_relevant_part`` reach the explicit
    side, forked or in turns: the vectorised expansion's weight is the option times actions
    times words of the searched (relevant) part, at most 1."""
    from helpers.minitasks import usar_like

    import mega_sat.planners.node_planner as np_mod
    from mega_sat.ground.grounding import ground
    from mega_sat.ground.relevance import relevant_part

    if forked and not hasattr(os, "fork"):
        pytest.skip("no fork here")
    seen = []
    real, real_child = np_mod.explicit_steps, np_mod.ForkedSearch

    def spy(task, lmcut_weight, vector_weight=1.0):
        seen.append((vector_weight, task))
        return real(task, lmcut_weight, vector_weight)

    def child_spy(task, lmcut_weight, vector_weight=1.0):
        seen.append((vector_weight, task))
        return real_child(task, lmcut_weight, vector_weight)

    monkeypatch.setattr(np_mod, "explicit_steps", spy)
    monkeypatch.setattr(np_mod, "ForkedSearch", child_spy)
    fam = ground(usar_like())
    opts = Options(race_processes=forked, race_search_vector_work=0.001,
                   race_search_relevant_part=True)  # fmt: skip
    planner = NodePlanner(None, fam, "portfolio", options=opts)
    r = planner.optimal(frozenset())
    assert r.cost == dijkstra(fam.specialize(frozenset()))
    part = relevant_part(fam.specialize(frozenset()))
    mutable = {p for a in part.actions for p in (*a.add, *a.delete)}
    weight = min(1.0, 0.001 * len(part.actions) * (-(-len(mutable) // 64)))
    assert 0 < weight < 1
    assert seen == [(weight, part)]  # forked: the child's arguments, taken in this process
    assert np_mod.vector_weight(part, replace(opts, race_search_vector_work=0)) == 1.0


def test_vectorised_expansions_count_at_their_weight_in_the_turns_and_the_child():
    """Past ``VECTOR_AFTER`` expansions uniform-cost search runs vectorised, and each
    expansion counts ``vector_weight`` of work (``uniform_cost_work``): in the turns with
    LM-cut and in the work the forked child reports to the referee.  LM-cut's one turn here
    costs 10^9, so uniform-cost search runs through and the work splits exactly."""
    from mega_sat.search.astar import VECTOR_AFTER, uniform_cost_work

    task = _switches(13)
    ends = {}
    for w in (1.0, 0.1):
        steps = explicit_steps(task, 1e9, w)
        try:
            while True:
                next(steps)
        except StopIteration as done:
            ends[w] = done.value
    status, plan, cost, whole, method = ends[1.0]
    assert (status, cost, method) == ("optimal", 13, "uniform-cost search")
    assert ends[0.1][:3] == ends[1.0][:3] and ends[0.1][4] == method
    turns, expanded = divmod(whole, 1e9)
    assert turns >= 1 and expanded > VECTOR_AFTER
    assert ends[0.1][3] == turns * 1e9 + uniform_cost_work(int(expanded), 0.1)
    if not hasattr(os, "fork"):
        return
    child = ForkedSearch(task, 1e9, 0.1)
    try:
        assert child.result(30.0)[:3] == ends[0.1][:3]
        done, work = child.progress(1 << 62, Deadline.after(30.0))
    finally:
        child.stop()
    assert done and work == int(ends[0.1][3])


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


def test_side_work_counts_vectorised_expansions_at_their_weight():
    """SAT OPT's lowered-cost search counts on SAT's side of the race: its first 2048
    expansions (pure Python) count 1 each, the vectorised ones after them
    ``Options.race_side_vector_weight`` each."""
    from pathlib import Path

    from mega_sat.ground.grounding import ground
    from mega_sat.pddl.loading import load_task_dir
    from mega_sat.sat.oracles import SatOracles
    from mega_sat.search.astar import uniform_cost_work

    root = Path(__file__).resolve().parent.parent
    fam = ground(load_task_dir(root / "domains" / "rover-martian" / "delta" / "2" / "p3"))
    side = {}
    for weight in (1.0, 0.1):
        orc = SatOracles(fam, options=Options(race_side_vector_weight=weight))
        orc.opt_oracle.tighten_extra(fam.robot_selection)
        side[weight] = orc.solving.side_work
    assert side[1.0] > 2048  # the search went past its pure-Python start
    assert side[0.1] == pytest.approx(uniform_cost_work(int(side[1.0]), 0.1))
    assert side[0.1] == pytest.approx(2048 + 0.1 * (side[1.0] - 2048))


def _fd_or_skip():
    from mega_sat.planners.fast_downward import fd_available

    if not fd_available() or not hasattr(os, "fork"):
        pytest.skip("needs Fast Downward (the fd extra) and fork")


@oracle_settings(8, suppress_health_check=())
@given(fam=families(), data=st.data())
def test_fast_downward_on_a_ground_family_gives_the_optimum(fam: GroundFamily, data):
    """The race hands FD the ground model when it has no lifted task (negative
    preconditions compiled away, FD's names mapped back onto the family's steps)."""
    _fd_or_skip()
    planner = NodePlanner(None, fam, "fd")
    for _ in range(2):
        sel = data.draw(selections(fam.n_updates))
        r = planner.optimal(sel)
        task = fam.specialize(sel)
        assert_optimum(task, r.status, r.cost, r.plan)


def _no_deletes_model():
    """blocks-no-deletes' hard model: its optimum 16 takes SAT and the pure-Python LM-cut
    search many seconds, Fast Downward about one."""
    from mega_sat import api
    from mega_sat.ground.grounding import ground

    task = api.load_task_dir(
        os.path.join(os.path.dirname(__file__), "..", "bench", "tasks", "blocks-no-deletes")
    )
    five = {
        "remove-has-initial-state-clear c",
        "remove-has-initial-state-clear g",
        "add-stack-has-precondition-clear ?y",
        "add-unstack-has-precondition-on ?x ?y",
        "add-unstack-has-delete-effect-clear ?x",
    }
    sel = frozenset(i for i, u in enumerate(task.delta) if u.name in five)
    assert len(sel) == 5
    return task, ground(task), sel


def test_a_stuck_race_goes_to_fast_downward_at_a_point_fixed_by_work():
    _fd_or_skip()
    task, fam, sel = _no_deletes_model()
    # an optimal plan to start from, as the loop's earlier answers give SAT: the race may
    # hand a call to FD only while SAT holds a plan of the model (SAT alone needs about 17 s
    # to find a first one here)
    known = NodePlanner(task, fam, "fd").optimal(sel)
    assert (known.status, known.cost) == ("optimal", 16)
    runs = []
    for _ in range(2):
        planner = NodePlanner(task, fam, "portfolio", options=Options(race_fd_after_work=5000))
        planner.oracles.opt_oracle._plans.append(known.plan)
        r = planner.optimal(sel)
        assert (r.status, r.cost, r.planner, r.exact) == ("optimal", 16, "fd", True)
        # FD proved the cost of the plan SAT held, which is kept
        assert r.reason.startswith("Fast Downward, after ") and r.reason.endswith("SAT's plan")
        assert r.plan == known.plan
        runs.append((r.plan, r.reason))
    assert runs[0] == runs[1]  # the same plan, handed over at the same work


def test_a_failing_fast_downward_leaves_the_race_to_answer(monkeypatch):
    _fd_or_skip()
    from mega_sat import api
    from mega_sat.errors import PlannerError
    from mega_sat.ground.grounding import ground

    task = api.load_task_dir(
        os.path.join(
            os.path.dirname(__file__), "..", "domains", "rover-martian", "delta", "10", "p3"
        )
    )
    fam = ground(task)
    sels = [frozenset(range(0, len(task.delta), k)) for k in (1, 2, 3, 5)] + [frozenset()]
    without = NodePlanner(task, fam, "portfolio", options=Options(race_fd_after_work=0))
    optima = [without.optimal(sel).cost for sel in sels]
    calls = []

    def failing(self, sel, task, call):
        calls.append(sel)
        raise PlannerError("Fast Downward failed (exit code 1): simulated")

    monkeypatch.setattr(NodePlanner, "_fd", failing)
    planner = NodePlanner(task, fam, "portfolio", options=Options(race_fd_after_work=1))
    got = [planner.optimal(sel) for sel in sels]
    assert calls, "no race was handed to FD: the test checks nothing"
    assert [r.cost for r in got] == optima
    assert all(r.exact and r.planner in ("builtin", "sat") for r in got)


@oracle_settings(30, suppress_health_check=())
@given(fam=families(), data=st.data())
def test_opt_says_when_it_holds_a_plan(fam: GroundFamily, data):
    """The race hands a call to FD only while ``OptOracle.descent`` says SAT holds a plan of
    the model: never for a model without one, and the plan it holds at the end is the
    answer's."""
    from mega_sat.sat.oracles import SatOracles

    orc = SatOracles(fam)
    for _ in range(3):
        sel = frozenset(data.draw(selections(fam.n_updates)))
        if orc.opt_oracle.cached(sel) is not None:
            continue
        r = orc.opt(sel)
        held = orc.opt_oracle.descent
        assert held is None or held[0] == sel  # never another model's plan
        if r.status != "optimal":
            assert held is None
        elif held is not None:
            assert held[2] == r.cost and plan_cost(fam.specialize(sel), held[1]) == r.cost


def test_a_race_without_a_plan_goes_to_fast_downward_once_the_greedy_search_finds_one():
    """SAT holds no plan of the hard model here (it needs about 17 s for one), but the
    greedy search finds one at once: the race goes to FD at the same point twice."""
    _fd_or_skip()
    task, fam, sel = _no_deletes_model()
    runs = []
    for _ in range(2):
        planner = NodePlanner(task, fam, "portfolio", options=Options(race_fd_after_work=5000))
        r = planner.optimal(sel)
        assert planner.oracles.opt_oracle.descent is None  # SAT held no plan
        assert (r.status, r.cost, r.planner, r.exact) == ("optimal", 16, "fd", True)
        assert r.reason.startswith("Fast Downward, after ") and "SAT's plan" not in r.reason
        assert plan_cost(fam.specialize(sel), r.plan) == 16  # (the known optimum)
        runs.append((r.plan, r.reason))
    assert runs[0] == runs[1]


def test_fast_downward_gets_only_races_on_models_with_a_plan(monkeypatch):
    """With the greedy search finding nothing, FD is handed a race only while SAT holds a
    plan of that model (FD fails here, so the race answers as without it)."""
    _fd_or_skip()
    from mega_sat import api
    from mega_sat.errors import PlannerError
    from mega_sat.ground.grounding import ground

    task = api.load_task_dir(
        os.path.join(
            os.path.dirname(__file__), "..", "domains", "rover-martian", "delta", "10", "p3"
        )
    )
    fam = ground(task)
    monkeypatch.setattr("mega_sat.search.greedy.greedy_plan", lambda *args: None)
    handed = []

    def failing(self, sel, task, call):
        held = self.oracles.opt_oracle.descent
        handed.append(held is not None and held[0] == sel)
        raise PlannerError("Fast Downward failed (exit code 1): simulated")

    monkeypatch.setattr(NodePlanner, "_fd", failing)
    planner = NodePlanner(task, fam, "portfolio", options=Options(race_fd_after_work=1))
    sels = [frozenset(range(0, len(task.delta), k)) for k in (1, 2, 3, 5)] + [frozenset()]
    for sel in sels:
        assert planner.optimal(sel).exact
    assert handed and all(handed)
