"""The two-model task: robot model, human model, and the model difference between them.

This is the object the rest of mega-sat works on.  Candidate human models are named by
subsets of ``delta`` (as frozensets of indices into it): ``frozenset()`` is the human model and
``task.all_updates`` (every index) is the robot model.
"""

from __future__ import annotations

from collections.abc import Iterable
from dataclasses import dataclass, field, replace
from functools import cached_property

from mega_sat.errors import ModelMismatchError, UsageError
from mega_sat.model.features import Update, apply_updates, model_difference
from mega_sat.model.lifted import (
    Model,
    Schema,
    canonical_equalities,
    has_equality,
    rename_schema,
    with_equality,
)

Selection = frozenset[int]
"""A subset E of Delta, as indices into ``TwoModelTask.delta``."""


def explanation_line(raw: str) -> str:
    """The update name on one line of an explanation ('' for none): without a byte-order mark,
    the ``Explanation >>`` prefix of printed answers, or a comment line (``;``, ``#``), in
    lower case with single spaces, as update names are written."""
    line = " ".join(raw.replace("\ufeff", "").split())
    if line.startswith("Explanation >>"):
        line = line[len("Explanation >>") :].strip()
    return "" if line.startswith((";", "#")) else line.lower()


def align_human(
    robot: Model,
    human: Model,
    *,
    robot_name: str = "the robot domain",
    human_name: str = "the human domain",
    robot_problem_name: str | None = None,
    human_problem_name: str | None = None,
) -> Model:
    """Rename the human's schema parameters to the robot's, matching them by position.

    A cost function the human's domain does not declare (a human model written without the
    robot's costs) takes the robot problem's values: the human holds no values of it to differ
    from, and a cost update that brings its term to the human needs them.  One only the
    human's domain declares keeps the human problem's values, which only the human's own
    costs use.

    Raises :class:`ModelMismatchError` on a schema or predicate of different arity.  The
    ``*_name`` arguments name the files in messages (problem names default to the domain
    names with 'domain' replaced by 'problem').
    """
    # PDDL has one name space for predicates and functions: a model written with both (by
    # `apply`, or for VAL and Fast Downward) would declare the name twice
    clashes = sorted(
        (set(robot.predicates) & set(human.function_arities))
        | (set(robot.function_arities) & set(human.predicates))
    )
    if clashes:
        name = clashes[0]
        here, there = (
            ("predicate", "function") if name in human.predicates else ("function", "predicate")
        )
        raise ModelMismatchError(
            f"'{name}' is a {here} in {human_name} but a {there} in {robot_name} (a name "
            "stands for one kind of symbol in both models; rename one of them)",
            anchor=("human_domain", here, (name,)),
        )
    unknown = {f: n for f, n in robot.function_arities.items() if f not in human.function_arities}
    if unknown:
        human = replace(
            human,
            functions={
                **human.functions,
                **{t: v for t, v in robot.functions.items() if t[0] in unknown},
            },
            function_arities={**human.function_arities, **unknown},
        )
    for p, n in human.predicates.items():
        if p in robot.predicates and robot.predicates[p] != n:
            raise ModelMismatchError(
                f"predicate '{p}' has {robot.predicates[p]} argument(s) in {robot_name} "
                f"but {n} in {human_name}",
                anchor=("human_domain", "predicate", (p,)),
            )
    # a function only the human's domain declares prices only the human's schemas: its values
    # are the human's beliefs, which no update can reach (the robot holds none to give)
    shared = set(robot.function_arities) & set(human.function_arities)
    for term in sorted(t for t in set(robot.functions) ^ set(human.functions) if t[0] in shared):
        if term in robot.functions:
            role, side = (
                "robot_problem",
                robot_problem_name or robot_name.replace("domain", "problem"),
            )
        else:
            role, side = (
                "human_problem",
                human_problem_name or human_name.replace("domain", "problem"),
            )
        raise ModelMismatchError(
            f"cost function value ({' '.join(term)}) is defined only in {side} (both problems "
            "give a value to the same terms; the values may differ)",
            anchor=(role, "value", term),
        )
    schemas: dict[str, Schema] = {}
    for name, hs in human.schemas.items():
        rs = robot.schemas.get(name)
        if rs is None:
            schemas[name] = hs
            continue
        if len(rs.params) != len(hs.params):
            raise ModelMismatchError(
                f"action '{name}' has {len(rs.params)} parameter(s) in {robot_name} but "
                f"{len(hs.params)} in {human_name}",
                anchor=("human_domain", "action", (name,)),
            )
        # by position: the human's parameters take the robot's names
        schemas[name] = rename_schema(hs, dict(zip(hs.params, rs.params, strict=True)))
    return Model(
        domain_name=human.domain_name,
        problem_name=human.problem_name,
        predicates=human.predicates,
        schemas=schemas,
        objects=human.objects,
        init=human.init,
        goal=human.goal,
        neggoal=human.neggoal,
        type_predicates=human.type_predicates,
        functions=human.functions,
        function_arities=human.function_arities,
        uses_costs=human.uses_costs,
    )


@dataclass(frozen=True)
class TwoModelTask:
    """Robot model ``M^R``, human model ``M^R_h`` (aligned) and ``Delta``.

    ``sources`` records where the models came from, for messages.
    """

    robot: Model
    human: Model
    delta: tuple[Update, ...]
    sources: dict[str, str] = field(default_factory=dict, compare=False)

    @classmethod
    def from_models(
        cls, robot: Model, human: Model, sources: dict[str, str] | None = None
    ) -> TwoModelTask:
        sources = sources or {}
        equality = has_equality(robot) or has_equality(human)
        if equality:
            # equality is built in, not a belief: both models hold (= o o) for every object
            objects = robot.objects | human.objects
            robot, human = with_equality(robot, objects), with_equality(human, objects)
        human = align_human(
            robot,
            human,
            robot_name=sources.get("robot_domain", "the robot domain"),
            human_name=sources.get("human_domain", "the human domain"),
            robot_problem_name=sources.get("robot_problem"),
            human_problem_name=sources.get("human_problem"),
        )
        if equality:  # after the human's parameters take the robot's names
            robot, human = canonical_equalities(robot), canonical_equalities(human)
        return cls(robot, human, model_difference(robot, human), dict(sources))

    @cached_property
    def all_updates(self) -> Selection:
        return frozenset(range(len(self.delta)))

    @cached_property
    def update_index(self) -> dict[str, int]:
        return {u.name: i for i, u in enumerate(self.delta)}

    def updated_model(self, selection: Iterable[int]) -> Model:
        """``human + E`` for ``E`` given as indices into ``delta``."""
        sel = self.check_selection(selection)
        return apply_updates(self.human, self.robot, [self.delta[i] for i in sorted(sel)])

    def selection_from_names(self, names: Iterable[str], *, path: str | None = None) -> Selection:
        """Turn ``add-...``/``remove-...`` lines into a selection; unknown lines are an error."""
        if isinstance(names, str):
            names = names.splitlines()
        elif isinstance(names, bytes) or not isinstance(names, Iterable):
            raise UsageError(
                f"an explanation is update names (lines of text), got {type(names).__name__}",
                path=path,
            )
        out = set()
        for lineno, raw in enumerate(names, 1):
            if not isinstance(raw, str):
                raise UsageError(
                    f"an explanation is update names (str), got {type(raw).__name__}",
                    path=path,
                    where=f"line {lineno}",
                )
            line = explanation_line(raw)
            if not line:
                continue
            if line not in self.update_index:
                shown = line if line.isprintable() else ascii(line)
                raise UsageError(
                    f"'{shown}' is not an update of the model difference (see 'mega-sat diff')",
                    path=path,
                    where=f"line {lineno}",
                )
            out.add(self.update_index[line])
        return frozenset(out)

    def names(self, selection: Iterable[int]) -> list[str]:
        """Update names of a selection, in canonical order."""
        return [self.delta[i].name for i in sorted(self.check_selection(selection))]

    def check_selection(self, selection: Iterable[int]) -> Selection:
        """``selection`` as a frozenset of valid indices into ``delta``; anything else (an index
        out of range, a negative one, a name) is a :class:`UsageError`."""
        if isinstance(selection, str | bytes) or not isinstance(selection, Iterable):
            raise UsageError(
                f"a selection is a set of update indices, got {type(selection).__name__}"
            )
        out = set()
        for i in selection:
            if isinstance(i, bool) or not isinstance(i, int):
                raise UsageError(f"a selection holds update indices (int), got {i!r}")
            if not 0 <= i < len(self.delta):
                raise UsageError(
                    f"update index {i} is out of range (Delta has {len(self.delta)} updates)"
                )
            out.add(i)
        return frozenset(out)
