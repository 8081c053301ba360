"""Result types shared by every engine: frontier points, frontiers, chosen solutions.

Both engines return these, so the A* baseline and the SAT engine are swapped by one argument and
compared field by field.  Everything is frozen and serialises with ``to_json()``.
"""

from __future__ import annotations

import json
from collections.abc import Sequence
from dataclasses import dataclass, field
from fractions import Fraction
from typing import Any

from mega_sat.family import PlanStep, step_str


@dataclass(frozen=True)
class FrontierPoint:
    """A MEGA solution ``(E, pi)``: ``pi`` is executable in the robot model and optimal (cost
    ``human_cost``) in ``human + E``."""

    explanation: tuple[str, ...]
    selection: frozenset[int]
    plan: tuple[PlanStep, ...]
    robot_cost: int
    human_cost: int

    @property
    def size(self) -> int:
        return len(self.explanation)

    def objective(self, alpha: float, robot_optimal_cost: int) -> float:
        """MEGA objective (4): ``|E| + alpha * (C(pi, M^R) - C*_R)``."""
        return self.size + alpha * (self.robot_cost - robot_optimal_cost)

    def to_dict(self) -> dict[str, Any]:
        return {
            "explanation": list(self.explanation),
            "plan": [step_str(s) for s in self.plan],
            "robot_cost": self.robot_cost,
            "human_cost": self.human_cost,
        }


@dataclass(frozen=True)
class Frontier:
    """Pareto-optimal pairs ``(|E|, robot cost)``, ordered by explanation size.

    ``exact`` is true only when every point is proven (minimal |E| for its robot cost, optimal
    human cost, complete frontier).  ``complete`` is false when a time limit stopped the engine
    early; then ``next_size_lower_bound`` is a proven lower bound on |E| for any solution cheaper
    for the robot than the last point found.
    """

    engine: str
    robot_optimal_cost: int
    model_difference: tuple[str, ...]
    points: tuple[FrontierPoint, ...]
    exact: bool
    complete: bool
    notes: tuple[str, ...] = ()
    next_size_lower_bound: int | None = None
    time_s: float = 0.0
    stats: dict[str, Any] = field(default_factory=dict, compare=False)

    def to_dict(self) -> dict[str, Any]:
        return {
            "engine": self.engine,
            "robot_optimal_cost": self.robot_optimal_cost,
            "model_difference": list(self.model_difference),
            "frontier": [p.to_dict() for p in self.points],
            "exact": self.exact,
            "complete": self.complete,
            "next_size_lower_bound": self.next_size_lower_bound,
            "notes": list(self.notes),
            "time_s": round(self.time_s, 6),
            "stats": self.stats,
        }

    def to_json(self, indent: int | None = 2) -> str:
        return json.dumps(self.to_dict(), indent=indent)


@dataclass(frozen=True)
class Solution:
    """The pair chosen for one ``alpha`` (SPEC tie-breaking: objective, then robot cost, then
    |E|), with the frontier it was chosen from."""

    alpha: float
    chosen: FrontierPoint
    objective: float
    frontier: Frontier

    def to_dict(self) -> dict[str, Any]:
        d = self.frontier.to_dict()
        chosen = self.chosen.to_dict()
        chosen["objective"] = self.objective
        d.update({"alpha": self.alpha, "chosen": chosen})
        return d

    def to_json(self, indent: int | None = 2) -> str:
        return json.dumps(self.to_dict(), indent=indent)


@dataclass(frozen=True)
class Explanation:
    """An MCE (``kind`` ``mce``): the smallest ``E`` that makes one given plan optimal in
    ``human + E``; or an MME (``kind`` ``mme``): the smallest ``E`` that keeps it optimal in
    ``human + E'`` for every ``E <= E' <= Delta``."""

    plan: tuple[PlanStep, ...]
    explanation: tuple[str, ...]
    selection: frozenset[int]
    robot_cost: int
    human_cost: int
    exact: bool
    notes: tuple[str, ...] = ()
    time_s: float = 0.0
    stats: dict[str, Any] = field(default_factory=dict, compare=False)
    kind: str = "mce"

    def to_dict(self) -> dict[str, Any]:
        # "kind" is written for MME only: MCE's JSON keeps the keys it always had
        head: dict[str, Any] = {} if self.kind == "mce" else {"kind": self.kind}
        return {
            **head,
            "plan": [step_str(s) for s in self.plan],
            "explanation": list(self.explanation),
            "robot_cost": self.robot_cost,
            "human_cost": self.human_cost,
            "exact": self.exact,
            "notes": list(self.notes),
            "time_s": round(self.time_s, 6),
            "stats": self.stats,
        }

    def to_json(self, indent: int | None = 2) -> str:
        return json.dumps(self.to_dict(), indent=indent)


def pareto_filter(points: Sequence[FrontierPoint]) -> tuple[FrontierPoint, ...]:
    """Keep the Pareto-optimal points (minimise |E| and robot cost), one per (|E|, cost) pair,
    ordered by |E|; among equal pairs the first given wins."""
    best: dict[tuple[int, int], FrontierPoint] = {}
    for p in points:
        best.setdefault((p.size, p.robot_cost), p)
    out: list[FrontierPoint] = []
    for key in sorted(best):
        p = best[key]
        if out and out[-1].robot_cost <= p.robot_cost:
            continue  # dominated by a smaller explanation at no higher cost
        if out and out[-1].size == p.size:
            continue
        out.append(p)
    return tuple(out)


def choose(frontier: Frontier, alpha: float) -> Solution:
    """Pick the frontier point minimising MEGA's objective for ``alpha``.

    Ties: lower robot cost, then smaller |E| (docs/index.md).  Because the frontier holds every
    Pareto-optimal pair, this is the optimum over all MEGA solutions (paper property 4).
    """
    if not alpha >= 0:
        raise ValueError("alpha must be a number >= 0")
    if not frontier.points:
        from mega_sat.errors import UnsolvableError

        raise UnsolvableError(
            "no MEGA solution found"
            + ("" if frontier.complete else " before the time limit (try a larger --timeout)")
        )
    c = frontier.robot_optimal_cost
    a = exact_alpha(alpha)
    best = min(
        frontier.points, key=lambda p: (p.size + a * (p.robot_cost - c), p.robot_cost, p.size)
    )
    return Solution(alpha, best, best.objective(alpha, c), frontier)


def exact_alpha(alpha: float) -> Fraction:
    """alpha as the exact decimal the user wrote, so ties such as ``1 + 0.1*30 == 3 + 0.1*10``
    are ties, not float noise."""
    return Fraction(repr(float(alpha)))
