"""The supports of a plan (``mega_sat/engines/support.py``) against brute force: every
selection that agrees with a support runs the plan, reaches the goal and pays the same cost.

The learned clauses of the hitting-set loop are sound only if this holds (encodings/hitting-set.md,
"The tight support" and "The causal support").  A failure core is the other way round: the plan
fails in every selection that agrees with it."""

from __future__ import annotations

from dataclasses import replace

from helpers.fuzzing import oracle_settings
from helpers.sat_families import agreeing, families, guards, plan_cost, random_run, selections
from hypothesis import given
from hypothesis import strategies as st

from mega_sat.engines.support import causal_support, failure_core, tight_support
from mega_sat.ground.family import GroundFamily, holds


@oracle_settings(400, suppress_health_check=())
@given(fam=families(max_atoms=3, max_actions=6, max_updates=4), data=st.data())
def test_supports_keep_the_plan_running_at_the_same_cost(fam: GroundFamily, data):
    sel = data.draw(selections(fam.n_updates))
    plan, end = random_run(fam, sel, data)
    if not all(p in end for p, g in fam.goal if holds(g, sel)):
        # the supports are defined for plans: ask for atoms the run reaches instead
        reached = sorted(end)
        goal = data.draw(st.lists(st.sampled_from(reached), max_size=3)) if reached else []
        fam = replace(fam, goal=tuple((p, data.draw(guards(fam.n_updates))) for p in goal))
        if not all(p in end for p, g in fam.goal if holds(g, sel)):
            return
    cost = plan_cost(fam.specialize(sel), plan)
    assert cost is not None
    tight, causal = tight_support(fam, sel, plan), causal_support(fam, sel, plan)
    assert set(causal) <= set(tight)
    for lits in (tight, causal):
        assert all((i in sel) == v for i, v in lits)
        for other in agreeing(lits, fam.n_updates):
            assert plan_cost(fam.specialize(other), plan) == cost, (lits, other)


@oracle_settings(400, suppress_health_check=())
@given(fam=families(max_atoms=3, max_actions=6, max_updates=4), data=st.data())
def test_a_failure_core_fails_the_plan_in_every_selection_agreeing_with_it(fam: GroundFamily, data):
    """MCE excludes a candidate where the fixed plan fails by NOT(failure core): sound only if
    the plan fails in every selection that agrees with the core."""
    plan, _ = random_run(fam, data.draw(selections(fam.n_updates)), data)
    sel = data.draw(selections(fam.n_updates))  # another model, where the plan may fail
    core = failure_core(fam, sel, plan)
    assert (core is None) == (plan_cost(fam.specialize(sel), plan) is not None)
    if core is None:
        return
    assert all((i in sel) == v for i, v in core)
    for other in agreeing(core, fam.n_updates):
        assert plan_cost(fam.specialize(other), plan) is None, (core, other)


def test_causal_support_drops_effects_no_condition_reads():
    """A delete that the plan's conditions never read after it is free to flip."""
    from mega_sat.ground.family import GroundAction

    # a0 needs p0, adds p1 and (under update 0) deletes p0; the goal is p1 alone
    fam = GroundFamily(
        atoms=(("p0",), ("p1",)),
        n_updates=1,
        actions=(
            GroundAction(
                "a0", ("o",), None, ((0, None),), (), ((1, None),), ((0, (0, True)),), (((), 1),)
            ),
        ),
        init=((0, None),),
        goal=((1, None),),
    )
    plan = (("a0", "o"),)
    assert tight_support(fam, frozenset(), plan) == ((0, False),)
    assert causal_support(fam, frozenset(), plan) == ()
