"""Plan simulation: execute a plan in a model and report its cost or the first failure.

:func:`simulate` works on the *lifted* :class:`Model` directly and shares no code with
grounding, so it cross-checks the ground family; :func:`simulate_ground` is the fast path on a
:class:`GroundTask` used inside engine loops.  Both return the same :class:`Simulation`.

Semantics are PDDL's: all preconditions are checked in the state before the step, then delete
effects are applied, then add effects.  The reported failing precondition is the first one in
sorted order, so both simulators name the same atom.
"""

from __future__ import annotations

from collections.abc import Sequence
from dataclasses import dataclass

from mega_sat.ground.family import GroundTask
from mega_sat.model.lifted import Atom, Model, PlanStep, atom_pddl, step_str


@dataclass(frozen=True)
class Simulation:
    """Outcome of executing a plan.

    ``failed_step`` is 1-based and ``None`` when every step applied (a plan that only misses
    the goal has ``valid`` false and ``failed_step`` ``None``).  ``cost`` is set only for valid
    plans.  ``final_state`` is the state reached (before the failing step on failure) and
    ``steps`` the number of steps applied.
    """

    valid: bool
    cost: int | None
    failed_step: int | None
    reason: str | None
    final_state: frozenset[Atom]
    steps: int


def _norm(step: PlanStep) -> PlanStep:
    return tuple(x.lower() for x in step)


def step_mismatch(model: Model, step: PlanStep) -> str | None:
    """Why ``step`` (lower-case) names no action schema of ``model`` with its number of
    arguments; ``None`` when it does."""
    schema = model.schemas.get(step[0])
    if schema is None:
        return f"unknown action '{step[0]}'"
    if len(step) - 1 != len(schema.params):
        return f"wrong number of arguments (expected {len(schema.params)}, got {len(step) - 1})"
    return None


def simulate(model: Model, plan: Sequence[PlanStep]) -> Simulation:
    """Execute ``plan`` in the lifted ``model``."""
    state = set(model.init)
    cost = 0
    for k, raw in enumerate(plan, 1):
        step = _norm(raw)
        name, args = step[0], step[1:]

        def fail(msg: str, k: int = k, step: PlanStep = step) -> Simulation:
            return Simulation(
                False, None, k, f"step {k} {step_str(step)}: {msg}", frozenset(state), k - 1
            )

        mismatch = step_mismatch(model, step)
        if mismatch is not None:
            return fail(mismatch)
        schema = model.schemas[name]
        for x in args:
            if x not in model.objects:
                return fail(f"unknown object '{x}'")
        binding = dict(zip(schema.params, args, strict=True))

        def g(a: Atom, b: dict[str, str] = binding) -> Atom:
            return (a[0],) + tuple(b.get(x, x) for x in a[1:])

        for p in sorted(g(a) for a in schema.pre):
            if p not in state:
                return fail(f"precondition {atom_pddl(p)} does not hold")
        for p in sorted(g(a) for a in schema.negpre):
            if p in state:
                return fail(f"negative precondition {atom_pddl(p)} holds")
        try:
            cost += model.schema_cost(schema, args)
        except KeyError as e:
            return fail(f"cost function value {e} is not defined")
        adds = {g(a) for a in schema.add}
        state.difference_update(g(a) for a in schema.delete)
        state.update(adds)
    for p in sorted(model.goal):
        if p not in state:
            return Simulation(
                False, None, None, f"goal {atom_pddl(p)} not reached", frozenset(state), len(plan)
            )
    for p in sorted(model.neggoal):
        if p in state:
            why = f"goal (not {atom_pddl(p)}) not reached"
            return Simulation(False, None, None, why, frozenset(state), len(plan))
    return Simulation(True, cost, None, None, frozenset(state), len(plan))


def simulate_ground(task: GroundTask, plan: Sequence[PlanStep]) -> Simulation:
    """Execute ``plan`` in a ground task.

    A step with no ground action in ``task`` is reported as not applicable: grounding only
    drops actions that are unknown or can never be applicable in a reachable state, so the
    lifted simulator fails at the same step (possibly naming another reason).
    """
    state = set(task.init)
    atoms = task.atoms
    cost = 0
    by_step = task.by_step
    for k, raw in enumerate(plan, 1):
        step = _norm(raw)
        a = by_step.get(step)
        if a is None:
            return Simulation(
                False,
                None,
                k,
                f"step {k} {step_str(step)}: no such applicable ground action",
                frozenset(atoms[i] for i in state),
                k - 1,
            )
        if not a.pre <= state:
            p = min(atoms[i] for i in a.pre - state)
            return Simulation(
                False,
                None,
                k,
                f"step {k} {step_str(step)}: precondition {atom_pddl(p)} does not hold",
                frozenset(atoms[i] for i in state),
                k - 1,
            )
        if not a.negpre.isdisjoint(state):
            p = min(atoms[i] for i in a.negpre & state)
            return Simulation(
                False,
                None,
                k,
                f"step {k} {step_str(step)}: negative precondition {atom_pddl(p)} holds",
                frozenset(atoms[i] for i in state),
                k - 1,
            )
        cost += a.cost
        state -= a.delete
        state |= a.add
    final = frozenset(atoms[i] for i in state)
    if not task.goal <= state:
        p = min(atoms[i] for i in task.goal - state)
        return Simulation(False, None, None, f"goal {atom_pddl(p)} not reached", final, len(plan))
    return Simulation(True, cost, None, None, final, len(plan))


def plan_cost(model: Model, plan: Sequence[PlanStep]) -> int | None:
    """``C(pi, M)``: the plan's cost if it is valid in ``model``, else ``None``."""
    return simulate(model, plan).cost


def ground_plan_cost(task: GroundTask, plan: Sequence[PlanStep]) -> int | None:
    """:func:`plan_cost` for a ground task: the cost if ``plan`` is valid in ``task``."""
    sim = simulate_ground(task, plan)
    return sim.cost if sim.valid else None
