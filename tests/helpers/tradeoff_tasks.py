"""Hypothesis strategy for random two-model tasks *with trade-offs* (several frontier points).

Random small maps: directed corridors (move, cost 1), rough corridors (move_rough, its own
cost), rubble that clear_passage removes at a high cost, and a permit the human may believe
rough corridors need.  The human model flips random map facts and random schema features, so
explaining more usually buys a cheaper robot plan.  State spaces stay in the hundreds.
"""

from __future__ import annotations

from hypothesis import strategies as st

from mega_sat.model.features import apply_updates
from mega_sat.model.lifted import Model, Schema
from mega_sat.model.task import TwoModelTask


def _schemas(rough_cost: int, clear_cost: int) -> dict[str, Schema]:
    move = Schema(
        "move",
        ("?a", "?b"),
        pre=frozenset({("at", "?a"), ("path", "?a", "?b")}),
        add=frozenset({("at", "?b")}),
        delete=frozenset({("at", "?a")}),
        cost=1,
    )
    rough = Schema(
        "move_rough",
        ("?a", "?b"),
        pre=frozenset({("at", "?a"), ("rough", "?a", "?b")}),
        add=frozenset({("at", "?b")}),
        delete=frozenset({("at", "?a")}),
        cost=rough_cost,
    )
    clear = Schema(
        "clear_passage",
        ("?a", "?b"),
        pre=frozenset({("at", "?a"), ("rubble", "?a", "?b")}),
        add=frozenset({("path", "?a", "?b")}),
        delete=frozenset({("rubble", "?a", "?b")}),
        cost=clear_cost,
    )
    permit = Schema("get_permit", (), pre=frozenset(), add=frozenset({("permit",)}), cost=2)
    return {s.name: s for s in (move, rough, clear, permit)}


@st.composite
def tradeoff_tasks(draw, max_schema_flips: int = 2) -> TwoModelTask:
    """2-3 parallel routes from s to g, 1-2 corridors each.  Every corridor is open, rough,
    blocked by rubble or absent, independently in each model (biased to agree), so the routes
    the human expects, the routes the robot can use and their costs all vary."""
    from mega_sat.model.features import COST, PRE, Feature, Update

    n_routes = draw(st.integers(2, 3))
    kinds = ["path", "rough", "rubble", None]
    robot_facts: set[tuple[str, ...]] = {("at", "s")}
    human_facts: set[tuple[str, ...]] = {("at", "s")}
    nodes = {"s", "g"}
    for r in range(n_routes):
        length = draw(st.integers(1, 2))
        chain = ["s"] + [f"r{r}n{i}" for i in range(length)] + ["g"]
        nodes.update(chain)
        for a, b in zip(chain, chain[1:], strict=False):
            rk = draw(st.sampled_from(kinds))
            hk = rk if draw(st.integers(0, 2)) else draw(st.sampled_from(kinds))
            if rk:
                robot_facts.add((rk, a, b))
            if hk:
                human_facts.add((hk, a, b))
    schemas = _schemas(draw(st.integers(1, 3)), draw(st.integers(2, 5)))
    robot = Model(
        "maps",
        "p",
        {"at": 1, "path": 2, "rough": 2, "rubble": 2, "permit": 0},
        schemas,
        frozenset(nodes),
        frozenset(robot_facts),
        frozenset({("at", "g")}),
        uses_costs=True,
    )
    human = Model(
        "maps",
        "p",
        robot.predicates,
        schemas,
        frozenset(nodes),
        frozenset(human_facts),
        robot.goal,
        uses_costs=True,
    )
    extra = [
        Update(Feature(PRE, "move_rough", ("permit",)), True),
        Update(Feature(PRE, "clear_passage", ("permit",)), True),
        Update(Feature(COST, "clear_passage", (str(draw(st.integers(1, 6))),)), True),
        Update(Feature(COST, "move_rough", (str(draw(st.integers(1, 4))),)), True),
    ]
    k = draw(st.integers(0, max_schema_flips))
    picks = draw(st.lists(st.sampled_from(extra), min_size=k, max_size=k, unique=True))
    human = apply_updates(human, robot, picks)
    return TwoModelTask.from_models(robot, human)
