"""Hypothesis strategies for random small planning models and two-model tasks.

Not a test file: the grounding, search, oracle and engine tests import it for cross-checks.

* :func:`models` — a random small STRIPS :class:`Model` (2-4 predicates of arity 0-2, 2-3
  objects, 2-4 schemas with 0-2 parameters (some typed by a unary precondition in their
  signature), random preconditions, negative preconditions, add
  and delete effects, costs 1-3 (optionally 0-3, optionally a static cost function), random
  initial state and goal).  The number of ground atoms is capped (``max_atoms``), so a model has
  at most ``2 ** max_atoms`` states and usually far fewer reachable ones.
* :func:`two_model_tasks` — a robot model and a human model derived from it by random flips of
  features (preconditions, effects, initial and goal atoms, schema costs, function values, and
  occasionally a schema only one model has), as ``TwoModelTask.from_models(robot, human)`` with
  ``len(task.delta) <= max_delta``.
* :func:`plans` — random action sequences for a model, mostly walks through applicable actions
  (so they get past the first step) with occasional arbitrary or malformed steps.
* :func:`selections` — random subsets of a task's Delta.
"""

from __future__ import annotations

from dataclasses import replace
from itertools import product

from hypothesis import strategies as st

from mega_sat.model.lifted import Atom, Model, PlanStep, Schema
from mega_sat.model.task import Selection, TwoModelTask

PARAMS = ("?x", "?y")
FUNCTION = "c"


def ground_atoms(predicates: dict[str, int], objects: list[str]) -> list[Atom]:
    """Every ground atom over ``objects``, sorted."""
    return sorted((p, *args) for p, n in predicates.items() for args in product(objects, repeat=n))


def lifted_atoms(predicates: dict[str, int], params: tuple[str, ...]) -> list[Atom]:
    """Every lifted atom over a schema's parameters, sorted."""
    return sorted((p, *args) for p, n in predicates.items() for args in product(params, repeat=n))


@st.composite
def _schema(draw, name: str, predicates: dict[str, int], cost_values, function_costs: bool):
    k = draw(st.integers(0, 2))
    params = PARAMS[:k]
    atoms = lifted_atoms(predicates, params)

    def subset(lo: int, hi: int) -> frozenset[Atom]:
        if not atoms:
            return frozenset()
        return frozenset(draw(st.lists(st.sampled_from(atoms), min_size=lo, max_size=hi)))

    pre = subset(0, 2)
    # a parameter type: a unary precondition on a parameter, declared as part of the signature
    # (it then travels with the schema's existence update when only one model has the schema)
    signature = set()
    for p in params:
        typed = sorted(a for a in pre if a[1:] == (p,))
        if typed and draw(st.booleans()):
            signature.add(draw(st.sampled_from(typed)))
    negpre = (subset(0, 1) - pre) if draw(st.integers(0, 2)) == 0 else frozenset()
    add = subset(1, 3)
    delete = subset(0, 2)
    if function_costs and k and draw(st.integers(0, 3)) == 0:
        cost: int | tuple[str, ...] = (FUNCTION, params[0])
    else:
        cost = draw(cost_values)
    return Schema(name, params, pre, negpre, add, delete, cost, frozenset(signature))


@st.composite
def models(
    draw,
    max_atoms: int = 10,
    allow_zero_cost: bool = False,
    function_costs: bool = True,
) -> Model:
    """A random small STRIPS model (see the module docstring)."""
    n_obj = draw(st.integers(2, 3))
    objects = [f"o{i}" for i in range(n_obj)]
    predicates: dict[str, int] = {}
    budget = max_atoms
    for i in range(draw(st.integers(2, 4))):
        fits = [n for n in (0, 1, 2) if n_obj**n <= budget]
        if not fits:
            break
        n = draw(st.sampled_from(fits))
        predicates[f"p{i}"] = n
        budget -= n_obj**n
    cost_values = st.integers(0 if allow_zero_cost else 1, 3)
    schemas = {}
    for i in range(draw(st.integers(2, 4))):
        s = draw(_schema(f"a{i}", predicates, cost_values, function_costs))
        schemas[s.name] = s
    uses_function = any(not isinstance(s.cost, int) for s in schemas.values())
    functions = {}
    if uses_function:
        functions = {(FUNCTION, o): draw(cost_values) for o in objects}
    atoms = ground_atoms(predicates, objects)
    init = frozenset(draw(st.lists(st.sampled_from(atoms), max_size=max(1, len(atoms) // 2))))
    model = Model(
        domain_name="rand",
        problem_name="rand-1",
        predicates=predicates,
        schemas=schemas,
        objects=frozenset(objects),
        init=init,
        goal=frozenset(),
        functions=functions,
        function_arities={FUNCTION: 1} if uses_function else {},
        uses_costs=True,
    )
    # usually a goal that is not true initially but relaxed-reachable (else mostly unsolvable)
    candidates = sorted(relaxed_reachable(model) - init)
    pool = candidates if candidates and draw(st.integers(0, 4)) else atoms
    goal = frozenset(draw(st.lists(st.sampled_from(pool), min_size=1, max_size=2)))
    return replace(model, goal=goal)


def relaxed_reachable(model: Model) -> frozenset[Atom]:
    """Atoms reachable ignoring deletes and negative preconditions (brute force)."""
    relaxed = replace(
        model,
        schemas={n: replace(s, negpre=frozenset()) for n, s in model.schemas.items()},
    )
    state = frozenset(model.init)
    while True:
        new = set(state)
        for step in applicable_steps(relaxed, state):
            s = model.schemas[step[0]]
            b = dict(zip(s.params, step[1:], strict=True))
            new.update((a[0], *(b.get(x, x) for x in a[1:])) for a in s.add)
        if len(new) == len(state):
            return state
        state = frozenset(new)


def _toggle(atoms: frozenset[Atom], atom: Atom) -> frozenset[Atom]:
    return atoms - {atom} if atom in atoms else atoms | {atom}


@st.composite
def _flip(draw, human: Model, allow_zero_cost: bool) -> Model:
    """One random change of the human model."""
    kind = draw(
        st.sampled_from(
            [
                "pre",
                "pre",
                "negpre",
                "add",
                "add",
                "delete",
                "init",
                "init",
                "goal",
                "cost",
                "fvalue",
                "schema",
            ]
        )
    )
    atoms = ground_atoms(dict(human.predicates), sorted(human.objects))
    if kind in ("init", "goal"):
        a = draw(st.sampled_from(atoms))
        return replace(human, **{kind: _toggle(getattr(human, kind), a)})
    if kind == "fvalue":
        if not human.functions:
            return human
        term = draw(st.sampled_from(sorted(human.functions)))
        value = draw(st.integers(0 if allow_zero_cost else 1, 3))
        return replace(human, functions={**human.functions, term: value})
    if kind == "schema":
        schemas = dict(human.schemas)
        if draw(st.booleans()) and len(schemas) > 1:  # the human lacks one of the robot's
            del schemas[draw(st.sampled_from(sorted(schemas)))]
        else:  # the human believes in an action the robot does not have
            cost_values = st.integers(0 if allow_zero_cost else 1, 3)
            s = draw(_schema("h0", dict(human.predicates), cost_values, False))
            schemas[s.name] = s
        return replace(human, schemas=schemas)
    if not human.schemas:
        return human
    s = human.schemas[draw(st.sampled_from(sorted(human.schemas)))]
    if kind == "cost":
        if not isinstance(s.cost, int):
            new: int | tuple[str, ...] = draw(st.integers(1, 3))
        else:
            new = draw(st.integers(0 if allow_zero_cost else 1, 3).filter(lambda c: c != s.cost))
        return replace(human, schemas={**human.schemas, s.name: replace(s, cost=new)})
    lifted = lifted_atoms(dict(human.predicates), s.params)
    if not lifted:
        return human
    a = draw(st.sampled_from(lifted))
    s2 = replace(s, **{kind: _toggle(getattr(s, kind), a)})
    s2 = replace(s2, signature=s2.signature & s2.pre)
    return replace(human, schemas={**human.schemas, s.name: s2})


@st.composite
def two_model_tasks(
    draw,
    max_delta: int = 6,
    min_delta: int = 0,
    allow_zero_cost: bool = False,
    function_costs: bool = True,
    max_atoms: int = 10,
) -> TwoModelTask:
    """A robot model and a randomly flipped human model with ``len(delta) <= max_delta``."""
    robot = draw(models(max_atoms, allow_zero_cost, function_costs))
    human = robot
    task = TwoModelTask.from_models(robot, human)
    for _ in range(draw(st.integers(max(1, min_delta), max_delta + 2))):
        h2 = draw(_flip(human, allow_zero_cost))
        t2 = TwoModelTask.from_models(robot, h2)
        if len(t2.delta) <= max_delta:
            human, task = h2, t2
    return task


def selections(task: TwoModelTask) -> st.SearchStrategy[Selection]:
    """Random subsets of ``task.delta``."""
    if not task.delta:
        return st.just(frozenset())
    return st.frozensets(st.integers(0, len(task.delta) - 1))


def applicable_steps(model: Model, state: frozenset[Atom]) -> list[PlanStep]:
    """Every ground step applicable in ``state`` (brute force over the objects)."""
    out = []
    objects = sorted(model.objects)
    for s in sorted(model.schemas.values(), key=lambda s: s.name):
        for args in product(objects, repeat=len(s.params)):
            b = dict(zip(s.params, args, strict=True))

            def g(a: Atom, b: dict[str, str] = b) -> Atom:
                return (a[0], *(b.get(x, x) for x in a[1:]))

            if all(g(a) in state for a in s.pre) and not any(g(a) in state for a in s.negpre):
                out.append((s.name, *args))
    return out


@st.composite
def plans(draw, model: Model, max_len: int = 6, malformed: bool = True) -> tuple[PlanStep, ...]:
    """A random action sequence: mostly applicable steps of ``model``, sometimes an arbitrary
    step (possibly inapplicable) and, with ``malformed``, sometimes an unknown action, an
    unknown object or a wrong number of arguments."""
    objects = sorted(model.objects)
    state = set(model.init)
    steps: list[PlanStep] = []
    for _ in range(draw(st.integers(0, max_len))):
        mode = draw(st.integers(0, 9))
        app = applicable_steps(model, frozenset(state))
        if mode < 7 and app:
            step = draw(st.sampled_from(app))
        elif mode == 9 and malformed:
            step = draw(
                st.sampled_from(
                    [("fly",), ("a0", "o0", "o0", "o0", "o0"), ("a0", "zz"), ("a1", "zz", "o0")]
                )
            )
        else:
            name = draw(st.sampled_from(sorted(model.schemas) or ["a0"]))
            n = len(model.schemas[name].params) if name in model.schemas else 0
            step = (name, *draw(st.lists(st.sampled_from(objects), min_size=n, max_size=n)))
        steps.append(step)
        s = model.schemas.get(step[0])
        if s is not None and len(step) - 1 == len(s.params):
            b = dict(zip(s.params, step[1:], strict=True))
            state.difference_update((a[0], *(b.get(x, x) for x in a[1:])) for a in s.delete)
            state.update((a[0], *(b.get(x, x) for x in a[1:])) for a in s.add)
    return tuple(steps)
