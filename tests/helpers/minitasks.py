"""Small hand-built two-model tasks (no PDDL parsing), for engine tests."""

from __future__ import annotations

from mega_sat.model.lifted import Model, Schema
from mega_sat.model.task import TwoModelTask


def _nav_model(paths: set[tuple[str, str]], blocked: set[tuple[str, str]]) -> Model:
    nodes = {x for e in paths | blocked for x in e}
    move = Schema(
        "move",
        ("?a", "?b"),
        pre=frozenset({("at", "?a"), ("clear_path", "?a", "?b")}),
        add=frozenset({("at", "?b")}),
        delete=frozenset({("at", "?a")}),
        cost=1,
    )
    clear = Schema(
        "clear_passage",
        ("?a", "?b"),
        pre=frozenset({("at", "?a"), ("rubble", "?a", "?b")}),
        add=frozenset({("clear_path", "?a", "?b")}),
        delete=frozenset({("rubble", "?a", "?b")}),
        cost=5,
    )
    init = {("at", "s")} | {("clear_path", *e) for e in paths} | {("rubble", *e) for e in blocked}
    return Model(
        "nav",
        "p",
        {"at": 1, "clear_path": 2, "rubble": 2},
        {"move": move, "clear_passage": clear},
        frozenset(nodes),
        frozenset(init),
        frozenset({("at", "g")}),
        uses_costs=True,
    )


def _with_human_init(robot: Model, human_init: set) -> TwoModelTask:
    """The task whose human model is ``robot`` with another initial state."""
    human = Model(
        robot.domain_name,
        robot.problem_name,
        robot.predicates,
        robot.schemas,
        robot.objects,
        frozenset(human_init),
        robot.goal,
        uses_costs=True,
    )
    return TwoModelTask.from_models(robot, human)


def usar_like() -> TwoModelTask:
    """A miniature of the paper's USAR map.  Both know a->g and y->g are open and that s->a has
    rubble.  The human believes s->a is nevertheless open and does not know s->x, x->y.
    Frontier: (|E| 1, robot cost 7: clear the rubble, s-a-g) and (|E| 3, robot cost 3: s-x-y-g).
    """
    robot = _nav_model({("a", "g"), ("y", "g"), ("s", "x"), ("x", "y")}, {("s", "a")})
    human_init = (set(robot.init) - {("clear_path", "s", "x"), ("clear_path", "x", "y")}) | {
        ("clear_path", "s", "a")
    }
    return _with_human_init(robot, human_init)


def hidden_trap() -> TwoModelTask:
    """A task whose robot-optimal plan has an empty MCE but an MME of one update.

    Both know s->x->y->g (cost 3, the robot's optimal plan).  The robot also has s->a, which
    the human does not know, and knows that a->g is closed, which the human believes open.
    Told only about s->a, the human would expect s->a->g (cost 2): the MME must also close
    a->g, the MCE need not.
    """
    robot = _nav_model({("s", "x"), ("x", "y"), ("y", "g"), ("s", "a")}, set())
    human_init = (set(robot.init) - {("clear_path", "s", "a")}) | {("clear_path", "a", "g")}
    return _with_human_init(robot, human_init)
