"""Greedy action elimination: make a valid plan cheaper by dropping steps it does not need.

A SAT model at a long horizon is any plan within the bounds, often with detours.  OPT's descent
asks "cost <= C - 1" once per improvement, so starting each round from a cheaper plan saves
whole SAT calls.  The reduction (Fink & Yang's greedy action elimination) tries to drop each
step together with the later steps that drop out of applicability; a candidate is kept only if
it is valid in the task and cheaper, so the result is always a valid plan of the same task.
"""

from __future__ import annotations

from collections.abc import Sequence

from mega_sat.ground.family import GroundTask
from mega_sat.ground.simulate import ground_plan_cost
from mega_sat.model.lifted import PlanStep


def _drop_from(task: GroundTask, plan: Sequence[PlanStep], i: int) -> list[PlanStep]:
    """``plan`` without step ``i`` and without every later step no longer applicable."""
    by_step = task.by_step
    state = set(task.init)
    out: list[PlanStep] = []
    for k, step in enumerate(plan):
        if k == i:
            continue
        a = by_step.get(step)
        if a is None or not a.pre <= state or not a.negpre.isdisjoint(state):
            continue  # only after step i: the prefix of a valid plan stays applicable
        state -= a.delete
        state |= a.add
        out.append(step)
    return out


def reduce_plan(task: GroundTask, plan: Sequence[PlanStep]) -> tuple[tuple[PlanStep, ...], int]:
    """A valid plan of ``task`` no costlier than ``plan`` (which must be valid), and its cost."""
    best = list(plan)
    cost = ground_plan_cost(task, best)
    if cost is None:
        raise ValueError("reduce_plan needs a valid plan")
    i = 0
    while i < len(best):
        cand = _drop_from(task, best, i)
        c = ground_plan_cost(task, cand)
        if c is not None and c < cost:
            best, cost = cand, c  # retry the same position: the plan shifted left
        else:
            i += 1
    return tuple(best), cost
