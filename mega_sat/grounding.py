"""Grounding a two-model task into one :class:`GroundFamily` that covers every ``human + E``.

Reachability is computed once, on the most permissive combination of the two models: the union
of both initial states, every schema either model has, the union of both models' add effects,
and only the positive preconditions *both* models share (a precondition only one model has is a
Delta feature, so some ``E`` removes it).  Deletes and negative preconditions are ignored.  The
relaxed fixpoint of that combination over-approximates the reachable atoms and applicable ground
actions of every family member, so no action any ``human + E`` could use is missing.

The fixpoint is a semi-naive join: each newly reached atom is unified with every shared
precondition of its predicate and the remaining preconditions are joined against the atoms
reached so far through an index by (predicate, position, object).  Static type preconditions
therefore prune bindings early instead of enumerating the cartesian product of the objects.

Each reachable ground action then gets its guarded components: a component both models have is
unguarded, one only the robot has is guarded by ``(i, True)`` and one only the human has by
``(i, False)``, ``i`` being the index of its update in ``task.delta``.
"""

from __future__ import annotations

from collections import deque
from collections.abc import Iterable, Iterator, Mapping
from dataclasses import dataclass
from itertools import product

from mega_sat.errors import PDDLError
from mega_sat.family import CostCase, Entry, GroundAction, GroundFamily, GroundTask, Guard
from mega_sat.features import (
    ADD,
    COST,
    DEL,
    FVALUE,
    GOAL,
    INIT,
    NEGPRE,
    PRE,
    SCHEMA,
    Feature,
    Update,
    cost_str,
)
from mega_sat.model import Atom, CostTerm, Model, Schema, atom_pddl
from mega_sat.task import TwoModelTask

Binding = dict[str, str]


@dataclass(frozen=True)
class _RelaxedSchema:
    """A schema of the permissive union model used only for reachability."""

    name: str
    params: tuple[str, ...]
    pre: tuple[Atom, ...]
    add: tuple[Atom, ...]


class _Guards:
    """Looks up the guard of a feature from the indices of ``task.delta``."""

    def __init__(self, delta: tuple[Update, ...]):
        self.index = {(u.feature, u.robot_has): i for i, u in enumerate(delta)}

    def of(self, feature: Feature, in_robot: bool, in_human: bool) -> Guard:
        if in_robot and in_human:
            return None
        has = in_robot
        i = self.index.get((feature, has))
        if i is None:  # contract violation between features.py and the models
            raise AssertionError(f"feature {feature.name!r} differs but is not in Delta")
        return (i, has)


def _is_var(x: str) -> bool:
    return x.startswith("?")


def _unify(lifted: Atom, ground: Atom, binding: Binding) -> Binding | None:
    """Extend ``binding`` so that ``lifted`` grounds to ``ground``; None if impossible."""
    if len(lifted) != len(ground):
        return None
    out = binding
    copied = False
    for x, v in zip(lifted[1:], ground[1:], strict=True):
        if _is_var(x):
            b = out.get(x)
            if b is None:
                if not copied:
                    out = dict(out)
                    copied = True
                out[x] = v
            elif b != v:
                return None
        elif x != v:
            return None
    return out


class _AtomIndex:
    """Reached atoms by predicate and by (predicate, position, object), for joins."""

    def __init__(self) -> None:
        self.by_pred: dict[str, list[Atom]] = {}
        self.by_pos: dict[tuple[str, int, str], list[Atom]] = {}

    def add(self, atom: Atom) -> None:
        self.by_pred.setdefault(atom[0], []).append(atom)
        for k, v in enumerate(atom[1:], 1):
            self.by_pos.setdefault((atom[0], k, v), []).append(atom)

    def candidates(self, lifted: Atom, binding: Binding) -> list[Atom]:
        """The smallest index bucket that can contain groundings of ``lifted``."""
        best = self.by_pred.get(lifted[0], [])
        for k, x in enumerate(lifted[1:], 1):
            v = binding.get(x) if _is_var(x) else x
            if v is not None:
                bucket = self.by_pos.get((lifted[0], k, v), [])
                if len(bucket) < len(best):
                    best = bucket
                    if not best:
                        break
        return best


def _join(pres: list[Atom], binding: Binding, index: _AtomIndex) -> Iterator[Binding]:
    """All extensions of ``binding`` under which every atom of ``pres`` is in ``index``."""
    if not pres:
        yield binding
        return
    # most constrained precondition first
    best_k, best_c = 0, None
    for k, p in enumerate(pres):
        c = index.candidates(p, binding)
        if best_c is None or len(c) < len(best_c):
            best_k, best_c = k, c
            if not c:
                return
    rest = pres[:best_k] + pres[best_k + 1 :]
    for atom in best_c:
        b = _unify(pres[best_k], atom, binding)
        if b is not None:
            yield from _join(rest, b, index)


def _relaxed_schemas(robot: Model, human: Model) -> list[_RelaxedSchema]:
    out = []
    for name in sorted(set(robot.schemas) | set(human.schemas)):
        rs, hs = robot.schemas.get(name), human.schemas.get(name)
        if rs is not None and hs is not None:
            pre = rs.pre & hs.pre
            add = rs.add | hs.add
            params = rs.params
        else:
            s = rs if rs is not None else hs
            assert s is not None
            # every component of a one-model schema is its own Delta feature, so some E adds
            # the schema without any of its preconditions: no precondition constrains it
            pre, add, params = frozenset(), s.add, s.params
        out.append(_RelaxedSchema(name, params, tuple(sorted(pre)), tuple(sorted(add))))
    return out


def _ground_args(schema: _RelaxedSchema, binding: Binding, objects: list[str]) -> Iterator:
    """Complete ``binding`` over parameters no shared precondition mentions."""
    free = [p for p in schema.params if p not in binding]
    if not free:
        yield tuple(binding[p] for p in schema.params)
        return
    for values in product(objects, repeat=len(free)):
        b = dict(binding)
        b.update(zip(free, values, strict=True))
        yield tuple(b[p] for p in schema.params)


def _relaxed_reachability(
    schemas: list[_RelaxedSchema], init: Iterable[Atom], objects: list[str]
) -> tuple[set[Atom], list[tuple[str, tuple[str, ...]]]]:
    """Relaxed fixpoint: reachable atoms and reachable ``(schema, args)`` pairs (sorted)."""
    by_pred: dict[str, list[tuple[_RelaxedSchema, int]]] = {}
    for s in schemas:
        for k, p in enumerate(s.pre):
            by_pred.setdefault(p[0], []).append((s, k))
    reached: set[Atom] = set()
    queue: deque[Atom] = deque()
    actions: set[tuple[str, tuple[str, ...]]] = set()

    def fire(s: _RelaxedSchema, binding: Binding) -> None:
        for args in _ground_args(s, binding, objects):
            key = (s.name, args)
            if key in actions:
                continue
            actions.add(key)
            b = dict(zip(s.params, args, strict=True))
            for a in s.add:
                g = (a[0],) + tuple(b.get(x, x) for x in a[1:])
                if g not in reached:
                    reached.add(g)
                    queue.append(g)

    for a in sorted(set(init)):
        if a not in reached:
            reached.add(a)
            queue.append(a)
    for s in schemas:
        if not s.pre:
            fire(s, {})
    index = _AtomIndex()
    while queue:
        atom = queue.popleft()
        index.add(atom)
        for s, k in by_pred.get(atom[0], ()):
            b = _unify(s.pre[k], atom, {})
            if b is None:
                continue
            rest = list(s.pre[:k] + s.pre[k + 1 :])
            for full in _join(rest, b, index):
                fire(s, full)
    return reached, sorted(actions)


def _eval_cost(
    cost: int | CostTerm, binding: Mapping[str, str], task: TwoModelTask, guards: _Guards
) -> list[CostCase]:
    """Cost cases of one cost expression: a function term's value is the robot's when its
    FVALUE update is selected and the human's otherwise (both models define the same terms)."""
    if isinstance(cost, int):
        return [((), cost)]
    term = tuple(binding.get(x, x) for x in cost)
    rv, hv = task.robot.functions.get(term), task.human.functions.get(term)
    if rv is None and hv is None:
        raise PDDLError(f"cost function value {atom_pddl(term)} is not defined in the problem")
    if rv is None or hv is None or rv == hv:
        v = rv if rv is not None else hv
        assert v is not None
        return [((), v)]
    i = guards.index.get((Feature(FVALUE, "", term + (str(rv),)), True))
    if i is None:
        raise AssertionError(f"function value {atom_pddl(term)} differs but is not in Delta")
    return [(((i, True),), rv), (((i, False),), hv)]


def _cost_cases(
    name: str,
    rs: Schema | None,
    hs: Schema | None,
    binding: Binding,
    task: TwoModelTask,
    guards: _Guards,
) -> tuple[CostCase, ...]:
    """Mutually exclusive, exhaustive cost cases of one ground action."""
    if rs is not None and hs is not None and cost_str(rs.cost) != cost_str(hs.cost):
        i = guards.index.get((Feature(COST, name, (cost_str(rs.cost),)), True))
        if i is None:
            raise AssertionError(f"cost of {name} differs but is not in Delta")
        cases: list[CostCase] = []
        for lit, s in (((i, True), rs), ((i, False), hs)):
            cases.extend(((lit, *g), v) for g, v in _eval_cost(s.cost, binding, task, guards))
    else:
        s = rs if rs is not None else hs
        assert s is not None
        cases = _eval_cost(s.cost, binding, task, guards)
    if len({v for _, v in cases}) == 1:  # same value in every case: no dependency
        return (((), cases[0][1]),)
    return tuple(cases)


@dataclass(frozen=True)
class _LiftedComponents:
    """One schema's lifted components with their guards, shared by all its groundings."""

    exists: Guard
    pre: tuple[tuple[Atom, Guard], ...]
    negpre: tuple[tuple[Atom, Guard], ...]
    add: tuple[tuple[Atom, Guard], ...]
    delete: tuple[tuple[Atom, Guard], ...]


def _lifted_components(
    name: str, rs: Schema | None, hs: Schema | None, guards: _Guards
) -> _LiftedComponents:
    s = rs if rs is not None else hs
    assert s is not None
    exists = guards.of(Feature(SCHEMA, name, s.params), rs is not None, hs is not None)

    def part(kind: str, attr: str) -> tuple[tuple[Atom, Guard], ...]:
        ra = getattr(rs, attr) if rs is not None else frozenset()
        ha = getattr(hs, attr) if hs is not None else frozenset()
        return tuple(
            (a, guards.of(Feature(kind, name, a), a in ra, a in ha)) for a in sorted(ra | ha)
        )

    return _LiftedComponents(
        exists, part(PRE, "pre"), part(NEGPRE, "negpre"), part(ADD, "add"), part(DEL, "delete")
    )


def _entries(
    lifted: tuple[tuple[Atom, Guard], ...],
    binding: Binding,
    ids: dict[Atom, int],
    keep_unknown: bool,
) -> tuple[Entry, ...]:
    """Ground entries, one per lifted atom; identical entries and entries made redundant by an
    unguarded entry of the same atom are merged.  Atoms outside ``ids`` are never true in any
    family member: they are given a fresh id when ``keep_unknown`` (preconditions), else
    dropped (negative preconditions, deletes)."""
    out: dict[int, set[Guard]] = {}
    for a, g in lifted:
        atom = (a[0],) + tuple(binding.get(x, x) for x in a[1:])
        i = ids.get(atom)
        if i is None:
            if not keep_unknown:
                continue
            i = ids[atom] = len(ids)
        out.setdefault(i, set()).add(g)
    res: list[Entry] = []
    for i, gs in out.items():
        if None in gs:
            res.append((i, None))
        else:
            res.extend((i, g) for g in sorted(gs))  # type: ignore[type-var]
    return tuple(res)


def ground(task: TwoModelTask) -> GroundFamily:
    """Ground every model ``human + E`` of ``task`` at once, with guarded components."""
    robot, human = task.robot, task.human
    guards = _Guards(task.delta)
    objects = sorted(robot.objects | human.objects)
    schemas = _relaxed_schemas(robot, human)
    reached, reachable = _relaxed_reachability(schemas, robot.init | human.init, objects)

    # atom ids: reached atoms first (sorted), then goal atoms and unreachable preconditions
    ids: dict[Atom, int] = {a: i for i, a in enumerate(sorted(reached))}
    for a in sorted(robot.goal | human.goal):
        ids.setdefault(a, len(ids))

    lifted = {
        s.name: _lifted_components(
            s.name, robot.schemas.get(s.name), human.schemas.get(s.name), guards
        )
        for s in schemas
    }
    params = {s.name: s.params for s in schemas}
    actions: list[GroundAction] = []
    for name, args in reachable:
        comp = lifted[name]
        b = dict(zip(params[name], args, strict=True))
        actions.append(
            GroundAction(
                name=name,
                args=args,
                exists=comp.exists,
                pre=_entries(comp.pre, b, ids, True),
                negpre=_entries(comp.negpre, b, ids, False),
                add=_entries(comp.add, b, ids, True),
                delete=_entries(comp.delete, b, ids, False),
                cost=_cost_cases(
                    name, robot.schemas.get(name), human.schemas.get(name), b, task, guards
                ),
            )
        )

    def state_entries(kind: str, r: frozenset[Atom], h: frozenset[Atom]) -> tuple[Entry, ...]:
        return tuple(
            (ids[a], guards.of(Feature(kind, "", a), a in r, a in h)) for a in sorted(r | h)
        )

    atoms = tuple(sorted(ids, key=ids.__getitem__))
    return GroundFamily(
        atoms=atoms,
        n_updates=len(task.delta),
        actions=tuple(actions),
        init=state_entries(INIT, robot.init, human.init),
        goal=state_entries(GOAL, robot.goal, human.goal),
    )


def ground_model(model: Model) -> GroundTask:
    """Ground a single model (the family of ``TwoModelTask(model, model)``, which has no
    updates)."""
    return ground(TwoModelTask.from_models(model, model)).specialize(frozenset())
