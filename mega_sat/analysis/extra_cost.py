"""Delete-relaxation bounds that size the SAT horizons (``encodings/sequential.md``).

A plan of cost ``<= B`` whose cheapest action costs ``c`` has at most ``floor(B / c)`` steps;
the bounds here shorten that: the cost every plan must spend above ``N * c``
(:func:`extra_cost_bound`), a relaxation valid for every model of a family
(:func:`family_relaxation`), and step and cost lower bounds that prove a plan optimal without a
final UNSAT call (:func:`relaxed_bounds`).
"""

from __future__ import annotations

from mega_sat.analysis.relaxation import RelaxedTask
from mega_sat.ground.family import GroundFamily, GroundTask, StripsAction

_INF = float("inf")


def extra_cost_bound(task: GroundTask, c_min: int) -> int:
    """LM-cut of ``task`` with every action cost lowered by ``c_min``.

    Every plan of ``N`` steps costs ``N * c_min + (its cost under the lowered costs)``, and the
    latter is at least this admissible estimate, so a plan of cost ``<= B`` has at most
    ``floor((B - extra) / c_min)`` steps: a tighter horizon than ``floor(B / c_min)`` when
    some actions cost more than the cheapest one.
    """
    if c_min <= 0 or task.goal <= task.init:
        return 0
    rt = RelaxedTask(task)
    rt.costs = [max(0, c - c_min) for c in rt.costs[:-1]] + [0]
    h = rt.lmcut(sorted(task.init))
    return 0 if h == _INF else int(h)


def family_relaxation(family: GroundFamily) -> GroundTask:
    """A task whose delete relaxation over-approximates that of *every* family member: every
    action, only unguarded (pre)conditions and goals, every add effect and initial atom, the
    cheapest cost case.  Its admissible estimates are lower bounds for every selection."""
    acts = []
    for i, a in enumerate(family.actions):
        acts.append(
            StripsAction(
                i,
                a.name,
                a.args,
                frozenset(p for p, g in a.pre if g is None),
                frozenset(),
                frozenset(p for p, _ in a.add),
                frozenset(),
                min((v for _, v in a.cost), default=0),
            )
        )
    return GroundTask(
        family.atoms,
        tuple(acts),
        frozenset(p for p, _ in family.init),
        frozenset(p for p, g in family.goal if g is None),
    )


def relaxed_bounds(task: GroundTask) -> tuple[int, int] | None:
    """``(steps, cost)`` lower bounds from the delete relaxation (unit-cost h^max; LM-cut);
    ``None`` if the goal is not even relaxed-reachable (then the task is provably unsolvable).

    A plan meeting the cost bound is optimal without the (often expensive) final UNSAT call.
    """
    if task.goal <= task.init:
        return 0, 0
    rt = RelaxedTask(task)
    state = sorted(task.init)
    h_cost = rt.hmax(state, rt.costs)[0][rt.goal_atom]
    if h_cost == _INF:
        return None
    units = [1] * len(task.actions) + [0]  # the artificial goal action is free
    h_steps = rt.hmax(state, units)[0][rt.goal_atom]
    return int(h_steps), int(max(h_cost, rt.lmcut(state)))
