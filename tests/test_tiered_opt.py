"""The tiers of the sat engine's OPT step (mega_sat/planners/tiered_opt.py) against brute force,
and the reachable-states tier on a model that only an exhaustive search proves unsolvable."""

from dataclasses import replace

from helpers.fuzzing import oracle_settings
from helpers.sat_families import all_selections, assert_optimum, families
from hypothesis import given
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


@oracle_settings(200)
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
        assert_optimum(task, r.status, r.cost, r.plan)


_NUMPY_BEFORE_THE_PLANNER = """
import sys
from mega_sat.ground.family import GroundAction, GroundFamily
from mega_sat.options import Options
from mega_sat.planners.tiered_opt import TieredOpt
from mega_sat.search.astar import PlanResult
from mega_sat.status import Status
n = 12  # 2^12 states, the goal (every switch on) last: past VECTOR_AFTER expansions
acts = tuple(
    GroundAction(f"on{i}", (), None, (), (), ((i, None),), (), (((), 1),)) for i in range(n)
)
goal = tuple((i, None) for i in range(n))
fam = GroundFamily(tuple((f"s{i}",) for i in range(n)), 0, acts, (), goal)
class Planner:
    kind = sys.argv[2]
    options = Options(quick_nodes=int(sys.argv[1]))
    def optimal(self, sel):
        print("vector search imported:", "mega_sat.search.vector_search" in sys.modules)
        plan = tuple((f"on{i}",) for i in range(n))
        return PlanResult(Status.OPTIMAL, plan, n, True, "sat", 0.0, "")
assert "mega_sat.search.vector_search" not in sys.modules
print(TieredOpt(fam, Planner()).optimal(frozenset()).planner)
"""


def test_a_quick_search_past_the_vector_threshold_imports_numpy_before_the_planner():
    """The planner's search passes the same states as the quick tier that missed; past
    ``VECTOR_AFTER`` expansions it goes on in numpy, imported once before the portfolio's
    forked race starts (a clean interpreter, so that no other test's imports count)."""
    import subprocess
    import sys

    def run(quick_nodes: int, kind: str = "portfolio") -> str:
        return subprocess.run(
            [sys.executable, "-c", _NUMPY_BEFORE_THE_PLANNER, str(quick_nodes), kind],
            capture_output=True,
            text=True,
            check=True,
        ).stdout

    assert run(3000) == "vector search imported: True\nsat\n"  # missed after 3000 expansions
    assert run(1000) == "vector search imported: False\nsat\n"  # missed below the threshold
    assert run(9000) == "quick_search\n"  # 4095 expansions: the quick tier answers
    assert run(3000, "sat") == "vector search imported: False\nsat\n"  # no race, no child


def test_a_model_a_remembered_plan_runs_in_skips_the_pair_check(monkeypatch):
    """The pair check can only prove a model unsolvable: where a remembered plan runs it is
    skipped, and a model without a running plan still gets it."""
    import mega_sat.planners.tiered_opt as tiered_opt

    calls = []
    real = tiered_opt.goal_pair_unreachable
    monkeypatch.setattr(
        tiered_opt, "goal_pair_unreachable", lambda task: calls.append(task) or real(task)
    )

    def reach(name, exists):
        return GroundAction(name, (), exists, (), (), ((0, None),), (), (((), 1),))

    # update 0 decides which of two actions reaches the goal
    fam = GroundFamily(
        (("g",),), 1, (reach("one", (0, True)), reach("two", (0, False))), (), ((0, None),)
    )
    tiers = TieredOpt(fam, NodePlanner(None, fam, "builtin"))
    tiers.remember((("one",),))
    assert tiers.optimal(frozenset({0})).cost == 1  # by the remembered plan
    assert calls == []
    assert tiers.optimal(frozenset()).cost == 1  # "one" is absent: the pair check runs
    assert len(calls) == 1
