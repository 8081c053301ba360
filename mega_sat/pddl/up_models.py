"""unified-planning models in and out: ``Problem`` objects become a task, plans go back as
``SequentialPlan`` objects.

A ``unified_planning.model.Problem`` is checked against the classical fragment mega-sat reads
(its ``kind`` names the features the library found), written as PDDL by the library's own
``PDDLWriter`` and read by :mod:`mega_sat.pddl.reader`, so a model built in Python and the same
model written as PDDL give the same task.  Plans map back through the same writer's names.
The ``up`` extra installs the library; nothing here imports it before it is needed.
"""

from __future__ import annotations

from collections.abc import Sequence
from typing import Any

from mega_sat.errors import UsageError
from mega_sat.model.lifted import PlanStep
from mega_sat.model.task import TwoModelTask
from mega_sat.pddl.loading import task_from_texts

# The problem-kind features (unified-planning's own names) of the fragment mega-sat reads:
# STRIPS with types, negative preconditions, equality in preconditions and integer action costs (constants or static
# fluents).  Any other feature is refused by name.
SUPPORTED_KIND_FEATURES = frozenset(
    {
        "ACTION_BASED",
        "FLAT_TYPING",
        "HIERARCHICAL_TYPING",
        "NEGATIVE_CONDITIONS",
        "EQUALITIES",
        "ACTIONS_COST",
        "PLAN_LENGTH",
        "STATIC_FLUENTS_IN_ACTIONS_COST",
        "INT_NUMBERS_IN_ACTIONS_COST",
    }
)


def _up() -> Any:
    try:
        import unified_planning
    except ImportError:
        raise UsageError(
            "the unified-planning package is not installed (install mega-sat with the 'up' extra)"
        ) from None
    return unified_planning


def _check_problem(role: str, problem: object) -> None:
    """Refuse anything but a classical ``Problem`` of the supported kind, naming the feature."""
    from unified_planning.model import Problem

    if not isinstance(problem, Problem):
        raise UsageError(
            f"load_task_from_up: {role} must be a unified_planning.model.Problem, "
            f"got {type(problem).__name__}"
        )
    try:
        features = set(problem.kind.features)
    except Exception as e:  # the library computes the kind; a broken model fails there
        raise UsageError(f"{role} '{problem.name}': its kind cannot be computed: {e}") from None
    unsupported = sorted(features - SUPPORTED_KIND_FEATURES)
    if unsupported:
        raise UsageError(
            f"{role} '{problem.name}' uses problem-kind features mega-sat does not support: "
            f"{', '.join(unsupported)} (supported: classical STRIPS with types, negative "
            "conditions, equality and integer action costs)"
        )


def _pddl(problem: Any) -> tuple[str, str, Any]:
    """Domain text, problem text and the writer (which maps PDDL names back to items)."""
    from unified_planning.io import PDDLWriter

    writer = PDDLWriter(problem)
    try:
        return writer.get_domain(), writer.get_problem(), writer
    except Exception as e:  # the writer refuses what PDDL cannot say; report it, not a trace
        raise UsageError(f"'{problem.name}' cannot be written as PDDL: {e}") from None


def load_task_from_up(robot_problem: Any, human_problem: Any = None) -> TwoModelTask:
    """The task of two unified-planning ``Problem`` objects: the robot's model and the human's
    (default: the robot's problem, as with PDDL files; then Delta is empty).

    Messages about the models name them 'robot domain (unified-planning)' and so on, with lines
    of the PDDL the library writes for them."""
    _up()
    _check_problem("robot_problem", robot_problem)
    if human_problem is not None:
        _check_problem("human_problem", human_problem)
    rd, rp, _ = _pddl(robot_problem)
    hd, hp, _ = _pddl(human_problem) if human_problem is not None else (rd, rp, None)
    texts = {"robot_domain": rd, "robot_problem": rp, "human_domain": hd, "human_problem": hp}
    names = {role: f"{role.replace('_', ' ')} (unified-planning)" for role in texts}
    return task_from_texts(texts, names)


def to_up_plan(plan: Sequence[PlanStep], problem: Any) -> Any:
    """``plan`` (steps as mega-sat prints them) as a ``SequentialPlan`` of ``problem``'s own
    actions and objects, e.g. the robot problem a task was loaded from."""
    _up()
    _check_problem("problem", problem)
    from unified_planning.plans import ActionInstance, SequentialPlan

    _, _, writer = _pddl(problem)
    em = problem.environment.expression_manager
    steps = []
    for step in plan:
        name, *args = step
        try:
            action = writer.get_item_named(name)
            objects = [writer.get_item_named(a) for a in args]
        except Exception:
            raise UsageError(
                f"plan step '({' '.join(step)})' names no action or object of '{problem.name}'"
            ) from None
        if not problem.has_action(getattr(action, "name", "")) or len(args) != len(
            action.parameters
        ):
            raise UsageError(f"plan step '({' '.join(step)})' is no action of '{problem.name}'")
        steps.append(ActionInstance(action, tuple(em.ObjectExp(o) for o in objects)))
    return SequentialPlan(steps, problem.environment)
