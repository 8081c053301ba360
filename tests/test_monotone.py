"""Monotone updates (``mega_sat/analysis/monotone.py``) against brute force on random families:
moving one update to its restricting value never adds a plan or lowers a plan's cost, never
lowers the optimum, and never creates a joint plan within given bounds.

The loop's cores drop literals on exactly this claim (encodings/hitting-set.md, "Monotone
updates"), so a wrong direction would make it learn clauses that cut off solutions."""

from __future__ import annotations

from helpers.fuzzing import oracle_settings
from helpers.sat_families import (
    dijkstra,
    families,
    joint_brute,
    plan_cost,
    random_run,
    selections,
)
from hypothesis import given
from hypothesis import strategies as st

from mega_sat.analysis.monotone import drop_relaxing, drop_restricting, restricting_values
from mega_sat.ground.family import GroundAction, GroundFamily


@oracle_settings(3000, suppress_health_check=())
@given(fam=families(max_atoms=3, max_actions=6, max_updates=4), data=st.data())
def test_the_restricting_value_gives_a_sub_model(fam: GroundFamily, data):
    restricting = restricting_values(fam)
    if not restricting:
        return
    i = data.draw(st.sampled_from(sorted(restricting)))
    w = restricting[i]
    sel = data.draw(selections(fam.n_updates))
    loose = sel - {i} if w else sel | {i}  # i at the relaxing value
    tight = sel | {i} if w else sel - {i}  # i at the restricting value
    loose_task, tight_task = fam.specialize(loose), fam.specialize(tight)
    # every run of the tight model runs in the loose one, at no higher cost, and reaches
    # at least the goals the tight one asks for
    plan, _ = random_run(fam, tight, data, max_steps=6)
    tight_cost = plan_cost(tight_task, plan)
    if tight_cost is not None:
        loose_cost = plan_cost(loose_task, plan)
        assert loose_cost is not None and loose_cost <= tight_cost
    opt_tight, opt_loose = dijkstra(tight_task), dijkstra(loose_task)
    if opt_tight is not None:
        assert opt_loose is not None and opt_loose <= opt_tight
    for bound in (2, 4, 6):
        if joint_brute(fam, loose, None, bound) is None:
            assert joint_brute(fam, tight, None, bound) is None


def test_negative_preconditions_take_the_direction_of_effects_on_their_atoms():
    """An add effect relaxes, unless the atom is tested by a negative precondition: then
    adding it may disable an action, and the update has no direction."""
    add_p0 = GroundAction("a", (), None, (), (), ((0, (0, True)),), (), (((), 1),))
    plain = GroundFamily(atoms=(("p0",), ("p1",)), n_updates=1, actions=(add_p0,), init=(), goal=())
    assert restricting_values(plain) == {0: False}
    tests_p0 = GroundAction("b", (), None, (), ((0, None),), ((1, None),), (), (((), 1),))
    neg = GroundFamily(
        atoms=(("p0",), ("p1",)), n_updates=1, actions=(add_p0, tests_p0), init=(), goal=()
    )
    assert restricting_values(neg) == {}


def test_costs_give_a_direction_only_when_every_context_agrees():
    cheap_when_selected = (((0, True),), 1), (((0, False),), 3)
    a = GroundAction("a", (), None, (), (), (), (), cheap_when_selected)
    fam = GroundFamily(atoms=(("p0",),), n_updates=1, actions=(a,), init=(), goal=())
    assert restricting_values(fam) == {0: False}
    # with update 1 selected, update 0 makes it dearer instead: no direction for 0
    mixed = (
        (((0, True), (1, False)), 1),
        (((0, False), (1, False)), 3),
        (((0, True), (1, True)), 5),
        (((0, False), (1, True)), 2),
    )
    b = GroundAction("b", (), None, (), (), (), (), mixed)
    fam2 = GroundFamily(atoms=(("p0",),), n_updates=2, actions=(b,), init=(), goal=())
    assert 0 not in restricting_values(fam2)


def test_cores_keep_the_restricting_side_and_supports_the_relaxing_side():
    restricting = {0: True, 1: False}
    lits = [(0, True), (0, False), (1, True), (1, False), (2, True)]
    assert drop_relaxing(lits, restricting) == {(0, True), (1, False), (2, True)}
    assert drop_restricting(lits, restricting) == {(0, False), (1, True), (2, True)}
