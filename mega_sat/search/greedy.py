"""Greedy best-first search with the additive heuristic (:meth:`RelaxedTask.h_add`): any
plan, fast, within a budget.

Its plans are not optimal and an exhausted budget proves nothing; it only answers "this
model has a plan" cheaply where one is easy to find (and, when it runs out of states before
its budget, "this model has none").  The OPT race uses that as the sign
that a model is worth handing to Fast Downward, whose LM-cut search proves the optima of
solvable models fast but exhausts every state of an unsolvable one
(:meth:`mega_sat.planners.node_planner.NodePlanner._race_forked`).
"""

from __future__ import annotations

import heapq
from typing import Literal

from mega_sat.analysis.relaxation import RelaxedTask
from mega_sat.deadline import NO_DEADLINE, Deadline
from mega_sat.ground.family import GroundTask, StripsAction

_INF = float("inf")


def greedy_plan(
    task: GroundTask, evaluations: int, deadline: Deadline = NO_DEADLINE
) -> tuple[StripsAction, ...] | None:
    """A plan of ``task`` found by greedy best-first search on h_add within ``evaluations``
    heuristic evaluations, or ``None`` (no plan found: proves nothing).  Ties go to the
    state generated first, so every run returns the same plan.  An evaluation costs a pass
    over every action, so on a large task the budget can take long: ``deadline`` also ends
    the search (checked once per expansion)."""
    plan = greedy_search(task, evaluations, deadline)
    return plan if isinstance(plan, tuple) else None


def greedy_search(
    task: GroundTask, evaluations: int, deadline: Deadline = NO_DEADLINE
) -> tuple[StripsAction, ...] | Literal[False] | None:
    """:func:`greedy_plan`, telling apart the two ways it finds no plan: ``False`` when the
    search has expanded every state reachable without passing a dead end (a state whose h_add
    is infinite: not even the delete relaxation reaches the goal from it), which proves that
    ``task`` has no plan; ``None`` when the budget or the deadline ended it first."""
    init = frozenset(task.init)
    goal = task.goal
    h = RelaxedTask(task).h_add
    h0 = h(init)
    if h0 == _INF:
        return False
    parent: dict[frozenset[int], tuple[frozenset[int], StripsAction] | None] = {init: None}
    queue = [(h0, 0, init)]
    made = 1
    while queue and made < evaluations and not deadline.expired():
        _, _, s = heapq.heappop(queue)
        if goal <= s:
            plan = []
            while (link := parent[s]) is not None:
                s, a = link
                plan.append(a)
            return tuple(reversed(plan))
        for a in task.actions:
            if a.pre <= s and a.negpre.isdisjoint(s):
                t = (s - a.delete) | a.add  # PDDL: deletes first, adds win
                if t in parent:
                    continue
                parent[t] = (s, a)
                hv = h(t)
                made += 1
                if hv < _INF:
                    heapq.heappush(queue, (hv, made, t))
    return False if not queue else None
