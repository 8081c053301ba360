"""Lifted STRIPS models: the one data type every stage of mega-sat starts from.

A :class:`Model` is a planning problem ``M = <D, I, G>`` in a normalised, untyped form:

* names are lower-case (PDDL is case-insensitive);
* types are compiled away: an object of type ``t`` (and of every supertype of ``t`` except
  ``object``) gets the static atom ``(t obj)`` in the initial state, and an action parameter
  ``?x - t`` becomes the precondition ``(t ?x)``.  This makes a difference in type hierarchies an
  ordinary, explainable model difference (an initial-state or precondition feature), which is
  what the two-model task needs;
* equality is compiled away too: ``(= ?x ?y)`` in a precondition is the atom
  ``(= ?x ?y)`` of the static predicate :data:`EQUALITY`, whose initial-state atoms are
  ``(= o o)`` for every object ``o`` (:func:`with_equality`).  A negated equality is a
  negative precondition.  Nothing adds or deletes it;
* action costs are per schema: a constant or a static function term whose ground values come
  from the problem's initial state.

Atoms are plain tuples ``(predicate, arg, ...)``; lifted arguments start with ``?``.
"""

from __future__ import annotations

from collections.abc import Iterable, Mapping
from dataclasses import dataclass, field, replace

Atom = tuple[str, ...]
"""``(predicate, arg1, ...)``; arguments are object names or ``?param`` variables."""

EQUALITY = "="
"""The predicate of PDDL's built-in equality, static: its atoms are ``(= o o)``."""

CostTerm = tuple[str, ...]
"""A static function term such as ``('road-length', '?from', '?to')``."""


PlanStep = tuple[str, ...]
"""One step of a plan, ``(action, arg1, ...)``, lower-case."""


def step_str(step: PlanStep) -> str:
    return "(" + " ".join(step) + ")"


def atom_str(atom: Atom) -> str:
    """Render an atom the way the paper prints features: ``clear_path p1 p8``."""
    return " ".join(atom)


def atom_pddl(atom: Atom) -> str:
    """Render an atom as PDDL: ``(clear_path p1 p8)``."""
    return "(" + " ".join(atom) + ")"


@dataclass(frozen=True)
class Schema:
    """A lifted action schema.

    ``cost`` is an ``int`` or a :data:`CostTerm` evaluated in the problem's function table.
    ``signature`` holds the type atoms ``(t ?x)`` of the parameter list (they are also in
    ``pre``): a schema only one model has enters or leaves the other model together with them,
    so they are part of its existence update rather than updates of their own.
    """

    name: str
    params: tuple[str, ...]
    pre: frozenset[Atom] = frozenset()
    negpre: frozenset[Atom] = frozenset()
    add: frozenset[Atom] = frozenset()
    delete: frozenset[Atom] = frozenset()
    cost: int | CostTerm = 1
    signature: frozenset[Atom] = frozenset()

    def param_types(self) -> tuple[str, ...]:
        """The declared type of each parameter ('' when untyped), from ``signature``."""
        by_param = {a[1]: a[0] for a in sorted(self.signature)}
        return tuple(by_param.get(p, "") for p in self.params)


@dataclass(frozen=True)
class Model:
    """A complete planning problem (domain + problem) in normalised form.

    ``predicates`` maps every predicate name (type predicates included) to its arity.
    ``type_predicates`` names the predicates that stand for PDDL types, so writers and docs can
    tell them apart.  ``functions`` holds the ground values of static cost functions.
    ``uses_costs`` records whether the domain declared ``:action-costs``; without it every
    action costs 1.  ``goal`` holds the atoms the goal requires true, ``neggoal`` those it
    requires false.
    """

    domain_name: str
    problem_name: str
    predicates: Mapping[str, int]
    schemas: Mapping[str, Schema]
    objects: frozenset[str]
    init: frozenset[Atom]
    goal: frozenset[Atom]
    type_predicates: frozenset[str] = frozenset()
    functions: Mapping[CostTerm, int] = field(default_factory=dict)
    function_arities: Mapping[str, int] = field(default_factory=dict)
    uses_costs: bool = False
    neggoal: frozenset[Atom] = frozenset()
    """Atoms the goal requires false (PDDL ``(not (p ...))`` in ``:goal``)."""

    def schema_cost(self, schema: Schema, args: tuple[str, ...]) -> int:
        """Cost of ``schema`` applied to ``args`` in this model.

        Raises ``KeyError`` when a cost function value is missing from the problem.
        """
        if isinstance(schema.cost, int):
            return schema.cost
        binding = dict(zip(schema.params, args, strict=True))
        term = tuple(binding.get(x, x) for x in schema.cost)
        return self.functions[term]


def unused_name(base: str, taken: set[str]) -> str:
    """``base-v``, or ``base-v1``, ``base-v2``, ... : the first not in ``taken``, which gets it."""
    k, name = 0, f"{base}-v"
    while name in taken:
        k += 1
        name = f"{base}-v{k}"
    taken.add(name)
    return name


def rename_schema(s: Schema, names: Mapping[str, str], *, heads: bool = False) -> Schema:
    """``s`` with every name of ``names`` replaced by its value, all at once: parameters,
    arguments of atoms and of the cost term; with ``heads`` also the schema's name and the
    predicate and function names."""

    def one(t: tuple[str, ...]) -> tuple[str, ...]:
        first = names.get(t[0], t[0]) if heads else t[0]
        return (first, *(names.get(x, x) for x in t[1:]))

    def atoms(xs: frozenset[Atom]) -> frozenset[Atom]:
        return frozenset(one(a) for a in xs)

    return Schema(
        names.get(s.name, s.name) if heads else s.name,
        tuple(names.get(p, p) for p in s.params),
        atoms(s.pre),
        atoms(s.negpre),
        atoms(s.add),
        atoms(s.delete),
        s.cost if isinstance(s.cost, int) else one(s.cost),
        atoms(s.signature),
    )


def tests_equality(schemas: Iterable[Schema]) -> bool:
    """Whether a precondition of ``schemas`` is an equality or a negated one."""
    return any(a[0] == EQUALITY for s in schemas for a in (*s.pre, *s.negpre))


def has_equality(model: Model) -> bool:
    """Whether ``model`` holds the equality predicate (some model of its task uses it)."""
    return EQUALITY in model.predicates


def with_equality(model: Model, objects: frozenset[str]) -> Model:
    """``model`` with the equality predicate and the atoms ``(= o o)`` of every object of
    ``objects`` added (the same set for both models of a task, and for the robot model of
    every human model, so equality is never a difference)."""
    return replace(
        model,
        predicates={**model.predicates, EQUALITY: 2},
        init=model.init | {(EQUALITY, o, o) for o in objects},
    )


def _canonical(atoms: frozenset[Atom], positive: bool) -> frozenset[Atom]:
    out = set()
    for a in atoms:
        if a[0] == EQUALITY and len(a) == 3:
            if positive and a[1] == a[2]:
                continue  # (= ?x ?x) always holds
            a = (EQUALITY, *sorted(a[1:]))
        out.add(a)
    return frozenset(out)


def canonical_equalities(model: Model) -> Model:
    """``model`` with each equality written one way: ``(= ?to ?from)`` as ``(= ?from ?to)``
    (equality is symmetric) and without the always-true ``(= ?x ?x)``, so that two models that
    say the same differ in no equality feature."""
    schemas = {
        n: replace(s, pre=_canonical(s.pre, True), negpre=_canonical(s.negpre, False))
        for n, s in model.schemas.items()
    }
    return replace(model, schemas=schemas)
