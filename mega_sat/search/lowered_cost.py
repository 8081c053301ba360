"""The exact cost a plan spends above ``N * c_min``: optimal search under lowered costs.

:func:`mega_sat.analysis.extra_cost.extra_cost_bound` estimates it by LM-cut; an explicit
optimal search on the task with every cost lowered by ``c_min`` makes it exact when it finishes
within its node limit, and the plan it finds is a valid plan of the task, a cheap first upper
bound for OPT.
"""

from __future__ import annotations

from dataclasses import replace

from mega_sat.analysis.extra_cost import extra_cost_bound
from mega_sat.ground.family import GroundTask
from mega_sat.model.lifted import PlanStep
from mega_sat.search.astar import astar


def extra_cost_search(
    task: GroundTask, c_min: int, node_limit: int, expanded: list[int] | None = None
) -> tuple[int, tuple[PlanStep, ...] | None]:
    """:func:`extra_cost_bound`, made exact by an explicit optimal search under the lowered
    costs when it finishes within ``node_limit`` expansions (else the LM-cut estimate), and
    the plan that search found (``None`` if it ran out); ``expanded`` (a list) gets the
    search's expansions appended.

    The plan has the fewest cost units above ``c_min`` per step; where every optimal plan of
    the task is one of those, OPT's descent starts at the optimum."""
    lm = extra_cost_bound(task, c_min)
    if c_min <= 0 or task.goal <= task.init or node_limit <= 0:
        return lm, None
    low = GroundTask(
        task.atoms,
        tuple(replace(a, cost=a.cost - c_min) for a in task.actions),
        task.init,
        task.goal,
    )
    r = astar(low, heuristic="blind", node_limit=node_limit)
    if expanded is not None:
        expanded.append(r.expanded)
    if r.status == "optimal" and r.cost is not None:
        return max(lm, int(r.cost)), tuple(r.plan)
    return lm, None


def extra_cost_exact(task: GroundTask, c_min: int, node_limit: int) -> int:
    """The exact (or LM-cut) extra cost of :func:`extra_cost_search`."""
    return extra_cost_search(task, c_min, node_limit)[0]
