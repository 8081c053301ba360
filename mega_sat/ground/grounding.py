"""Grounding a two-model task into one :class:`GroundFamily` that covers every ``human + E``.

Reachability is computed once, on the most permissive combination of the two models: the union
of both initial states, every schema either model has, the union of both models' add effects,
and only the positive preconditions *both* models share (a precondition only one model has is a
Delta feature, so some ``E`` removes it).  A schema only one model has keeps its signature (the
type preconditions of its parameters), since it never exists in a family member without them;
its other preconditions are Delta features of their own.  Deletes and negative preconditions
are ignored.  The relaxed fixpoint of that combination over-approximates the reachable atoms and
applicable ground actions of every family member, so no action any ``human + E`` could use is
missing.

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
from collections.abc import Callable, Iterable, Iterator, Mapping
from dataclasses import dataclass
from itertools import groupby, product
from operator import itemgetter
from typing import Protocol

from mega_sat.errors import FamilyNotCompiled, PDDLError
from mega_sat.ground.family import CostCase, Entry, GroundAction, GroundFamily, GroundTask, Guard
from mega_sat.model.features import (
    ADD,
    COST,
    DEL,
    FVALUE,
    GOAL,
    INIT,
    NEGGOAL,
    NEGPRE,
    PRE,
    SCHEMA,
    Feature,
    Update,
    cost_str,
)
from mega_sat.model.lifted import EQUALITY, Atom, CostTerm, Model, Schema, atom_pddl
from mega_sat.model.task import TwoModelTask

Binding = dict[str, str]

VECTORISE_MIN_ROWS = 256
"""Groundings of one schema from which numpy pays for itself (below, per action is faster)."""

_CHECK_EVERY = 4096
_VECTOR_ROWS = 1 << 15
"""Actions grounded per vectorised block: the deadline is checked between blocks."""
"""Ground actions between two deadline checks: frequent enough to stop within a fraction of a
second, rare enough to cost nothing measurable."""


class Deadline(Protocol):
    """What grounding needs of a time limit: ``check()`` raises once it has passed."""

    def check(self) -> None: ...


@dataclass(frozen=True)
class _RelaxedSchema:
    """A schema of the permissive union model used only for reachability."""

    name: str
    params: tuple[str, ...]
    pre: tuple[Atom, ...]
    add: tuple[Atom, ...]
    distinct: tuple[Atom, ...] = ()
    """Negated equalities both models share: a grounding that makes one ``(= o o)`` is dead in
    every member of the family, since ``(= o o)`` holds in both initial states and nothing
    changes it."""


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


ArgGetter = Callable[[tuple[str, ...]], tuple[str, ...]]
"""Maps a ground action's arguments to the arguments of one of its atoms."""


def _arg_getter(lifted_args: tuple[str, ...], params: tuple[str, ...]) -> ArgGetter:
    """Compile the substitution of ``params`` in ``lifted_args`` into tuple indexing: grounding
    runs it once per atom of every ground action, so it avoids building a binding dict."""
    pos = {p: k for k, p in enumerate(params)}
    if all(x in pos for x in lifted_args):
        idx = [pos[x] for x in lifted_args]
        if not idx:
            return lambda args: ()
        if len(idx) == 1:
            k = idx[0]
            return lambda args: (args[k],)
        return itemgetter(*idx)
    spec = tuple((pos.get(x), x) for x in lifted_args)
    return lambda args: tuple(c if k is None else args[k] for k, c in spec)


GroundingTemplate = tuple[tuple[str, ArgGetter, Guard], ...]
"""Guarded lifted atoms of one schema component, compiled for :func:`_entries`."""


def _template(lifted: tuple[tuple[Atom, Guard], ...], params: tuple[str, ...]) -> GroundingTemplate:
    return tuple((a[0], _arg_getter(a[1:], params), g) for a, g in lifted)


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
    # unary preconditions on distinct unbound parameters (typically the types of a schema's
    # remaining parameters) bind independently: their product, without recursion
    names = [p[1] for p in pres if len(p) == 2 and _is_var(p[1]) and p[1] not in binding]
    if len(names) == len(pres) and len(set(names)) == len(names):
        options = [[a[1] for a in index.candidates(p, binding)] for p in pres]
        for values in product(*options):
            b = dict(binding)
            b.update(zip(names, values, strict=True))
            yield b
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
    static_equality = any(EQUALITY in m.predicates for m in (robot, human)) and _static_equality(
        robot, human
    )
    for name in sorted(set(robot.schemas) | set(human.schemas)):
        rs, hs = robot.schemas.get(name), human.schemas.get(name)
        distinct: frozenset[Atom] = frozenset()
        if rs is not None and hs is not None:
            pre = rs.pre & hs.pre
            add = rs.add | hs.add
            params = rs.params
            if static_equality:
                distinct = frozenset(a for a in rs.negpre & hs.negpre if a[0] == EQUALITY)
        else:
            s = rs if rs is not None else hs
            assert s is not None
            # a one-model schema's components other than its signature are Delta features of
            # their own, so some E adds the schema with only its parameter types
            pre, add, params = s.signature, s.add, s.params
        out.append(
            _RelaxedSchema(
                name, params, tuple(sorted(pre)), tuple(sorted(add)), tuple(sorted(distinct))
            )
        )
    return out


def _static_equality(robot: Model, human: Model) -> bool:
    """Whether ``=`` is PDDL's equality in both models: ``(= o o)`` in both initial states for
    every object, and no schema adding or deleting an ``=`` atom."""
    objects = robot.objects | human.objects
    identity = {(EQUALITY, o, o) for o in objects}
    return (
        identity <= robot.init
        and identity <= human.init
        and not any(
            a[0] == EQUALITY
            for m in (robot, human)
            for sc in m.schemas.values()
            for a in (*sc.add, *sc.delete)
        )
    )


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


def _unary_slots(s: _RelaxedSchema) -> list[str | None] | None:
    """Per parameter, the predicate of its one unary precondition (None: unconstrained), when
    every precondition of ``s`` is unary on a parameter of its own (typically a schema's
    signature); None otherwise.  Such a schema's groundings are a product of object sets."""
    slots: list[str | None] = [None] * len(s.params)
    pos = {p: k for k, p in enumerate(s.params)}
    for p in s.pre:
        if len(p) != 2 or p[1] not in pos or slots[pos[p[1]]] is not None:
            return None
        slots[pos[p[1]]] = p[0]
    return slots


def _relaxed_reachability(
    schemas: list[_RelaxedSchema],
    init: Iterable[Atom],
    objects: list[str],
    deadline: Deadline | None = None,
) -> tuple[set[Atom], list[tuple[str, tuple[str, ...]]]]:
    """Relaxed fixpoint: reachable atoms and reachable ``(schema, args)`` pairs (sorted)."""
    by_pred: dict[str, list[tuple[_RelaxedSchema, int]]] = {}
    for s in schemas:
        for k, p in enumerate(s.pre):
            by_pred.setdefault(p[0], []).append((s, k))
    reached: set[Atom] = set()
    queue: deque[Atom] = deque()
    actions: dict[str, set[tuple[str, ...]]] = {s.name: set() for s in schemas}
    adds = {s.name: [(a[0], _arg_getter(a[1:], s.params)) for a in s.add] for s in schemas}
    distinct = {s.name: [_arg_getter(a[1:], s.params) for a in s.distinct] for s in schemas}
    dead: set[tuple[str, tuple[str, ...]]] = set()
    unary = {s.name: _unary_slots(s) for s in schemas}
    count = 0

    def fire(s: _RelaxedSchema, groundings: Iterable[tuple[str, ...]]) -> None:
        nonlocal count
        schema_adds, seen, differ = adds[s.name], actions[s.name], distinct[s.name]
        for args in groundings:
            if args in seen:
                continue
            seen.add(args)
            if differ and any(len(set(get(args))) == 1 for get in differ):
                dead.add((s.name, args))  # it asks two equal objects to differ
                continue
            count += 1
            if deadline is not None and count % _CHECK_EVERY == 0:
                deadline.check()
            for pred, get in schema_adds:
                g = (pred,) + get(args)
                if g not in reached:
                    reached.add(g)
                    queue.append(g)

    for a in sorted(set(init)):
        if a not in reached:
            reached.add(a)
            queue.append(a)
    for s in schemas:
        if not s.pre:
            fire(s, _ground_args(s, {}, objects))
    index = _AtomIndex()
    while queue:
        atom = queue.popleft()
        index.add(atom)
        for s, k in by_pred.get(atom[0], ()):
            slots = unary[s.name]
            if slots is not None and len(atom) == 2:
                # the new atom fixes its parameter; the others range over what is reached
                fixed = s.params.index(s.pre[k][1])
                options = [
                    [atom[1]]
                    if j == fixed
                    else objects
                    if pred is None
                    else [a[1] for a in index.by_pred.get(pred, ())]
                    for j, pred in enumerate(slots)
                ]
                fire(s, product(*options))
                continue
            b = _unify(s.pre[k], atom, {})
            if b is None:
                continue
            rest = list(s.pre[:k] + s.pre[k + 1 :])
            for full in _join(rest, b, index):
                fire(s, _ground_args(s, full, objects))
    index_of = {o: k for k, o in enumerate(objects)}
    return reached, [
        (name, args)
        for name in sorted(actions)
        for args in _sorted_args(actions[name], index_of)
        if not dead or (name, args) not in dead
    ]


def _sorted_args(rows: set[tuple[str, ...]], index_of: dict[str, int]) -> list[tuple[str, ...]]:
    """``sorted(rows)``; many rows of objects are sorted by their object indices (the objects
    are sorted, so the order is the same) with numpy, which is much faster on tuples."""
    if len(rows) < 1000:
        return sorted(rows)
    import numpy as np  # imported only where it pays: small tasks start faster without it

    from mega_sat.ground.atom_table import object_indices

    listed = list(rows)
    idx = object_indices(listed, index_of)
    if idx is None:
        return sorted(rows)
    return [listed[i] for i in np.lexsort(idx.T[::-1]).tolist()]


def _eval_cost(
    cost: int | CostTerm,
    binding: Mapping[str, str],
    task: TwoModelTask,
    guards: _Guards,
    schema: Schema | None = None,
    side: str = "",
) -> list[CostCase]:
    """Cost cases of one cost expression: a function term's value is the robot's when its
    FVALUE update is selected and the human's otherwise (both models define the same terms).
    ``schema`` (whose grounding this is) and ``side`` (whose cost it is) are for the message
    when the term has no value."""
    if isinstance(cost, int):
        return [((), cost)]
    term = tuple(binding.get(x, x) for x in cost)
    rv, hv = task.robot.functions.get(term), task.human.functions.get(term)
    if rv is None and hv is None:
        step = () if schema is None else (schema.name, *(binding[p] for p in schema.params))
        raise _undefined_value(term, task, step, side)
    if rv is None or hv is None or rv == hv:
        v = rv if rv is not None else hv
        assert v is not None
        return [((), v)]
    i = guards.index.get((Feature(FVALUE, "", term + (str(rv),)), True))
    if i is None:
        raise AssertionError(f"function value {atom_pddl(term)} differs but is not in Delta")
    return [(((i, True),), rv), (((i, False),), hv)]


def _undefined_value(
    term: CostTerm, task: TwoModelTask, step: tuple[str, ...], side: str
) -> PDDLError:
    """The error for a cost term with a value in neither problem, at the place to mend it.

    The common cause in a model written by someone else is an object that only the human
    problem declares: the human's groundings with it may cost a value of a function whose
    values come from the robot problem (or from both, which must give the same terms), and
    there the object does not exist.  That object's declaration is the place named then;
    otherwise the ``:init`` of the problem that holds the function's values (the robot's,
    unless only the human's domain declares the function), where the value is missing.
    """
    from mega_sat.pddl.loading import line_in_file  # an error path: loading reads the file

    shown = atom_pddl(term)
    whose = f"in the {side}'s model " if side else ""
    needs = f"the cost of ({' '.join(step)}) {whose}is {shown}" if step else f"{shown} is needed"
    robot_problem = task.sources.get("robot_problem")
    for o in term[1:]:
        if o in task.human.objects and o not in task.robot.objects:
            path = task.sources.get("human_problem")
            line = line_in_file(path, "object", (o,))
            return PDDLError(
                f"object '{o}' is declared only in this problem, and {needs}, which has no "
                f"value: declare '{o}' in {robot_problem or 'the robot problem'} too and give "
                f"(= {shown} N) in :init",
                path=path,
                where=None if line is None else f"line {line}",
            )
    # a function only the human's domain declares has its values in the human problem
    own = "robot" if term[0] in task.robot.function_arities else "human"
    path = task.sources.get(f"{own}_problem")
    line = line_in_file(path, "init", ())
    return PDDLError(
        f"cost function value {shown} is not defined: {needs}, and :init gives it no value "
        f"(add (= {shown} N))",
        path=path,
        where=None if line is None else f"line {line}",
    )


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
        for lit, s, side in (((i, True), rs, "robot"), ((i, False), hs, "human")):
            cases.extend(
                ((lit, *g), v) for g, v in _eval_cost(s.cost, binding, task, guards, s, side)
            )
    else:
        s = rs if rs is not None else hs
        assert s is not None
        side = "" if rs is not None and hs is not None else "robot" if rs is not None else "human"
        cases = _eval_cost(s.cost, binding, task, guards, s, side)
    if len({v for _, v in cases}) == 1:  # same value in every case: no dependency
        return (((), cases[0][1]),)
    return tuple(cases)


def _fixed_cost_cases(
    name: str, rs: Schema | None, hs: Schema | None
) -> tuple[CostCase, ...] | None:
    """The cost cases shared by every grounding of a schema whose cost is one constant in
    every family member (the cases :func:`_cost_cases` gives), or None when they depend on the
    arguments (a cost function) or on an update (the models disagree)."""
    if any(s is not None and not isinstance(s.cost, int) for s in (rs, hs)):
        return None
    if rs is not None and hs is not None and rs.cost != hs.cost:
        return None
    s = rs if rs is not None else hs
    assert s is not None and isinstance(s.cost, int)
    return (((), s.cost),)


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
    # the signature of a one-model schema holds whenever the schema exists
    own_signature = s.signature if rs is None or hs is None else frozenset()

    def part(kind: str, attr: str) -> tuple[tuple[Atom, Guard], ...]:
        ra = getattr(rs, attr) if rs is not None else frozenset()
        ha = getattr(hs, attr) if hs is not None else frozenset()
        return tuple(
            (
                a,
                None
                if kind == PRE and a in own_signature
                else guards.of(Feature(kind, name, a), a in ra, a in ha),
            )
            for a in sorted(ra | ha)
        )

    return _LiftedComponents(
        exists, part(PRE, "pre"), part(NEGPRE, "negpre"), part(ADD, "add"), part(DEL, "delete")
    )


def _entries(
    template: GroundingTemplate,
    args: tuple[str, ...],
    ids: dict[Atom, int],
    keep_unknown: bool,
) -> tuple[Entry, ...]:
    """Ground entries, one per lifted atom; identical entries and entries made redundant by an
    unguarded entry of the same atom are merged.  Atoms outside ``ids`` are never true in any
    family member: they are given a fresh id when ``keep_unknown`` (preconditions), else
    dropped (negative preconditions, deletes)."""
    out: dict[int, list[Guard]] = {}
    for pred, get, g in template:
        atom = (pred,) + get(args)
        i = ids.get(atom)
        if i is None:
            if not keep_unknown:
                continue
            i = ids[atom] = len(ids)
        gs = out.get(i)
        if gs is None:
            out[i] = [g]
        else:
            gs.append(g)
    return merge_guards(out)


def merge_guards(guards_by_atom: dict[int, list[Guard]]) -> tuple[Entry, ...]:
    """One entry per atom and distinct guard, in first-occurrence order of the atoms; an
    unguarded entry makes the atom's guarded ones redundant."""
    res: list[Entry] = []
    for i, gs in guards_by_atom.items():
        if len(gs) == 1:
            res.append((i, gs[0]))
        elif None in gs:
            res.append((i, None))
        else:
            res.extend((i, g) for g in sorted(set(gs)))  # type: ignore[type-var]
    return tuple(res)


def ground(
    task: TwoModelTask,
    *,
    deadline: Deadline | None = None,
    vectorise_from: int | None = VECTORISE_MIN_ROWS,
) -> GroundFamily:
    """Ground every model ``human + E`` of ``task`` at once, with guarded components.

    ``deadline`` (anything with a ``check()`` that raises once time is up) is checked every
    few thousand ground actions, so a grounding too large for the time limit stops in time.
    Schemas with at least ``vectorise_from`` groundings are grounded through
    :class:`~mega_sat.ground.atom_table.AtomTable`, the others action by action (``None``: every
    schema); both give the same family, and the tests compare them.
    """
    robot, human = task.robot, task.human
    guards = _Guards(task.delta)
    objects = sorted(robot.objects | human.objects)
    schemas = _relaxed_schemas(robot, human)
    reached, reachable = _relaxed_reachability(schemas, robot.init | human.init, objects, deadline)

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
    fixed_costs = {
        s.name: _fixed_cost_cases(s.name, robot.schemas.get(s.name), human.schemas.get(s.name))
        for s in schemas
    }
    table = None  # an AtomTable, made for the first schema large enough to vectorise
    actions: list[GroundAction] = []
    for name, block in groupby(reachable, key=itemgetter(0)):
        arg_rows = [args for _, args in block]
        comp = lifted[name]
        parts = (comp.pre, comp.negpre, comp.add, comp.delete)
        entries = None
        if vectorise_from is not None and len(arg_rows) >= vectorise_from:
            if table is None:
                from mega_sat.ground.atom_table import AtomTable

                table = AtomTable(ids, objects)
            # in blocks of rows, the deadline checked between them: one block of a few
            # hundred thousand actions takes seconds
            entries = []
            for start in range(0, len(arg_rows), _VECTOR_ROWS):
                got = table.ground_block(
                    parts, params[name], arg_rows[start : start + _VECTOR_ROWS]
                )
                if got is None:
                    entries = None
                    break
                entries += got
                if deadline is not None:
                    deadline.check()
        if entries is None:  # per action (the reference path)
            if table is not None:
                table.forget()  # the path below may give atoms fresh ids
            templates = [_template(part, params[name]) for part in parts]
            entries = []
            for args in arg_rows:
                if deadline is not None and len(entries) % _CHECK_EVERY == 0:
                    deadline.check()
                entries.append(
                    tuple(
                        _entries(t, args, ids, keep)
                        for t, keep in zip(templates, (True, False, True, False), strict=True)
                    )
                )
        for k, (args, (pre, negpre, add, delete)) in enumerate(zip(arg_rows, entries, strict=True)):
            if deadline is not None and k % _CHECK_EVERY == 0:
                deadline.check()
            cost = fixed_costs[name]
            if cost is None:
                b = dict(zip(params[name], args, strict=True))
                cost = _cost_cases(
                    name, robot.schemas.get(name), human.schemas.get(name), b, task, guards
                )
            actions.append(
                GroundAction(
                    name=name,
                    args=args,
                    exists=comp.exists,
                    pre=pre,
                    negpre=negpre,
                    add=add,
                    delete=delete,
                    cost=cost,
                )
            )

    def state_entries(kind: str, r: frozenset[Atom], h: frozenset[Atom]) -> tuple[Entry, ...]:
        return tuple(
            (ids[a], guards.of(Feature(kind, "", a), a in r, a in h)) for a in sorted(r | h)
        )

    init = state_entries(INIT, robot.init, human.init)
    goal = state_entries(GOAL, robot.goal, human.goal)
    negative = {
        ids[a]: guards.of(Feature(NEGGOAL, "", a), a in robot.neggoal, a in human.neggoal)
        for a in sorted(robot.neggoal | human.neggoal)
        if a in ids  # an atom no model reaches is false in every state: nothing to compile
    }
    if negative:
        # the domain that states an action, for the one error below
        sources = {
            name: task.sources.get("robot_domain" if name in robot.schemas else "human_domain")
            for name in lifted
        }
        actions, init, goal = _complement_negative_goals(
            negative, ids, actions, init, goal, sources
        )
    atoms = tuple(sorted(ids, key=ids.__getitem__))
    return GroundFamily(
        atoms=atoms,
        n_updates=len(task.delta),
        actions=tuple(actions),
        init=init,
        goal=goal,
    )


def complement_atom(atom: Atom) -> Atom:
    """The atom that holds exactly when ``atom`` does not, for negative goals: its predicate
    ``not p`` is no PDDL name, so it never meets one of the model's."""
    return (f"not {atom[0]}", *atom[1:])


def _complement_negative_goals(
    negative: dict[int, Guard],
    ids: dict[Atom, int],
    actions: list[GroundAction],
    init: tuple[Entry, ...],
    goal: tuple[Entry, ...],
    sources: dict[str, str | None],
) -> tuple[list[GroundAction], tuple[Entry, ...], tuple[Entry, ...]]:
    """Negative goals as positive goals on complement atoms, kept in sync by every action and
    under the same guards, so that every model of the family stays plain STRIPS with positive
    goals (encodings/sequential.md, "Negative goals").

    An action adding ``p`` deletes its complement under the add's guard.  One deleting ``p``
    adds the complement under the delete's guard, unless the action also adds ``p`` (PDDL's
    add wins): then under the conjunction of the delete's guard and no add's, which is one
    literal (or none) when the delete is unguarded and there is at most one guarded add.
    Anything else would need a guard of two literals, and is refused (a :class:`PDDLError`
    naming the file ``sources`` gives for the action's schema).
    """
    names = {i: a for a, i in ids.items()}
    comp = {}
    for p in sorted(negative):
        comp[p] = ids[complement_atom(names[p])] = len(ids)
    out = []
    for act in actions:
        adds: dict[int, list[Guard]] = {}
        for p, g in act.add:
            if p in comp:
                adds.setdefault(p, []).append(g)
        dels = [(p, g) for p, g in act.delete if p in comp]
        if not adds and not dels:
            out.append(act)
            continue
        new_add: list[Entry] = []
        for p, g in dels:
            a_gs = adds.get(p, [])
            if not a_gs:
                new_add.append((comp[p], g))
            elif None in a_gs:
                continue  # p ends true whenever the action runs
            elif g is None and len(a_gs) == 1:
                i, v = a_gs[0]  # type: ignore[misc]
                new_add.append((comp[p], (i, not v)))
            else:
                # an inequality can rule out a grounding that repeats an object, as when
                # (at ?from) and (at ?to) meet at ?from = ?to
                hint = (
                    f" (an inequality precondition of '{act.name}' in both models that rules "
                    "out this grounding avoids it)"
                    if len(set(act.args)) < len(act.args)
                    else ""
                )
                raise FamilyNotCompiled(
                    f"negative goal (not {atom_pddl(names[p])}): action "
                    f"({' '.join((act.name, *act.args))}) both adds and deletes that atom under "
                    f"two different updates, which mega-sat cannot compile{hint}",
                    path=sources.get(act.name),
                )
        new_del = [(comp[p], g) for p, gs in adds.items() for g in gs]
        out.append(
            GroundAction(
                name=act.name,
                args=act.args,
                exists=act.exists,
                pre=act.pre,
                negpre=act.negpre,
                add=act.add + tuple(new_add),
                delete=act.delete + tuple(new_del),
                cost=act.cost,
            )
        )
    in_init = {p: g for p, g in init if p in comp}
    extra_init: list[Entry] = []
    for p in sorted(comp):
        if p not in in_init:
            extra_init.append((comp[p], None))
        elif in_init[p] is not None:
            i, v = in_init[p]  # type: ignore[misc]
            extra_init.append((comp[p], (i, not v)))
    extra_goal = [(comp[p], g) for p, g in negative.items()]
    return out, init + tuple(extra_init), goal + tuple(extra_goal)


def ground_member(
    task: TwoModelTask, selection: frozenset[int]
) -> tuple[TwoModelTask, GroundFamily]:
    """``human + selection`` (the robot's model for every update) as a task of its own and its
    ground family, which has no updates: for a command about one model when the family of all
    of them cannot be compiled (:class:`~mega_sat.errors.FamilyNotCompiled`).  Its one member
    is ``frozenset()``."""
    if selection == task.all_updates:
        model, side = task.robot, "robot"
    else:
        model, side = task.updated_model(selection), "human"
    files = {k: task.sources.get(f"{side}_{k}") for k in ("domain", "problem")}
    sources = {f"{who}_{k}": v for who in ("robot", "human") for k, v in files.items() if v}
    member = TwoModelTask.from_models(model, model, sources=sources)
    return member, ground(member)


def ground_model(model: Model) -> GroundTask:
    """Ground a single model (the family of ``TwoModelTask(model, model)``, which has no
    updates)."""
    return ground(TwoModelTask.from_models(model, model)).specialize(frozenset())
