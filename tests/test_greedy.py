"""Greedy best-first search (mega_sat/search/greedy.py) against brute force on random models:
every plan it returns runs, it finds one wherever one exists given the budget of the whole
state space, and h_add is zero exactly on goal states and infinite only where the
relaxation says no plan exists."""

from __future__ import annotations

from helpers.fuzzing import oracle_settings
from helpers.sat_families import dijkstra, families, plan_cost, selections
from hypothesis import given
from hypothesis import strategies as st

from mega_sat.analysis.relaxation import RelaxedTask
from mega_sat.ground.family import GroundAction, GroundFamily
from mega_sat.search.greedy import greedy_plan, greedy_search

_INF = float("inf")


@oracle_settings(150, suppress_health_check=())
@given(fam=families(max_atoms=5, max_actions=7), data=st.data())
def test_a_plan_wherever_brute_force_finds_one(fam: GroundFamily, data):
    task = fam.specialize(data.draw(selections(fam.n_updates)))
    best = dijkstra(task)
    # 5 atoms: at most 32 states, each generated once, and the initial state's evaluation
    plan = greedy_plan(task, 2 + 2 ** len(task.atoms))
    if best is None:
        assert plan is None
    else:
        assert plan is not None
        cost = plan_cost(task, [a.step for a in plan])
        assert cost is not None and cost >= best


@oracle_settings(150, suppress_health_check=())
@given(fam=families(max_atoms=5, max_actions=7), data=st.data(), budget=st.integers(1, 40))
def test_no_plan_only_when_brute_force_finds_none(fam: GroundFamily, data, budget):
    """``greedy_search`` says "no plan" (False) only for models brute force finds unsolvable,
    and says it for each of them once its budget covers the whole state space; a budget that
    runs out first gives ``None`` (nothing proven)."""
    task = fam.specialize(data.draw(selections(fam.n_updates)))
    best = dijkstra(task)
    got = greedy_search(task, budget)
    if got is False:
        assert best is None
    elif got is not None:
        assert best is not None and plan_cost(task, [a.step for a in got]) is not None
    if best is None:
        assert greedy_search(task, 2 + 2 ** len(task.atoms)) is False


@oracle_settings(150, suppress_health_check=())
@given(fam=families(max_atoms=5, max_actions=7), data=st.data())
def test_h_add_is_zero_on_goals_and_infinite_only_without_a_relaxed_plan(fam, data):
    task = fam.specialize(data.draw(selections(fam.n_updates)))
    h = RelaxedTask(task).h_add
    state = sorted(data.draw(st.sets(st.integers(0, len(task.atoms) - 1))))
    got = h(state)
    if task.goal <= set(state):
        assert got == 0
    assert (got == _INF) == (RelaxedTask(task).lmcut(state) == _INF)
    if got != _INF:
        assert got >= RelaxedTask(task).h_max(state)  # h_add sums what h_max maximises


def _chain(n: int) -> GroundFamily:
    """Atoms p0..pn in a line, one action per link: the only plan has n steps."""
    acts = tuple(
        GroundAction(f"step{i}", (), None, ((i, None),), (), ((i + 1, None),), (), (((), 1),))
        for i in range(n)
    )
    atoms = tuple((f"p{i}",) for i in range(n + 1))
    return GroundFamily(atoms, 0, acts, ((0, None),), ((n, None),))


def test_the_budget_counts_evaluations_and_a_short_one_finds_nothing():
    task = _chain(6).specialize(frozenset())
    assert greedy_plan(task, 3) is None  # proves nothing: the plan needs 7 evaluations
    assert greedy_search(task, 3) is None
    plan = greedy_plan(task, 8)
    assert [a.name for a in plan] == [f"step{i}" for i in range(6)]


def _act(name, pre, add, delete=(), negpre=()):
    def entries(ps):
        return tuple((p, None) for p in ps)

    return GroundAction(
        name, (), None, entries(pre), entries(negpre), entries(add), entries(delete), (((), 1),)
    )


def test_h_add_sums_the_goal_atoms_costs():
    # goals g0 and g1, one action each from the initial atom, and g2 after both
    fam = GroundFamily(
        (("p",), ("g0",), ("g1",), ("g2",)),
        0,
        (_act("a", [0], [1]), _act("b", [0], [2]), _act("c", [1, 2], [3])),
        ((0, None),),
        ((1, None), (2, None), (3, None)),
    )
    h = RelaxedTask(fam.specialize(frozenset())).h_add
    assert h([0]) == 1 + 1 + 3  # g2: c's cost plus the sum of its preconditions' costs
    assert h([0, 1]) == 0 + 1 + 2


def test_a_deleted_atom_is_gone_from_the_successor():
    """``use`` deletes the atom ``finish`` needs: no plan exists, though a search that kept
    deleted atoms would find use, finish."""
    fam = GroundFamily(
        (("p",), ("q",), ("g",)),
        0,
        (_act("use", [0], [1], delete=[0]), _act("finish", [0, 1], [2])),
        ((0, None),),
        ((2, None),),
    )
    assert greedy_plan(fam.specialize(frozenset()), 100) is None
    assert greedy_search(fam.specialize(frozenset()), 100) is False  # every state expanded


def test_an_expired_deadline_ends_the_search():
    from mega_sat.deadline import Deadline

    task = _chain(6).specialize(frozenset())
    assert greedy_plan(task, 100, Deadline.after(1, elapsed=2)) is None  # expired
    assert greedy_search(task, 100, Deadline.after(1, elapsed=2)) is None  # proves nothing
    assert greedy_plan(task, 100, Deadline.after(60)) is not None
