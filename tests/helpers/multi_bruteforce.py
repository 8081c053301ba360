"""Brute-force MEGA oracle for several human models: every subset of the union Delta.

For each selection ``E`` it explores the whole state space of every ``human_i + E`` with
explicit-state Dijkstra (forward ``g*`` and backward ``h*``, as :mod:`helpers.bruteforce`),
and then runs a Dijkstra on robot cost over product states (robot state, human_1 state, ...)
that only follows, in each human model, transitions lying on an optimal plan of that model
(``g*(s) + c = g*(t)`` and ``g*(t) + h*(t) = c*``).  A path that reaches every goal that way
is optimal in every ``human_i + E``, and every such plan is such a path, so the first goal
popped is the cheapest robot plan among the plans optimal for every human model.  It shares no
code with the engine's OPT tiers or its product A*; it is exponential, for small tasks only.
"""

from __future__ import annotations

import heapq
import itertools
from collections.abc import Sequence
from dataclasses import dataclass

from helpers.bruteforce import _mask, _Space
from mega_sat.ground.family import GroundFamily, PlanStep
from mega_sat.pddl.multi_task import MultiHumanTask
from mega_sat.results import pareto_filter


@dataclass(frozen=True)
class MultiBruteResult:
    """Best robot cost among plans optimal in every ``human_i + E`` (``None``: no solution)."""

    selection: frozenset[int]
    human_costs: tuple[int | None, ...]
    robot_cost: int | None
    plan: tuple[PlanStep, ...] | None


def multi_best_for_selection(
    task: MultiHumanTask,
    families: Sequence[GroundFamily],
    sel: frozenset[int],
    *,
    state_limit: int = 200_000,
) -> MultiBruteResult:
    """The cheapest robot plan that is optimal in every ``human_i + sel``."""
    spaces = [
        _Space(f.specialize(task.project(sel, i)), state_limit) for i, f in enumerate(families)
    ]
    opts = tuple(s.opt for s in spaces)
    if any(o is None or s.h.get(s.init) != o for o, s in zip(opts, spaces, strict=True)):
        return MultiBruteResult(sel, opts, None, None)
    robot = families[0].specialize(families[0].robot_selection)
    racts = {
        a.step: (_mask(a.pre), _mask(a.negpre), _mask(a.add), _mask(a.delete), a.cost)
        for a in robot.actions
    }
    rgoal = _mask(robot.goal)
    # per human model: state -> [(step, successor)] along optimal plans only
    steps_of = [{j: a.step for j, a in enumerate(f.actions)} for f in families]
    opt_succ = []
    for i, sp in enumerate(spaces):
        table = {}
        for s, out in sp.succ.items():
            if s not in sp.h or sp.g[s] + sp.h[s] != opts[i]:
                continue
            table[s] = {
                steps_of[i][idx]: t
                for idx, t, c in out
                if sp.g[s] + c == sp.g[t] and sp.g[t] + sp.h.get(t, 10**18) == opts[i]
            }
        opt_succ.append(table)
    start = (_mask(robot.init), *(s.init for s in spaces))
    dist = {start: 0}
    parent: dict[tuple[int, ...], tuple[tuple[int, ...], PlanStep]] = {}
    counter = itertools.count()
    heap = [(0, next(counter), start)]
    while heap:
        d, _, state = heapq.heappop(heap)
        if d > dist[state]:
            continue
        if state[0] & rgoal == rgoal and all(
            state[i + 1] & sp.goal == sp.goal and sp.g[state[i + 1]] == opts[i]
            for i, sp in enumerate(spaces)
        ):
            plan = []
            node = state
            while node in parent:
                node, step = parent[node]
                plan.append(step)
            return MultiBruteResult(sel, opts, d, tuple(reversed(plan)))
        first = opt_succ[0].get(state[1], {})
        for step, t1 in first.items():
            r = racts.get(step)
            if r is None:
                continue
            pre, neg, add, dele, cr = r
            sr = state[0]
            if sr & pre != pre or sr & neg:
                continue
            nxt = [(sr & ~dele) | add, t1]
            for i in range(1, len(spaces)):
                t = opt_succ[i].get(state[i + 1], {}).get(step)
                if t is None:
                    break
                nxt.append(t)
            else:
                key = tuple(nxt)
                nd = d + cr
                if key not in dist or nd < dist[key]:
                    dist[key] = nd
                    parent[key] = (state, step)
                    heapq.heappush(heap, (nd, next(counter), key))
    return MultiBruteResult(sel, opts, None, None)


def multi_brute_force_frontier(
    task: MultiHumanTask,
    families: Sequence[GroundFamily],
    *,
    state_limit: int = 200_000,
    update_costs: Sequence[int] | None = None,
) -> tuple[int, tuple, dict[frozenset[int], MultiBruteResult]]:
    """``(C*_R, Pareto frontier, per-selection results)`` over every subset of ``task.delta``;
    the points are :class:`~mega_sat.engines.multi_human.MultiHumanPoint`, with ``update_costs`` over
    (sum of costs, robot cost)."""
    from mega_sat.engines.multi_human import MultiHumanPoint

    robot = _Space(families[0].specialize(families[0].robot_selection), state_limit)
    if robot.opt is None:
        raise ValueError("robot problem unsolvable")
    n = len(task.delta)
    results = {}
    points = []
    for k in range(n + 1):
        for combo in itertools.combinations(range(n), k):
            sel = frozenset(combo)
            r = multi_best_for_selection(task, families, sel, state_limit=state_limit)
            results[sel] = r
            if r.robot_cost is not None:
                weighted = None if update_costs is None else sum(update_costs[i] for i in sel)
                hc = tuple(c for c in r.human_costs if c is not None)
                points.append(
                    MultiHumanPoint(
                        tuple(task.names(sel)), sel, r.plan, r.robot_cost, hc[0], weighted, hc
                    )
                )
    return robot.opt, pareto_filter(points), results
