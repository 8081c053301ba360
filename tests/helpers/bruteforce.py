"""Brute-force MEGA oracle: every subset of Delta, explicit-state search, no SAT.

For each selection ``E`` (all ``2^|Delta|`` of them) it computes, with explicit-state Dijkstra,
the optimal human cost ``c*`` of ``human + E`` and the cheapest robot cost among plans that are
optimal in ``human + E`` — by a Dijkstra over *paired* states (robot state, human state) that
only follows human transitions lying on some optimal human plan.  This is the reference the
engines are tested against; it is exponential and meant for small instances only.
"""

from __future__ import annotations

import heapq
import itertools
from collections.abc import Sequence
from dataclasses import dataclass

from mega_sat.ground.family import GroundFamily, GroundTask
from mega_sat.model.lifted import PlanStep
from mega_sat.model.task import TwoModelTask
from mega_sat.results import FrontierPoint, pareto_filter


def _mask(ids) -> int:
    m = 0
    for i in ids:
        m |= 1 << i
    return m


class _Space:
    """The reachable state space of one ground task as bitmask states."""

    def __init__(self, task: GroundTask, state_limit: int):
        self.task = task
        self.acts = [
            (_mask(a.pre), _mask(a.negpre), _mask(a.add), _mask(a.delete), a.cost, a.index)
            for a in task.actions
        ]
        self.goal = _mask(task.goal)
        init = _mask(task.init)
        # forward Dijkstra: g*(s) and the reachable graph
        self.g: dict[int, int] = {init: 0}
        self.succ: dict[int, list[tuple[int, int, int]]] = {}
        heap = [(0, init)]
        while heap:
            g, s = heapq.heappop(heap)
            if g > self.g[s] or s in self.succ:
                continue
            out = []
            for pre, neg, add, dele, cost, idx in self.acts:
                if s & pre == pre and not s & neg:
                    t = (s & ~dele) | add
                    out.append((idx, t, cost))
                    if t not in self.g or g + cost < self.g[t]:
                        self.g[t] = g + cost
                        heapq.heappush(heap, (g + cost, t))
            self.succ[s] = out
            if len(self.succ) > state_limit:
                raise RuntimeError(f"state space exceeds {state_limit} states")
        self.init = init
        goals = [s for s in self.g if s & self.goal == self.goal]
        self.opt = min((self.g[s] for s in goals), default=None)
        # backward Dijkstra: h*(s), exact cost-to-goal
        pred: dict[int, list[tuple[int, int]]] = {}
        for s, out in self.succ.items():
            for _, t, c in out:
                pred.setdefault(t, []).append((s, c))
        self.h: dict[int, int] = {}
        heap = [(0, s) for s in goals]
        for s in goals:
            self.h[s] = 0
        heapq.heapify(heap)
        while heap:
            h, t = heapq.heappop(heap)
            if h > self.h[t]:
                continue
            for s, c in pred.get(t, ()):
                if s not in self.h or h + c < self.h[s]:
                    self.h[s] = h + c
                    heapq.heappush(heap, (h + c, s))


@dataclass(frozen=True)
class BruteResult:
    """Best robot cost among human-optimal plans of one selection (``None``: no solution)."""

    selection: frozenset[int]
    human_cost: int | None
    robot_cost: int | None
    plan: tuple[PlanStep, ...] | None


def best_for_selection(
    family: GroundFamily, sel: frozenset[int], *, state_limit: int = 200_000
) -> BruteResult:
    """Cheapest robot cost of a plan that is optimal in ``human + sel`` and valid for the
    robot."""
    hum = _Space(family.specialize(sel), state_limit)
    if hum.opt is None:
        return BruteResult(sel, None, None, None)
    rob = family.specialize(family.robot_selection)
    racts = {
        a.index: (_mask(a.pre), _mask(a.negpre), _mask(a.add), _mask(a.delete), a.cost)
        for a in rob.actions
    }
    rgoal = _mask(rob.goal)
    start = (_mask(rob.init), hum.init)
    dist = {start: 0}
    parent: dict[tuple[int, int], tuple[tuple[int, int], int]] = {}
    counter = itertools.count()
    heap = [(0, next(counter), start)]
    c_star = hum.opt
    if hum.h.get(hum.init) != c_star:
        return BruteResult(sel, c_star, None, None)
    while heap:
        d, _, (sr, sh) = heapq.heappop(heap)
        if d > dist[(sr, sh)]:
            continue
        if sr & rgoal == rgoal and sh & hum.goal == hum.goal and hum.g[sh] == c_star:
            plan = []
            node = (sr, sh)
            while node in parent:
                node, idx = parent[node]
                plan.append(family.actions[idx].step)
            return BruteResult(sel, c_star, d, tuple(reversed(plan)))
        gh = hum.g[sh]
        for idx, th, ch in hum.succ[sh]:
            if idx not in racts:
                continue
            if gh + ch != hum.g[th] or hum.g[th] + hum.h.get(th, 10**18) != c_star:
                continue
            pre, neg, add, dele, cr = racts[idx]
            if sr & pre != pre or sr & neg:
                continue
            tr = (sr & ~dele) | add
            nd = d + cr
            key = (tr, th)
            if key not in dist or nd < dist[key]:
                dist[key] = nd
                parent[key] = ((sr, sh), idx)
                heapq.heappush(heap, (nd, next(counter), key))
    return BruteResult(sel, c_star, None, None)


def brute_force_frontier(
    task: TwoModelTask,
    family: GroundFamily,
    *,
    state_limit: int = 200_000,
    update_costs: Sequence[int] | None = None,
) -> tuple[int, tuple[FrontierPoint, ...], dict[frozenset[int], BruteResult]]:
    """``(C*_R, Pareto frontier, per-selection results)`` by enumerating every subset; with
    ``update_costs`` (one per update) the frontier is over (sum of costs, robot cost)."""
    n = len(task.delta)
    robot = _Space(family.specialize(family.robot_selection), state_limit)
    if robot.opt is None:
        raise ValueError("robot problem unsolvable")
    results = {}
    points = []
    for k in range(n + 1):
        for combo in itertools.combinations(range(n), k):
            sel = frozenset(combo)
            r = best_for_selection(family, sel, state_limit=state_limit)
            results[sel] = r
            if r.robot_cost is not None:
                weighted = None if update_costs is None else sum(update_costs[i] for i in sel)
                points.append(
                    FrontierPoint(
                        tuple(task.names(sel)), sel, r.plan, r.robot_cost, r.human_cost, weighted
                    )
                )
    return robot.opt, pareto_filter(points), results


def brute_force_mce(
    task: TwoModelTask,
    family: GroundFamily,
    plan: Sequence[PlanStep],
    *,
    state_limit: int = 200_000,
    update_costs: Sequence[int] | None = None,
) -> int | None:
    """Size (with ``update_costs``: the smallest sum of costs) of the cheapest ``E`` making
    ``plan`` optimal in ``human + E`` (None: none)."""
    from mega_sat.ground.simulate import simulate_ground

    n = len(task.delta)
    costs = update_costs if update_costs is not None else (1,) * n
    best = None
    for k in range(n + 1):
        for combo in itertools.combinations(range(n), k):
            sel = frozenset(combo)
            w = sum(costs[i] for i in sel)
            if best is not None and w >= best:
                continue
            t = family.specialize(sel)
            sim = simulate_ground(t, plan)
            if not sim.valid:
                continue
            sp = _Space(t, state_limit)
            if sp.opt is not None and sim.cost == sp.opt:
                best = w
        if update_costs is None and best is not None:
            return best
    return best


def brute_force_mme(
    task: TwoModelTask,
    family: GroundFamily,
    plan: Sequence[PlanStep],
    *,
    state_limit: int = 200_000,
    update_costs: Sequence[int] | None = None,
) -> int | None:
    """Size (with ``update_costs``: the smallest sum of costs) of the cheapest ``E`` such that
    ``plan`` is optimal in ``human + E'`` for every ``E <= E' <= Delta`` (None: none, i.e.
    ``plan`` is not optimal in the robot model)."""
    from mega_sat.ground.simulate import simulate_ground

    n = len(task.delta)
    optimal = []
    for mask in range(1 << n):
        t = family.specialize(i for i in range(n) if mask >> i & 1)
        sim = simulate_ground(t, plan)
        optimal.append(sim.valid and sim.cost == _Space(t, state_limit).opt)
    monotonic = [False] * (1 << n)
    for mask in reversed(range(1 << n)):  # every superset comes first
        monotonic[mask] = optimal[mask] and all(
            monotonic[mask | 1 << i] for i in range(n) if not mask >> i & 1
        )
    costs = update_costs if update_costs is not None else (1,) * n
    sizes = [sum(costs[i] for i in range(n) if m >> i & 1) for m in range(1 << n) if monotonic[m]]
    return min(sizes, default=None)


def check_witnesses(
    task: TwoModelTask, fam: GroundFamily, points, results, update_costs=None
) -> None:
    """Every frontier point's witness is a real MEGA solution: the oracle's best plan for its
    explanation is no dearer for the robot, and ``verify_pair`` (simulation, no VAL) accepts
    it, with the point's explanation cost when there are ``update_costs``."""
    from mega_sat.engines.verify import verify_pair

    for p in points:
        r = results[p.selection]
        assert r.robot_cost is not None and r.robot_cost <= p.robot_cost
        weighted = {}
        if update_costs is not None:
            weighted = {"update_costs": update_costs, "explanation_cost": p.weighted_cost}
        rep = verify_pair(
            task,
            fam,
            p.selection,
            p.plan,
            producer="sat",
            robot_cost=p.robot_cost,
            human_cost=p.human_cost,
            use_val=False,
            **weighted,
        )
        assert rep.ok, rep.lines()
        assert update_costs is None or rep.explanation_cost == p.weighted_cost
