"""The family encoding alone: SAT at horizon h iff a plan of <= h steps exists (with a cost
bound: of <= h steps and cost <= B), on random families and selections, in every variant."""

from __future__ import annotations

import heapq
import itertools

import pytest
from helpers.fuzzing import oracle_settings
from helpers.sat_families import check_bounded_answer, families, plan_cost, selections
from hypothesis import given
from hypothesis import strategies as st
from pysat.solvers import Solver

from mega_sat.ground.family import GroundFamily, GroundTask
from mega_sat.sat.encoding import HUMAN, ROBOT, FamilyEncoding

SETTINGS = oracle_settings(120)


def cheapest_within(task: GroundTask, h: int) -> int | None:
    """Minimum cost of a plan with at most ``h`` steps (None: none)."""
    start = (frozenset(task.init), 0)
    best = {start: 0}
    heap = [(0, 0, start)]
    tie = itertools.count()
    while heap:
        c, _, (s, n) = heapq.heappop(heap)
        if c > best[(s, n)]:
            continue
        if task.goal <= s:
            return c
        if n == h:
            continue
        for a in task.actions:
            if a.pre <= s and not a.negpre & s:
                node = ((s - a.delete) | a.add, n + 1)
                if c + a.cost < best.get(node, 1 << 60):
                    best[node] = c + a.cost
                    heapq.heappush(heap, (c + a.cost, next(tie), node))
    return None


VARIANTS = [
    dict(),
    dict(symmetry_breaking=False),
    dict(partial_order=True),
    dict(unary_max_units=0),  # binary cost sums and comparators on small costs
]


@pytest.mark.parametrize("variant", VARIANTS, ids=["default", "no-symmetry", "por", "binary"])
@SETTINGS
@given(fam=families(min_cost=0), data=st.data())
def test_sat_iff_bounded_plan(variant, fam: GroundFamily, data):
    with Solver(name="cadical195") as solver:
        enc = FamilyEncoding(fam, solver.add_clause, **variant)
        for _ in range(3):
            sel = data.draw(selections(fam.n_updates))
            task = fam.specialize(sel)
            h = data.draw(st.integers(0, 4))
            bound = data.draw(st.one_of(st.none(), st.integers(0, 6)))
            cost_lits = enc.cost_assumptions(HUMAN, bound, h)
            lits = enc.selection_assumptions(sel) + enc.goal_assumptions(h) + cost_lits
            best = cheapest_within(task, h)
            check_bounded_answer(solver, enc, task, lits, h, best, bound)


@SETTINGS
@given(fam=families(), data=st.data())
def test_two_copies_need_both_models(fam: GroundFamily, data):
    """With both copies a plan must be valid in the robot model and in human + E."""
    robot = fam.specialize(fam.robot_selection)
    with Solver(name="cadical195") as solver:
        enc = FamilyEncoding(fam, solver.add_clause, copies=(HUMAN, ROBOT))
        sel = data.draw(selections(fam.n_updates))
        h = data.draw(st.integers(0, 3))
        lits = enc.selection_assumptions(sel) + enc.goal_assumptions(h)
        if solver.solve(assumptions=lits):
            plan = enc.decode_plan(solver.get_model(), h)
            assert plan_cost(robot, plan) is not None
            assert plan_cost(fam.specialize(sel), plan) is not None
        else:
            human = fam.specialize(sel)
            steps = [a.step for a in fam.actions]
            for n in range(h + 1):
                for plan in itertools.product(steps, repeat=n):
                    assert plan_cost(robot, plan) is None or plan_cost(human, plan) is None


def test_var_map_and_size():
    fam = GroundFamily(
        atoms=(("at", "p1"), ("at", "p2")), n_updates=1, actions=(), init=(), goal=()
    )
    from mega_sat.ground.family import GroundAction

    act = GroundAction(
        "move", ("p1", "p2"), None, ((0, None),), (), ((1, None),), ((0, (0, True)),), (((), 2),)
    )
    fam = GroundFamily(fam.atoms, 1, (act,), ((0, None),), ((1, None),))
    clauses: list[list[int]] = []
    enc = FamilyEncoding(fam, clauses.append)
    enc.extend(2)
    enc.goal_assumptions(2)
    names = enc.var_map()
    assert names[enc.a(1, 0)] == "a[1]=(move p1 p2)"
    assert names[enc.x(HUMAN, 2, 1)] == "x[human][2](at p2)"
    assert names[enc.e(0)] == "e[0]"
    assert enc.size().clauses == len(clauses) and enc.size().horizon == 2
    assert enc.cost_unit == 2 and enc.max_units == 1


def test_bad_copies():
    fam = GroundFamily((), 0, (), (), ())
    with pytest.raises(ValueError):
        FamilyEncoding(fam, lambda c: None, copies=("human", "human"))


def test_guarded_mutexes_wait_for_a_longer_encoding_then_cover_every_layer():
    """The guarded mutexes (up to two h^2 computations per update) are computed only once the
    encoding reaches ``GUARDED_FROM_STEPS`` steps, and then added to every human state layer,
    the earlier ones included.  rover-martian/p3 has some."""
    from pathlib import Path

    from mega_sat.ground.grounding import ground
    from mega_sat.pddl.loading import load_task, resolve_task_dir
    from mega_sat.sat.encoding import GUARDED_FROM_STEPS, _state_lit

    root = Path(__file__).resolve().parents[1] / "domains" / "rover-martian" / "p3"
    fam = ground(load_task(**resolve_task_dir(str(root))))
    clauses: list[list[int]] = []
    enc = FamilyEncoding(fam, clauses.append)
    enc.extend(GUARDED_FROM_STEPS - 1)
    assert "guarded" not in vars(enc.facts)  # not computed yet
    enc.extend(GUARDED_FROM_STEPS + 1)
    guarded = enc.facts.guarded
    assert guarded
    have = {tuple(sorted(c)) for c in clauses}
    for layer in range(1, enc.horizon + 1):
        xl = enc.x_base[HUMAN][layer]
        for g, l1, l2 in guarded:
            assert tuple(sorted((-g, _state_lit(xl, l1), _state_lit(xl, l2)))) in have
