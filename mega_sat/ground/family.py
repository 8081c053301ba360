"""Ground model families: one ground task that stands for every model ``human + E``.

Every ground component (precondition, effect, initial or goal atom, schema existence, cost) that
depends on an update of Delta carries a *guard*: the update's index and the truth value that
update's selection must have for the component to be present.  A candidate model is then just a
selection (a subset of Delta's indices); ``frozenset()`` is the human model, every index the
robot model.  This is what lets one SAT encoding serve the whole family: guards become selector
literals, selections become assumptions.

:class:`GroundTask` is one member of the family, plain STRIPS, for explicit-state planners and
the simulator.
"""

from __future__ import annotations

from collections.abc import Iterable
from dataclasses import dataclass
from functools import cached_property

from mega_sat.model.lifted import Atom, PlanStep, atom_pddl, step_str

__all__ = ["PlanStep", "step_str"]  # their home is model.lifted; callers still import them here

GuardLit = tuple[int, bool]
"""``(i, v)`` holds in a selection ``E`` iff ``(i in E) == v``."""

Guard = GuardLit | None
"""``None``: present in every model of the family."""

Entry = tuple[int, Guard]
"""An atom id with the guard under which the component is present."""

CostCase = tuple[tuple[GuardLit, ...], int]
"""``(guards, value)``: the action costs ``value`` when all guards hold."""


_RECENT_TASKS = 16
"""Ground tasks :meth:`GroundFamily.specialize` keeps for the selections asked last."""
_VERSIONS_KEPT = 4
"""Ground action versions :meth:`GroundFamily.specialize` keeps, per action of the family on
average (an action that mentions ``k`` updates has up to ``2 ** k``): at most the memory of
that many ground tasks, on any family."""
_MISSING = object()


def holds(guard: Guard, selection: frozenset[int]) -> bool:
    """Whether a guarded component is present in ``human + selection``."""
    return guard is None or ((guard[0] in selection) == guard[1])


@dataclass(frozen=True)
class GroundAction:
    """A ground action of the family with guarded components.

    ``cost`` lists mutually exclusive, exhaustive cases; exactly one applies in any selection.
    """

    name: str
    args: tuple[str, ...]
    exists: Guard
    pre: tuple[Entry, ...]
    negpre: tuple[Entry, ...]
    add: tuple[Entry, ...]
    delete: tuple[Entry, ...]
    cost: tuple[CostCase, ...]

    @property
    def step(self) -> PlanStep:
        return (self.name, *self.args)

    def cost_in(self, selection: frozenset[int]) -> int:
        for guards, value in self.cost:
            if all(holds(g, selection) for g in guards):
                return value
        raise AssertionError(f"no cost case of {step_str(self.step)} applies")

    def guards(self) -> set[int]:
        """Every update index this action's presence, conditions, effects or cost depend on."""
        out = {self.exists[0]} if self.exists else set()
        for entries in (self.pre, self.negpre, self.add, self.delete):
            out.update(g[0] for _, g in entries if g)
        for guards, _ in self.cost:
            out.update(i for i, _ in guards)
        return out


@dataclass(frozen=True)
class StripsAction:
    """One ground action of one model; ``index`` points back into the family's actions."""

    index: int
    name: str
    args: tuple[str, ...]
    pre: frozenset[int]
    negpre: frozenset[int]
    add: frozenset[int]
    delete: frozenset[int]
    cost: int

    @property
    def step(self) -> PlanStep:
        return (self.name, *self.args)


@dataclass(frozen=True)
class GroundTask:
    """One member of a family as plain STRIPS (atom ids index ``atoms``)."""

    atoms: tuple[Atom, ...]
    actions: tuple[StripsAction, ...]
    init: frozenset[int]
    goal: frozenset[int]

    @cached_property
    def by_step(self) -> dict[PlanStep, StripsAction]:
        return {a.step: a for a in self.actions}

    def describe(self) -> str:
        return f"{len(self.atoms)} atoms, {len(self.actions)} actions"


@dataclass(frozen=True)
class GroundFamily:
    """All ground actions any model ``human + E`` could use, with guarded components.

    Built by :mod:`mega_sat.ground.grounding` from the most permissive combination of the two models,
    so no action of any family member is missing.
    """

    atoms: tuple[Atom, ...]
    n_updates: int
    actions: tuple[GroundAction, ...]
    init: tuple[Entry, ...]
    goal: tuple[Entry, ...]

    @cached_property
    def atom_index(self) -> dict[Atom, int]:
        return {a: i for i, a in enumerate(self.atoms)}

    @cached_property
    def action_index(self) -> dict[PlanStep, int]:
        return {a.step: i for i, a in enumerate(self.actions)}

    @cached_property
    def robot_selection(self) -> frozenset[int]:
        return frozenset(range(self.n_updates))

    @cached_property
    def min_cost(self) -> int:
        """Smallest cost any action has in any model of the family (the horizon argument)."""
        return min((v for a in self.actions for _, v in a.cost), default=1)

    @cached_property
    def max_cost(self) -> int:
        """Largest cost any action has in any model of the family."""
        return max((v for a in self.actions for _, v in a.cost), default=0)

    def specialize(self, selection: Iterable[int]) -> GroundTask:
        """The ground task of ``human + selection``.

        The loop asks for the same model several times (its bounds, its search, its
        oracles), and an action's part of it depends only on the updates it mentions: the
        last few tasks and every action's versions so far are kept, so a repeated model
        costs a lookup and a new one a pass over the actions."""
        sel = frozenset(selection)
        recent = self._recent_tasks
        task = recent.pop(sel, None)
        if task is None:
            task = self._specialized(sel)
            if len(recent) >= _RECENT_TASKS:
                del recent[next(iter(recent))]
        recent[sel] = task  # most recent last
        return task

    def _specialized(self, sel: frozenset[int]) -> GroundTask:
        def keep(entries: tuple[Entry, ...]) -> frozenset[int]:
            return frozenset(p for p, g in entries if holds(g, sel))

        acts = []
        room = self._versions_room
        for i, (a, mentions, versions) in enumerate(
            zip(self.actions, self._action_guards, self._action_versions, strict=True)
        ):
            key = mentions & sel
            version = versions.get(key, _MISSING)
            if version is _MISSING:
                version = (
                    StripsAction(
                        i, a.name, a.args, keep(a.pre), keep(a.negpre), keep(a.add),
                        keep(a.delete), a.cost_in(sel),
                    )
                    if holds(a.exists, sel)
                    else None
                )  # fmt: skip
                if room[0] > 0:
                    versions[key] = version
                    room[0] -= 1
            if version is not None:
                acts.append(version)
        return GroundTask(self.atoms, tuple(acts), keep(self.init), keep(self.goal))

    @cached_property
    def _action_guards(self) -> tuple[frozenset[int], ...]:
        return tuple(frozenset(a.guards()) for a in self.actions)

    @cached_property
    def _action_versions(self) -> tuple[dict[frozenset[int], StripsAction | None], ...]:
        """Per action, its ground versions (``None``: absent) by the updates it mentions that
        are selected (the first ones built, within :attr:`_versions_room`)."""
        return tuple({} for _ in self.actions)

    @cached_property
    def _versions_room(self) -> list[int]:
        """How many more versions :attr:`_action_versions` may keep (one mutable count)."""
        return [_VERSIONS_KEPT * len(self.actions)]

    @cached_property
    def _recent_tasks(self) -> dict[frozenset[int], GroundTask]:
        return {}

    def describe(self) -> str:
        return (
            f"{len(self.atoms)} atoms, {len(self.actions)} ground actions, {self.n_updates} updates"
        )

    def atom_name(self, i: int) -> str:
        return atom_pddl(self.atoms[i])
