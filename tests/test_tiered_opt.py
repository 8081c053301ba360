"""The tiers of the sat engine's OPT step (mega_sat/planners/tiered_opt.py) against brute force,
and the reachable-states tier on a model that only an exhaustive search proves unsolvable."""

from dataclasses import replace

from helpers.sat_families import all_selections, dijkstra, families, plan_cost
from hypothesis import HealthCheck, given, settings
from hypothesis import strategies as st

from mega_sat.ground.family import GroundAction, GroundFamily
from mega_sat.options import DEFAULT
from mega_sat.planners.node_planner import NodePlanner
from mega_sat.planners.tiered_opt import TieredOpt


def _two_of_three() -> GroundFamily:
    """Exactly two of the atoms a, b, c hold in every reachable state, and the goal asks for
    all three: every pair of goal atoms is reachable (h^2 and the relaxation see a plan), the
    triple is not.  Update 0 only guards a useless action."""

    def act(name, pre, add, delete, exists=None):
        return GroundAction(
            name=name,
            args=(),
            exists=exists,
            pre=tuple((p, None) for p in pre),
            negpre=(),
            add=tuple((p, None) for p in add),
            delete=tuple((p, None) for p in delete),
            cost=(((), 1),),
        )

    a, b, c = 0, 1, 2
    return GroundFamily(
        atoms=(("a",), ("b",), ("c",)),
        n_updates=1,
        actions=(
            act("ac", [a], [c], [b]),
            act("bc", [b], [c], [a]),
            act("cb", [c], [b], [a]),
            act("ca", [c], [a], [b]),
            act("idle", [a], [a], [], exists=(0, True)),
        ),
        init=((a, None), (b, None)),
        goal=((a, None), (b, None), (c, None)),
    )


def test_reachable_states_prove_a_model_unsolvable_after_the_first_one():
    fam = _two_of_three()
    tiers = TieredOpt(fam, NodePlanner(None, fam, "builtin"))
    first = tiers.optimal(frozenset())
    assert first.status == "unsolvable" and tiers.stats["opt_by_planner"] == 1
    second = tiers.optimal(frozenset({0}))
    assert second.status == "unsolvable" and second.planner == "reachable_states"
    assert tiers.stats["opt_by_reachable_states"] == 1 and tiers.stats["opt_by_planner"] == 1


def test_the_reachable_states_tier_can_be_switched_off():
    fam = _two_of_three()
    off = replace(DEFAULT, unsolvable_probe_states=0)
    tiers = TieredOpt(fam, NodePlanner(None, fam, "builtin", options=off))
    for sel in (frozenset(), frozenset({0})):
        assert tiers.optimal(sel).status == "unsolvable"
    assert tiers.stats["opt_by_reachable_states"] == 0 and tiers.stats["opt_by_planner"] == 2


def test_a_state_budget_too_small_proves_nothing_and_the_planner_answers():
    fam = _two_of_three()
    small = replace(DEFAULT, unsolvable_probe_states=2)  # the model has 3 reachable states
    tiers = TieredOpt(fam, NodePlanner(None, fam, "builtin", options=small))
    for sel in (frozenset(), frozenset({0})):
        assert tiers.optimal(sel).status == "unsolvable"
    assert tiers.stats["opt_by_reachable_states"] == 0 and tiers.stats["opt_by_planner"] == 2


@settings(
    max_examples=200, deadline=None, derandomize=True, suppress_health_check=list(HealthCheck)
)
@given(fam=families(), states=st.sampled_from([1, 3, 50_000]), bounds_first=st.booleans())
def test_every_tier_gives_the_optimal_cost_on_every_model(fam, states, bounds_first):
    """All selections in turn, so that the reachable-states tier runs once a model had no plan,
    with budgets that run out and budgets that do not; through ``bounds`` (the loop's JOINT
    before OPT) or ``optimal`` alone."""
    opts = replace(DEFAULT, unsolvable_probe_states=states)
    tiers = TieredOpt(fam, NodePlanner(None, fam, "builtin", options=opts))
    for sel in all_selections(fam.n_updates):
        r = tiers.bounds(sel) if bounds_first else None
        if r is None or not hasattr(r, "status"):
            r = tiers.optimal(sel, searched_only=bounds_first)
        task = fam.specialize(sel)
        c = dijkstra(task)
        if c is None:
            assert r.status == "unsolvable"
        else:
            assert r.status == "optimal" and r.cost == c and plan_cost(task, r.plan) == c
