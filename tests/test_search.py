"""The built-in optimal planner against an independent uniform-cost search."""

from __future__ import annotations

import heapq
import time

import pytest
from helpers.fuzzing import oracle_settings
from helpers.randomtasks import models, selections, two_model_tasks
from hypothesis import given
from hypothesis import strategies as st

from mega_sat.analysis.relaxation import RelaxedTask
from mega_sat.deadline import Deadline
from mega_sat.ground.family import GroundTask, StripsAction
from mega_sat.ground.grounding import ground, ground_model
from mega_sat.ground.simulate import simulate_ground
from mega_sat.search.astar import HEURISTICS, astar, bounded_search, solve_optimal
from mega_sat.status import Status


def dijkstra(task: GroundTask) -> int | None:
    """Optimal cost by plain uniform-cost search over frozenset states (no heuristic)."""
    start = frozenset(task.init)
    dist = {start: 0}
    heap = [(0, 0, start)]
    n = 0
    while heap:
        d, _, s = heapq.heappop(heap)
        if d > dist[s]:
            continue
        if task.goal <= s:
            return d
        for a in task.actions:
            if a.pre <= s and not (a.negpre & s):
                t = (s - a.delete) | a.add
                if d + a.cost < dist.get(t, d + a.cost + 1):
                    dist[t] = d + a.cost
                    n += 1
                    heapq.heappush(heap, (d + a.cost, n, t))
    return None


def check_all_heuristics(gt: GroundTask) -> None:
    expected = dijkstra(gt)
    for h in HEURISTICS:
        r = astar(gt, heuristic=h)
        if expected is None:
            assert r.status == "unsolvable" and r.plan is None and r.cost is None
            continue
        assert r.status == "optimal" and r.cost == expected, h
        sim = simulate_ground(gt, r.plan)
        assert sim.valid and sim.cost == expected
    if expected is not None:
        relaxed = RelaxedTask(gt)
        init = sorted(gt.init)
        assert relaxed.h_max(init) <= relaxed.lmcut(init) <= expected  # dominance, admissible


@oracle_settings(80, suppress_health_check=())
@given(data=st.data())
def test_astar_matches_uniform_cost_search(data):
    task = data.draw(two_model_tasks())
    fam = ground(task)
    for sel in (frozenset(), data.draw(selections(task))):
        check_all_heuristics(fam.specialize(sel))


@oracle_settings(60, suppress_health_check=())
@given(models(allow_zero_cost=True))
def test_astar_matches_uniform_cost_search_with_zero_cost_actions(model):
    check_all_heuristics(ground_model(model))


def chain(n: int, zero: bool) -> GroundTask:
    """Atoms 0..n-1; step i moves from i to i+1; a costly shortcut 0 -> n-1; with ``zero``
    a zero-cost detour loop that must not confuse the search."""
    acts = [
        StripsAction(
            i, "step", (str(i),), frozenset({i}), frozenset(), frozenset({i + 1}), frozenset({i}), 1
        )
        for i in range(n - 1)
    ]
    acts.append(
        StripsAction(
            n - 1,
            "jump",
            (),
            frozenset({0}),
            frozenset(),
            frozenset({n - 1}),
            frozenset({0}),
            n + 5,
        )
    )
    if zero:
        acts += [
            StripsAction(
                n + i,
                "back",
                (str(i),),
                frozenset({i + 1}),
                frozenset(),
                frozenset({i}),
                frozenset({i + 1}),
                0,
            )
            for i in range(n - 1)
        ]
    atoms = tuple(("at", str(i)) for i in range(n))
    return GroundTask(atoms, tuple(acts), frozenset({0}), frozenset({n - 1}))


@pytest.mark.parametrize("heuristic", HEURISTICS)
@pytest.mark.parametrize("zero", [False, True])
def test_chain_optimal_and_deterministic(heuristic, zero):
    gt = chain(8, zero)
    r1 = astar(gt, heuristic=heuristic)
    r2 = astar(gt, heuristic=heuristic)
    assert r1.status == "optimal" and r1.cost == 7
    assert r1.plan == tuple(("step", str(i)) for i in range(7))
    assert r1.plan == r2.plan and r1.expanded == r2.expanded
    assert r1.planner.startswith("builtin")


def test_lmcut_is_perfect_on_a_chain_and_blind_expands_more():
    gt = chain(8, True)
    assert RelaxedTask(gt).lmcut([0]) == 7
    assert astar(gt, heuristic="lmcut").expanded <= astar(gt, heuristic="blind").expanded


def test_unsolvable_and_limits():
    gt = chain(6, False)
    dead = GroundTask(gt.atoms, gt.actions, gt.init, frozenset({1, 3}) | {5})
    # the chain deletes as it goes: {1, 3, 5} is relaxed reachable but not reachable
    r = astar(dead, heuristic="lmcut")
    assert r.status == "unsolvable" and r.expanded > 0
    no_way = GroundTask(gt.atoms + (("x",),), gt.actions, gt.init, frozenset({6}))
    r = astar(no_way)
    assert r.status == "unsolvable" and r.expanded == 0  # h is infinite at the start
    r = astar(chain(30, True), heuristic="blind", node_limit=3)
    assert r.status is Status.LIMIT and r.plan is None and r.expanded == 3 and not r.exact
    r = astar(chain(30, True), heuristic="blind", deadline=Deadline(time.perf_counter()))
    assert r.status is Status.TIMEOUT and r.status == "timeout" and r.reason == "timeout"
    with pytest.raises(ValueError):
        astar(gt, heuristic="ff")


def test_negative_preconditions_respected():
    # a: 0 -> 1 needs not(2); b: adds 2 cheaply; the goal {1, 2} forces a before b
    acts = (
        StripsAction(0, "a", (), frozenset({0}), frozenset({2}), frozenset({1}), frozenset(), 1),
        StripsAction(1, "b", (), frozenset({0}), frozenset(), frozenset({2}), frozenset(), 1),
    )
    gt = GroundTask((("s",), ("p",), ("q",)), acts, frozenset({0}), frozenset({1, 2}))
    for h in HEURISTICS:
        assert astar(gt, heuristic=h).plan == (("a",), ("b",))


@st.composite
def token_tasks(draw) -> GroundTask:
    """k tokens moving on a random weighted digraph (edge costs 0-4), at most one token per
    node (a negative precondition), goal positions for some tokens: a few hundred reachable
    states with deletes, zero costs and dead ends."""
    n = draw(st.integers(4, 8))
    k = draw(st.integers(2, min(4, n - 1)))
    edges = draw(
        st.lists(
            st.tuples(st.integers(0, n - 1), st.integers(0, n - 1), st.integers(0, 4)),
            min_size=n,
            max_size=3 * n,
        )
    )
    atoms = [("at", str(t), str(v)) for t in range(k) for v in range(n)]
    atoms += [("occ", str(v)) for v in range(n)]
    ix = {a: i for i, a in enumerate(atoms)}
    acts = []
    for t in range(k):
        for u, v, c in sorted(set(edges)):
            if u == v:
                continue
            at_u, at_v = ix[("at", str(t), str(u))], ix[("at", str(t), str(v))]
            occ_u, occ_v = ix[("occ", str(u))], ix[("occ", str(v))]
            acts.append(
                StripsAction(
                    len(acts),
                    "move",
                    (str(t), str(u), str(v), str(c)),
                    frozenset({at_u}),
                    frozenset({occ_v}),
                    frozenset({at_v, occ_v}),
                    frozenset({at_u, occ_u}),
                    c,
                )
            )
    start = draw(st.permutations(range(n)))[:k]
    goal = draw(st.permutations(range(n)))[:k]
    init = {ix[("at", str(t), str(v))] for t, v in enumerate(start)}
    init |= {ix[("occ", str(v))] for v in start}
    goals = {ix[("at", str(t), str(v))] for t, v in enumerate(goal)}
    return GroundTask(tuple(atoms), tuple(acts), frozenset(init), frozenset(goals))


@oracle_settings(40, suppress_health_check=())
@given(token_tasks())
def test_astar_on_larger_state_spaces(gt):
    """Bigger spaces exercise reopening (LM-cut is not consistent) and the successor groups."""
    check_all_heuristics(gt)


@oracle_settings(40, suppress_health_check=())
@given(token_tasks(), st.integers(0, 12))
def test_bounded_search_finds_the_optimum_within_the_bound_or_proves_none(gt, bound):
    """The search the sat engine runs for a human plan below the robot optimum: within the
    bound it returns the optimum itself (the loop then skips OPT); above it, a proof that no
    plan costs that little (the loop raises its lower bound to the robot optimum)."""
    expected = dijkstra(gt)
    status, plan, cost = bounded_search(gt, bound, 10**6)
    if expected is None or expected > bound:
        assert (status, plan, cost) == (Status.INFEASIBLE, None, None)
    else:
        assert status == Status.OPTIMAL and cost == expected
        sim = simulate_ground(gt, plan)
        assert sim.valid and sim.cost == expected
    if not gt.goal <= gt.init:  # with no expansion allowed, only a goal start is answered
        assert bounded_search(gt, bound, 0)[0] in (Status.LIMIT, Status.INFEASIBLE)


def test_lmcut_admissible_on_a_shipped_family():
    """Regression: LM-cut once stopped h^max at the goal, leaving the justification graph
    partial, so its cuts were not landmarks (12 > 8 on usar-fetch Delta 10/p1 with E = {2, 5}).
    Checked against uniform-cost search on 64 models of that family."""
    import itertools
    from pathlib import Path

    from mega_sat.pddl.loading import load_task, resolve_task_dir

    root = Path(__file__).resolve().parent.parent / "domains" / "usar-fetch" / "delta" / "10" / "p1"
    task = load_task(**{k: str(v) for k, v in resolve_task_dir(root).items()})
    fam = ground(task)
    sels = [frozenset({2, 5})]
    sels += [frozenset(c) for c in itertools.combinations(range(fam.n_updates), 3)][::2][:63]
    for sel in sels:
        gt = fam.specialize(sel)
        r = astar(gt, heuristic="blind")
        h = RelaxedTask(gt).lmcut(sorted(gt.init))
        if r.status == "optimal":
            assert h <= r.cost, (sorted(sel), h, r.cost)
        else:
            assert r.status == "unsolvable"


def test_solve_optimal_switches_to_lmcut_after_blind_nodes():
    """``blind_nodes`` (Options.blind_nodes) is where the portfolio gives up on blind search;
    the answer is the same optimum either way."""
    task = chain(12, True)
    blind = solve_optimal(task)
    both = solve_optimal(task, blind_nodes=2)
    assert blind.planner == "builtin-astar(blind)" and both.planner == "builtin(blind+lmcut)"
    assert (blind.status, blind.cost) == (both.status, both.cost) == (Status.OPTIMAL, blind.cost)
    assert both.exact and both.expanded > 2
