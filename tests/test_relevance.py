"""Backward relevance (mega_sat/ground/relevance.py) against explicit search on random tasks and
random families: the reduced task has the same optimum and its plans run in the whole task;
the may-reachability tests (tests/test_may_reachability.py) check the projection of its states."""

from __future__ import annotations

from helpers.fuzzing import oracle_settings
from helpers.sat_families import dijkstra, families, selections
from hypothesis import given
from hypothesis import strategies as st
from test_vector_search import strips_tasks

from mega_sat.ground.family import GroundTask, StripsAction
from mega_sat.ground.relevance import may_relevant_atoms, relevant_atoms, relevant_part
from mega_sat.ground.simulate import ground_plan_cost
from mega_sat.search.astar import astar
from mega_sat.search.vector_search import goal_reachable
from mega_sat.status import Status

SETTINGS = oracle_settings(300)


@SETTINGS
@given(strips_tasks())
def test_the_relevant_part_keeps_the_optimum_and_its_plans_run_in_the_task(task: GroundTask):
    part = relevant_part(task)
    assert dijkstra(part) == dijkstra(task)
    assert part.goal == task.goal and part.init <= task.init
    whole = {a.index: a for a in task.actions}
    for a in part.actions:
        b = whole[a.index]
        assert (a.pre, a.negpre, a.cost) == (b.pre, b.negpre, b.cost)
        assert a.add <= b.add and a.delete <= b.delete
    r = astar(part, heuristic="blind")
    if r.status == Status.OPTIMAL:
        assert ground_plan_cost(task, r.plan) == r.cost == dijkstra(task)
    else:
        assert r.status == Status.UNSOLVABLE and dijkstra(task) is None


@SETTINGS
@given(fam=families(max_atoms=5, max_actions=7), data=st.data())
def test_the_may_relevant_atoms_cover_the_model_itself(fam, data):
    sel = data.draw(selections(fam.n_updates))
    assert relevant_atoms(fam.specialize(sel)) <= may_relevant_atoms(fam, sel)


def _act(i, pre=(), neg=(), add=(), delete=(), cost=1) -> StripsAction:
    return StripsAction(
        i, f"a{i}", (), frozenset(pre), frozenset(neg), frozenset(add), frozenset(delete), cost
    )


def test_flags_nothing_reads_are_dropped_and_shrink_the_search():
    # a robot walks a line 0..9; each step also flips a photo flag (atoms 10..19) no goal or
    # condition mentions: 2^10 times the states, none of them needed
    at = list(range(10))
    flags = list(range(10, 20))
    acts = [_act(i, pre=[at[i]], add=[at[i + 1], flags[i]], delete=[at[i]]) for i in range(9)] + [
        _act(9 + i, add=[flags[i]]) for i in range(10)
    ]
    task = GroundTask(
        tuple((f"p{i}",) for i in range(20)), tuple(acts), frozenset({at[0]}), frozenset({at[9]})
    )
    part = relevant_part(task)
    assert relevant_atoms(task) == frozenset(at)
    assert len(part.actions) == 9
    assert all(not (a.add | a.delete) & set(flags) for a in part.actions)
    assert goal_reachable(task) == (Status.PLAN, 9)
    # without the last step nothing reaches the goal atom: proven at the initial state
    blocked = GroundTask(task.atoms, task.actions[:8] + task.actions[9:], task.init, task.goal)
    assert goal_reachable(blocked) == (Status.UNSOLVABLE, 1)
    assert dijkstra(part) == dijkstra(task) == 9


def test_actions_whose_conditions_contradict_each_other_are_dropped():
    task = GroundTask(
        (("p",), ("g",)),
        (_act(0, pre=[0], neg=[0], add=[1]), _act(1, add=[0])),
        frozenset(),
        frozenset({1}),
    )
    part = relevant_part(task)
    assert part.actions == () and dijkstra(task) is None
