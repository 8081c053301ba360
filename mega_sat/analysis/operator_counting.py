"""Operator-counting lower bounds: an integer program over how often each action is used.

A SAT proof of "no plan of cost <= C* - 1" is the expensive part of ``OPT``.  Often a cheaper
argument gives the same bound: every plan uses each action a whole number of times ``Y_a``,
and those counts satisfy linear constraints (Pommerening et al., "LP-based heuristics for
cost-optimal planning", ICAPS 2014), so ``min sum cost_a * Y_a`` over them is a lower bound on
the cost of every plan.  When it equals the cost of a plan in hand, that plan is optimal and
no UNSAT call is needed.  Two families of constraints are used:

* **disjunctive action landmarks** (the cuts LM-cut finds): ``sum_{a in L} Y_a >= 1``;
* **the state equation** (net change of each fact): a fact that must be true at the end was
  either true initially or is produced more often than it is consumed; a fact can be true at
  most once, so it is not produced more often than consumed plus one.  An action *always*
  produces ``p`` when it adds ``p`` and one of its preconditions is h^2-mutex with ``p``
  (so ``p`` was false before), *sometimes* when it adds ``p`` without such a precondition;
  it always consumes ``p`` when ``p`` is a precondition it deletes, sometimes when it deletes
  ``p`` without requiring it.

The task must have positive preconditions only (the two-fact abstraction of
:mod:`mega_sat.analysis.abstraction`); since every plan of a model agreeing with an abstraction is an
abstract plan of no greater cost, the bound of an abstraction holds for all of them, which is
what makes it usable for JOINT's cores.  The integer program is solved by CBC through PuLP;
only a solution CBC reports as optimal gives a bound (a time-out gives none).

Large costs are scaled down before CBC sees them (:data:`MAX_SOLVER_COST`): PuLP writes the
problem with 13 significant digits, so 10^13 + 1 and 10^13 + 3 both reach CBC as 10^13, and CBC
may then count the dearer action, whose true cost is a "bound" above the optimum; CBC's
tolerances are absolute as well, and large coefficients magnify them.
"""

from __future__ import annotations

import math
import warnings

from mega_sat.analysis.pair_reachability import pair_masks
from mega_sat.ground.family import GroundTask

Row = tuple[list[int], list[int], list[int], list[int], int, int]

MAX_SOLVER_COST = 1000
"""Largest action cost given to CBC.  Above it, costs are divided by their gcd, and if still
too large, replaced by ``floor(cost / s)`` with ``s = ceil(max cost / MAX_SOLVER_COST)``; the
bound is ``s`` times the scaled optimum.  Every plan costs at least ``s`` times its scaled
cost, so the bound stays a lower bound (only weaker); on costs up to this value nothing
changes."""


def _scaled_costs(costs: list[int]) -> tuple[list[int], int]:
    """``(scaled costs, s)`` with ``s * scaled <= cost`` for each (see :data:`MAX_SOLVER_COST`)."""
    top = max(costs, default=0)
    if top <= MAX_SOLVER_COST:
        return costs, 1
    s = math.gcd(*costs)
    if top // s > MAX_SOLVER_COST:
        s = -(-top // MAX_SOLVER_COST)
    return [c // s for c in costs], s


def state_equation_rows(task: GroundTask) -> list[Row]:
    """Per fact that some action changes: ``(always_p, some_p, always_c, some_c, lower,
    upper)``.  Every plan's counts satisfy ``Y[always_p] + Y[some_p] - Y[always_c] >= lower``
    (goal minus initial value: the most the fact can gain) and ``Y[always_p] - Y[always_c] -
    Y[some_c] <= upper`` (one minus initial value: the least it gains), sums over the lists."""
    masks = pair_masks(task)
    rows = []
    for p in range(len(task.atoms)):
        always_p, some_p, always_c, some_c = [], [], [], []
        for j, a in enumerate(task.actions):
            if p in a.add and p not in a.pre:
                if any(not (masks[q] >> p) & 1 for q in a.pre):
                    always_p.append(j)
                else:
                    some_p.append(j)
            elif p in a.delete and p not in a.add:
                (always_c if p in a.pre else some_c).append(j)
        if always_p or some_p or always_c or some_c:
            init = int(p in task.init)
            rows.append((always_p, some_p, always_c, some_c, int(p in task.goal) - init, 1 - init))
    return rows


def landmarks(task: GroundTask) -> list[list[int]] | None:
    """LM-cut's disjunctive action landmarks of ``task`` from its initial state; ``None`` if
    the goal is not even relaxed-reachable."""
    from mega_sat.analysis.relaxation import RelaxedTask

    cuts: list[list[int]] = []
    if RelaxedTask(task).lmcut(sorted(task.init), cuts) == math.inf:
        return None
    return cuts


def operator_counting_bound(task: GroundTask, *, time_limit: float = 2.0) -> float | None:
    """A proven lower bound on the cost of every plan of ``task``: the optimum of the integer
    program above (``math.inf``: no count vector at all, so no plan), or ``None`` when CBC does
    not prove its optimum within ``time_limit`` seconds."""
    import pulp

    from mega_sat.analysis.cbc import solve_cbc

    if any(a.negpre for a in task.actions):
        raise ValueError("operator counting needs a task without negative preconditions")
    if task.goal <= task.init:
        return 0
    cuts = landmarks(task)
    if cuts is None:
        return math.inf
    with warnings.catch_warnings():
        # PuLP 3.x announces API changes for 4.0 on every call; the calls below work in both
        warnings.simplefilter("ignore", DeprecationWarning)
        prob = pulp.LpProblem("operator_counting", pulp.LpMinimize)
        y = [pulp.LpVariable(f"y{j}", lowBound=0, cat="Integer") for j in range(len(task.actions))]
        costs, scale = _scaled_costs([a.cost for a in task.actions])
        prob += pulp.lpSum(c * y[j] for j, c in enumerate(costs))
        for cut in cuts:
            prob += pulp.lpSum(y[j] for j in cut) >= 1
        for always_p, some_p, always_c, some_c, lower, upper in state_equation_rows(task):
            gain_max = pulp.lpSum(y[j] for j in always_p + some_p) - pulp.lpSum(
                y[j] for j in always_c
            )
            gain_min = pulp.lpSum(y[j] for j in always_p) - pulp.lpSum(
                y[j] for j in always_c + some_c
            )
            prob += gain_max >= lower
            prob += gain_min <= upper
        # gapRel=0: "optimal" must mean proven optimal, not within a tolerance
        status = solve_cbc(prob, time_limit=time_limit, gapRel=0)
    if status == pulp.LpStatusInfeasible:
        return math.inf
    if status != pulp.LpStatusOptimal or prob.sol_status != pulp.LpSolutionOptimal:
        return None
    value = pulp.value(prob.objective)
    # costs are integers: the optimum is an integer up to CBC's tolerances
    return scale * max(0, math.ceil((value or 0) - 1e-6))
