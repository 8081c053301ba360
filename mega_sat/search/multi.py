"""Explicit-state JOINT for several human models: one plan for the robot and every human.

``MultiJointSearcher.search(humans, K, bounds)`` finds a plan that is valid in the robot task
with robot cost ``<= K`` (``None``: no bound) and valid in every human task ``i`` with human
cost ``<= bounds[i]``, of minimum robot cost, or proves that there is none.

It is an A* over product states ``(robot state, human_1 state, ..., human_n state)``: an
action is applicable when it is applicable in every component (matched by its ground step,
since each human model has a ground family of its own), and a path carries the cost vector
``(robot cost, human_1 cost, ..., human_n cost)``.  A product state keeps the Pareto set of the
vectors it was reached with; a label is dropped only when another label of the same state is no
worse in every component (whatever a path can still do from the state, the other label can do
at no higher cost in any component).  The queue is ordered by robot cost plus the robot's
LM-cut, which is admissible; a path is pruned once a component's cost plus that component's
admissible heuristic (LM-cut for the robot, h^max for each human) passes its bound.  So the
first goal label popped has the minimum robot cost among all plans within the bounds, and an
exhausted queue proves that there is none.  No horizon is involved: the answer holds with
zero-cost actions too (the label sets are finite, since labels within the bounds are).
"""

from __future__ import annotations

import heapq
from collections.abc import Sequence
from dataclasses import dataclass

from mega_sat.analysis.relaxation import RelaxedTask, bits
from mega_sat.deadline import Deadline
from mega_sat.ground.family import GroundTask, PlanStep

_INF = float("inf")


@dataclass(frozen=True)
class MultiJointResult:
    """``status``: ``plan`` (a cheapest-robot-cost plan within the bounds), ``none`` (proven:
    no plan within the bounds), ``limit`` (the deadline passed: nothing proven) or ``nodes``
    (the node limit reached: nothing proven)."""

    status: str
    plan: tuple[PlanStep, ...] | None
    robot_cost: int | None
    human_costs: tuple[int, ...] | None
    expanded: int


def _masks(a) -> tuple[int, int, int, int, int]:
    """(pre, negpre, ~delete, add, cost) bitmasks of a STRIPS action."""
    return (
        sum(1 << p for p in a.pre),
        sum(1 << p for p in a.negpre),
        ~sum(1 << p for p in a.delete),
        sum(1 << p for p in a.add),
        a.cost,
    )


def _dominated(vec: tuple[int, ...], others: list[tuple[int, ...]]) -> bool:
    return any(all(o <= v for o, v in zip(other, vec, strict=True)) for other in others)


class MultiJointSearcher:
    """The search against one fixed robot task (its LM-cut values are cached across calls)."""

    def __init__(self, robot: GroundTask):
        self.robot = robot
        self._r_goal = sum(1 << p for p in robot.goal)
        self._r_init = sum(1 << p for p in robot.init)
        self._r_relaxed = RelaxedTask(robot)
        self._r_h: dict[int, float] = {}

    def robot_h(self, s: int) -> float:
        h = self._r_h.get(s)
        if h is None:
            h = self._r_h[s] = self._r_relaxed.lmcut(bits(s))
        return h

    def search(
        self,
        humans: Sequence[GroundTask],
        robot_bound: int | None,
        human_bounds: Sequence[int],
        *,
        deadline: Deadline | None = None,
        node_limit: int | None = None,
    ) -> MultiJointResult:
        """The cheapest-robot-cost plan within the bounds (see the module docstring);
        ``deadline``: the run's time limit (checked every 64 expansions); ``node_limit``: at
        most that many expansions, then status ``nodes`` (nothing proven)."""
        n = len(humans)
        bounds = tuple(human_bounds)
        h_goals = [sum(1 << p for p in h.goal) for h in humans]
        relaxed = [RelaxedTask(h) for h in humans]
        h_caches: list[dict[int, float]] = [{} for _ in humans]

        def human_h(i: int, s: int) -> float:
            v = h_caches[i].get(s)
            if v is None:
                v = h_caches[i][s] = relaxed[i].h_max(bits(s))
            return v

        # an action takes part only if every human model has it: a plan using one a human
        # model lacks is not valid there
        by_step = [h.by_step for h in humans]
        acts = []
        for a in self.robot.actions:
            parts = [bs.get(a.step) for bs in by_step]
            if any(p is None for p in parts):
                continue
            acts.append((a.step, _masks(a), tuple(_masks(p) for p in parts)))
        k_bound = _INF if robot_bound is None else robot_bound
        start = (self._r_init, *(sum(1 << p for p in h.init) for h in humans))
        hr0 = self.robot_h(start[0])
        if hr0 > k_bound or any(human_h(i, start[i + 1]) > bounds[i] for i in range(n)):
            return MultiJointResult("none", None, None, None, 0)
        zero = (0,) * (n + 1)
        labels: dict[tuple[int, ...], list[tuple[int, ...]]] = {start: [zero]}
        parent: dict[tuple, tuple[tuple, PlanStep] | None] = {(start, zero): None}
        counter = 0
        heap = [(hr0, hr0, counter, zero, start)]
        expanded = 0
        while heap:
            _, _, _, g, state = heapq.heappop(heap)
            if g not in labels[state]:
                continue  # dominated after it was queued
            if state[0] & self._r_goal == self._r_goal and all(
                state[i + 1] & h_goals[i] == h_goals[i] for i in range(n)
            ):
                steps = []
                node = (state, g)
                while parent[node] is not None:
                    node, step = parent[node]  # type: ignore[misc]
                    steps.append(step)
                return MultiJointResult("plan", tuple(reversed(steps)), g[0], g[1:], expanded)
            if deadline is not None and expanded % 64 == 0 and deadline.expired():
                return MultiJointResult("limit", None, None, None, expanded)
            if node_limit is not None and expanded >= node_limit:
                return MultiJointResult("nodes", None, None, None, expanded)
            expanded += 1
            for step, (rpre, rneg, rkeep, radd, rc), parts in acts:
                sr = state[0]
                if sr & rpre != rpre or sr & rneg:
                    continue
                g2 = [g[0] + rc]
                if g2[0] > k_bound:
                    continue
                nxt = [(sr & rkeep) | radd]
                ok = True
                for i, (pre, neg, keep, add, c) in enumerate(parts):
                    sh = state[i + 1]
                    gi = g[i + 1] + c
                    if sh & pre != pre or sh & neg or gi > bounds[i]:
                        ok = False
                        break
                    th = (sh & keep) | add
                    if gi + human_h(i, th) > bounds[i]:
                        ok = False
                        break
                    g2.append(gi)
                    nxt.append(th)
                if not ok:
                    continue
                hr = self.robot_h(nxt[0])
                if g2[0] + hr > k_bound:
                    continue
                key = tuple(nxt)
                vec = tuple(g2)
                old = labels.get(key)
                if old is None:
                    labels[key] = [vec]
                else:
                    if _dominated(vec, old):
                        continue
                    old[:] = [
                        o for o in old if not all(v <= x for v, x in zip(vec, o, strict=True))
                    ]
                    old.append(vec)
                parent[(key, vec)] = ((state, g), step)
                counter += 1
                heapq.heappush(heap, (g2[0] + hr, hr, counter, vec, key))
        return MultiJointResult("none", None, None, None, expanded)
