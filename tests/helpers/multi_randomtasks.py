"""Hypothesis strategy for random small tasks with several human models.

Not a test file: the several-human tests import it.  :func:`multi_human_tasks` draws a robot
model (:func:`randomtasks.models`) and two or three human models, each derived from it by its
own random flips (as :func:`randomtasks.two_model_tasks` does for one), so the model
differences overlap in part.
"""

from __future__ import annotations

from hypothesis import strategies as st

from helpers.randomtasks import _flip, models
from mega_sat.model.task import TwoModelTask
from mega_sat.pddl.multi_task import MultiHumanTask


@st.composite
def multi_human_tasks(
    draw,
    max_delta: int = 5,
    humans: tuple[int, int] = (2, 3),
    allow_zero_cost: bool = False,
    max_atoms: int = 8,
) -> MultiHumanTask:
    """A robot model and 2-3 flipped human models with ``len(task.delta) <= max_delta``."""
    robot = draw(models(max_atoms, allow_zero_cost, True))
    tasks: list[TwoModelTask] = []
    union: set[str] = set()
    for _ in range(draw(st.integers(*humans))):
        human = robot
        task = TwoModelTask.from_models(robot, human)
        for _ in range(draw(st.integers(1, 3))):
            h2 = draw(_flip(human, allow_zero_cost))
            t2 = TwoModelTask.from_models(robot, h2)
            if len(union | {u.name for u in t2.delta}) <= max_delta:
                human, task = h2, t2
        union |= {u.name for u in task.delta}
        tasks.append(task)
    return MultiHumanTask.from_tasks(tasks)


STALE: dict[str | None, list[str | None]] = {
    "path": [None, "rubble"],  # a new passage the commander does not know, or old rubble
    "rough": [None, "path"],
    "rubble": ["path", None],  # a corridor blocked since the commander's map was drawn
    None: ["path", "rough"],
}
"""What a commander's stale map shows for a corridor the robot sees as the key."""


@st.composite
def multi_tradeoff_tasks(
    draw, humans: tuple[int, int] = (2, 3), max_delta: int = 6
) -> MultiHumanTask:
    """Route maps with trade-offs (as :func:`tradeoff_tasks.tradeoff_tasks`) and 2-3 human
    maps, each corridor of each human map drawn on its own (agreeing with the robot, or stale:
    a new passage missing, a blocked corridor still open), so the commanders disagree with the robot and with each other.  A
    long detour s-d0-d1-d2-g is open in every model: some plan is always explicable, and
    shorter routes cost explanations."""
    from helpers.tradeoff_tasks import _schemas
    from mega_sat.model.lifted import Model

    n_routes = draw(st.integers(2, 3))
    n_humans = draw(st.integers(*humans))
    kinds = ["path", "rough", "rubble", None]
    robot_facts: set[tuple[str, ...]] = {("at", "s")}
    human_facts: list[set[tuple[str, ...]]] = [{("at", "s")} for _ in range(n_humans)]
    nodes = {"s", "g", "d0", "d1", "d2"}
    detour = {("path", a, b) for a, b in (("s", "d0"), ("d0", "d1"), ("d1", "d2"), ("d2", "g"))}
    robot_facts |= detour
    for facts in human_facts:
        facts |= detour
    corridors = []
    for r in range(n_routes):
        chain = ["s"] + [f"r{r}n{i}" for i in range(draw(st.integers(1, 2)))] + ["g"]
        nodes.update(chain)
        for a, b in zip(chain, chain[1:], strict=False):
            rk = draw(st.sampled_from(kinds))
            if rk:
                robot_facts.add((rk, a, b))
            corridors.append((a, b, rk))
    # the models differ in initial facts only, so the union Delta is the union of the
    # symmetric differences; a human corridor that would grow it past max_delta stays as is
    union: set[tuple[str, ...]] = set()
    for facts in human_facts:
        for a, b, rk in corridors:
            hk = rk if draw(st.booleans()) else draw(st.sampled_from(STALE[rk]))
            diff = {(k, a, b) for k in (rk, hk) if k} if hk != rk else set()
            if len(union | diff) > max_delta:
                hk, diff = rk, set()
            union |= diff
            if hk:
                facts.add((hk, a, b))
    schemas = _schemas(draw(st.integers(1, 3)), draw(st.integers(2, 5)))

    def model(facts: set[tuple[str, ...]]) -> Model:
        return Model(
            "maps",
            "p",
            {"at": 1, "path": 2, "rough": 2, "rubble": 2, "permit": 0},
            schemas,
            frozenset(nodes),
            frozenset(facts),
            frozenset({("at", "g")}),
            uses_costs=True,
        )

    return MultiHumanTask.from_models(model(robot_facts), [model(f) for f in human_facts])
