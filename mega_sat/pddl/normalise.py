"""Turn the ``pddl`` library's Domain and Problem into a normalised :class:`~mega_sat.model.lifted.Model`.

Types are compiled into static unary predicates as :mod:`mega_sat.model.lifted` describes.  With
``:action-costs`` an action without a cost effect costs 0 (the PDDL semantics), and costs come
from the domain whether or not the problem states ``(:metric minimize (total-cost))``.  Equality in
preconditions becomes the static predicate ``=`` (:func:`~mega_sat.model.lifted.with_equality`).
Negative initial literals ``(not p)`` are dropped (closed world), as is ``(= (total-cost) 0)``.  The
input has passed :mod:`mega_sat.pddl.check`, so anything else is a construct the check missed.
"""

from __future__ import annotations

from mega_sat.errors import PDDLError
from mega_sat.model.lifted import (
    EQUALITY,
    Atom,
    CostTerm,
    Model,
    Schema,
    rename_schema,
    tests_equality,
    with_equality,
)
from mega_sat.pddl.check import DomainInfo


def _term(t) -> str:
    from pddl.logic.terms import Variable

    return f"?{t.name}" if isinstance(t, Variable) else str(t.name)


def _atom(p) -> Atom:
    return (str(p.name), *(_term(t) for t in p.terms))


def _conjuncts(formula) -> list:
    """The literals of a (possibly nested, possibly empty) conjunction."""
    from pddl.logic.base import And, Or

    if formula is None:
        return []
    if isinstance(formula, And):
        return [x for op in formula.operands for x in _conjuncts(op)]
    if isinstance(formula, Or) and not formula.operands:  # '()' parses as an empty Or
        return []
    return [formula]


def _unexpected(what: object, path: str) -> PDDLError:
    return PDDLError(f"unsupported construct {what}", path=path)


def _schema(action, uses_costs: bool, path: str) -> Schema:
    from pddl.logic.base import Not
    from pddl.logic.functions import Increase, NumericFunction, NumericValue
    from pddl.logic.predicates import EqualTo, Predicate

    params = tuple(f"?{v.name}" for v in action.parameters)
    signature = frozenset(
        (str(tag), f"?{v.name}")
        for v in action.parameters
        for tag in v.type_tags
        if str(tag) != "object"
    )
    pre: set[Atom] = set(signature)
    negpre: set[Atom] = set()
    for lit in _conjuncts(action.precondition):
        if isinstance(lit, Predicate):
            pre.add(_atom(lit))
        elif isinstance(lit, EqualTo):
            pre.add((EQUALITY, _term(lit.left), _term(lit.right)))
        elif isinstance(lit, Not) and isinstance(lit.argument, Predicate):
            negpre.add(_atom(lit.argument))
        elif isinstance(lit, Not) and isinstance(lit.argument, EqualTo):
            negpre.add((EQUALITY, _term(lit.argument.left), _term(lit.argument.right)))
        else:
            raise _unexpected(lit, path)
    add: set[Atom] = set()
    delete: set[Atom] = set()
    cost: int | CostTerm = 0 if uses_costs else 1
    for lit in _conjuncts(action.effect):
        if isinstance(lit, Predicate):
            add.add(_atom(lit))
        elif isinstance(lit, Not) and isinstance(lit.argument, Predicate):
            delete.add(_atom(lit.argument))
        elif isinstance(lit, Increase):
            value = lit.operands[1]
            if isinstance(value, NumericValue):
                cost = int(value.value)
            elif isinstance(value, NumericFunction):
                cost = (str(value.name), *(_term(t) for t in value.terms))
            else:
                raise _unexpected(value, path)
        else:
            raise _unexpected(lit, path)
    return Schema(
        str(action.name),
        params,
        frozenset(pre),
        frozenset(negpre),
        frozenset(add),
        frozenset(delete),
        cost,
        signature,
    )


def _type_atoms(obj: str, typ: str, types: dict[str, str]) -> set[Atom]:
    """``(t obj)`` for ``typ`` and each of its supertypes except ``object``."""
    out = set()
    while typ != "object":
        out.add((typ, obj))
        typ = types.get(typ, "object")
    return out


def to_model(domain, problem, info: DomainInfo, domain_path: str, problem_path: str) -> Model:
    """The :class:`Model` of a checked domain and problem; ``info`` is the domain check's."""
    from pddl.logic.base import Not
    from pddl.logic.functions import EqualTo as FunctionEqualTo
    from pddl.logic.predicates import Predicate

    types = info.types  # includes supertypes that are never declared on their own
    uses_costs = ":action-costs" in info.requirements
    schemas = {}
    for action in sorted(domain.actions, key=lambda a: str(a.name)):
        s = _schema(action, uses_costs, domain_path)
        if s.name in info.variables:
            s = rename_schema(s, info.variables[s.name])  # the file's own names
        schemas[s.name] = s

    predicates = {str(p.name): len(p.terms) for p in domain.predicates}
    type_preds = frozenset(t for t in types if t != "object")
    predicates.update((t, 1) for t in type_preds)

    objects: dict[str, str] = {}
    init: set[Atom] = set()
    for c in (*domain.constants, *problem.objects):
        tags = [str(t) for t in c.type_tags] or ["object"]
        objects[str(c.name)] = tags[0]
        init |= _type_atoms(str(c.name), tags[0], types)

    functions: dict[CostTerm, int] = {}
    for el in problem.init:
        if isinstance(el, Predicate):
            init.add(_atom(el))
        elif isinstance(el, FunctionEqualTo):
            term, value = el.operands
            if str(term.name) == "total-cost":
                continue
            functions[(str(term.name), *(_term(t) for t in term.terms))] = int(value.value)
        elif not isinstance(el, Not):  # negative initial literals: closed world, no-op
            raise _unexpected(el, problem_path)

    goal: set[Atom] = set()
    neggoal: set[Atom] = set()
    for lit in _conjuncts(problem.goal):
        if isinstance(lit, Not) and isinstance(lit.argument, Predicate):
            neggoal.add(_atom(lit.argument))
        elif isinstance(lit, Predicate):
            goal.add(_atom(lit))
        else:
            raise _unexpected(lit, problem_path)

    model = Model(
        domain_name=str(domain.name),
        problem_name=str(problem.name),
        predicates=predicates,
        schemas=schemas,
        objects=frozenset(objects),
        init=frozenset(init),
        goal=frozenset(goal),
        neggoal=frozenset(neggoal),
        type_predicates=type_preds,
        functions=functions,
        function_arities=dict(info.functions),
        uses_costs=uses_costs,
    )
    return with_equality(model, model.objects) if tests_equality(schemas.values()) else model
