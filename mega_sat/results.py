"""Result types shared by every engine: frontier points, frontiers, chosen solutions.

Both engines return these, so the A* baseline and the SAT engine are swapped by one argument and
compared field by field.  Everything is frozen and serialises with ``to_json()``.
"""

from __future__ import annotations

import json
from collections.abc import Sequence
from dataclasses import dataclass, field
from decimal import Decimal
from fractions import Fraction
from typing import Any

from mega_sat.model.lifted import PlanStep, step_str


@dataclass(frozen=True)
class FrontierPoint:
    """A MEGA solution ``(E, pi)``: ``pi`` is executable in the robot model and optimal (cost
    ``human_cost``) in ``human + E``."""

    explanation: tuple[str, ...]
    selection: frozenset[int]
    plan: tuple[PlanStep, ...]
    robot_cost: int
    human_cost: int
    weighted_cost: int | None = None
    """The sum of the explanation's update costs when update costs are in use, else ``None``."""

    @property
    def size(self) -> int:
        return len(self.explanation)

    @property
    def explanation_cost(self) -> int:
        """cost(E): the sum of the update costs, or ``|E|`` without update costs."""
        return self.size if self.weighted_cost is None else self.weighted_cost

    def objective(self, alpha: float, robot_optimal_cost: int) -> float:
        """MEGA objective (4): ``cost(E) + alpha * (C(pi, M^R) - C*_R)``."""
        return self.explanation_cost + alpha * (self.robot_cost - robot_optimal_cost)

    def to_up_plan(self, problem: Any) -> Any:
        """The plan as a unified-planning ``SequentialPlan`` of ``problem`` (see
        :mod:`mega_sat.pddl.up_models`)."""
        from mega_sat.pddl.up_models import to_up_plan

        return to_up_plan(self.plan, problem)

    def to_dict(self) -> dict[str, Any]:
        d: dict[str, Any] = {"explanation": list(self.explanation)}
        if self.weighted_cost is not None:
            d["explanation_cost"] = self.weighted_cost
        d.update(
            {
                "plan": [step_str(s) for s in self.plan],
                "robot_cost": self.robot_cost,
                "human_cost": self.human_cost,
            }
        )
        return d


@dataclass(frozen=True)
class Frontier:
    """Pareto-optimal pairs ``(cost(E), robot cost)``, ordered by explanation cost (``|E|``
    without update costs).

    ``exact`` is true only when every point is proven (minimal cost(E) for its robot cost,
    optimal human cost, complete frontier).  ``complete`` is false when a time limit stopped the
    engine early; then ``next_cost_lower_bound`` is a proven lower bound on cost(E) for any
    solution cheaper for the robot than the last point found, or for any solution when no point was found
    (``next_size_lower_bound`` the
    same bound on |E|, given without update costs, where the two are one).  ``update_costs``:
    the cost of every update of ``model_difference`` when update costs are in use.
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
    update_costs: tuple[int, ...] | None = None
    next_cost_lower_bound: int | None = None

    def to_dict(self) -> dict[str, Any]:
        d: dict[str, Any] = {
            "engine": self.engine,
            "robot_optimal_cost": self.robot_optimal_cost,
            "model_difference": list(self.model_difference),
        }
        if self.update_costs is not None:
            d["update_costs"] = dict(zip(self.model_difference, self.update_costs, strict=True))
        d.update(
            {
                "frontier": [p.to_dict() for p in self.points],
                "exact": self.exact,
                "complete": self.complete,
                "next_size_lower_bound": self.next_size_lower_bound,
            }
        )
        if self.update_costs is not None:
            d["next_cost_lower_bound"] = self.next_cost_lower_bound
        d.update({"notes": list(self.notes), "time_s": round(self.time_s, 6), "stats": self.stats})
        return d

    def to_json(self, indent: int | None = 2) -> str:
        return json.dumps(self.to_dict(), indent=indent)


@dataclass(frozen=True)
class Solution:
    """The pair chosen for one ``alpha`` (tie-breaking: objective, then robot cost, then
    cost(E)), with the frontier it was chosen from."""

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

    def to_up_plan(self, problem: Any) -> Any:
        """The plan as a unified-planning ``SequentialPlan`` of ``problem`` (see
        :mod:`mega_sat.pddl.up_models`)."""
        from mega_sat.pddl.up_models import to_up_plan

        return to_up_plan(self.chosen.plan, problem)

    def to_json(self, indent: int | None = 2) -> str:
        return json.dumps(self.to_dict(), indent=indent)


@dataclass(frozen=True)
class Explanation:
    """An MCE (``kind`` ``mce``): the smallest ``E`` that makes one given plan optimal in
    ``human + E``; or an MME (``kind`` ``mme``): the smallest ``E`` that keeps it optimal in
    ``human + E'`` for every ``E <= E' <= Delta``.  With
    update costs: the cheapest, ``weighted_cost`` its sum of costs."""

    plan: tuple[PlanStep, ...]
    explanation: tuple[str, ...]
    selection: frozenset[int]
    robot_cost: int
    human_cost: int
    exact: bool
    notes: tuple[str, ...] = ()
    time_s: float = 0.0
    stats: dict[str, Any] = field(default_factory=dict, compare=False)
    weighted_cost: int | None = None
    kind: str = "mce"

    @property
    def explanation_cost(self) -> int:
        """cost(E): the sum of the update costs, or ``|E|`` without update costs."""
        return len(self.explanation) if self.weighted_cost is None else self.weighted_cost

    def to_dict(self) -> dict[str, Any]:
        # "kind" is written for MME only: MCE's JSON keeps the keys it always had
        d: dict[str, Any] = {} if self.kind == "mce" else {"kind": self.kind}
        d |= {
            "plan": [step_str(s) for s in self.plan],
            "explanation": list(self.explanation),
        }
        if self.weighted_cost is not None:
            d["explanation_cost"] = self.weighted_cost
        d.update(
            {
                "robot_cost": self.robot_cost,
                "human_cost": self.human_cost,
                "exact": self.exact,
                "notes": list(self.notes),
                "time_s": round(self.time_s, 6),
                "stats": self.stats,
            }
        )
        return d

    def to_up_plan(self, problem: Any) -> Any:
        """The plan as a unified-planning ``SequentialPlan`` of ``problem`` (see
        :mod:`mega_sat.pddl.up_models`)."""
        from mega_sat.pddl.up_models import to_up_plan

        return to_up_plan(self.plan, problem)

    def to_json(self, indent: int | None = 2) -> str:
        return json.dumps(self.to_dict(), indent=indent)


def pareto_filter(points: Sequence[FrontierPoint]) -> tuple[FrontierPoint, ...]:
    """Keep the Pareto-optimal points (minimise cost(E) and robot cost), one per (cost(E),
    robot cost) pair, ordered by cost(E); among equal pairs the first given wins."""
    best: dict[tuple[int, int], FrontierPoint] = {}
    for p in points:
        best.setdefault((p.explanation_cost, p.robot_cost), p)
    out: list[FrontierPoint] = []
    for key in sorted(best):
        p = best[key]
        if out and out[-1].robot_cost <= p.robot_cost:
            continue  # dominated by a cheaper explanation at no higher cost
        if out and out[-1].explanation_cost == p.explanation_cost:
            continue
        out.append(p)
    return tuple(out)


def needs(bound: int, weighted: bool = False) -> str:
    """What a lower bound of the hitting set proves about the explanation cost (|E|, or
    cost(E) with update costs) of every solution it covers."""
    return f"any solution needs {'cost(E)' if weighted else '|E|'} >= {bound}"


def choose(frontier: Frontier, alpha: float) -> Solution:
    """Pick the frontier point minimising MEGA's objective for ``alpha``.

    Ties: lower robot cost, then smaller cost(E) (docs/index.md).  Because the frontier holds every
    Pareto-optimal pair, this is the optimum over all MEGA solutions (paper property 4).
    """
    exact = exact_alpha(alpha)  # before the float: a Fraction(1, 3) ties as 1/3 does
    alpha = check_alpha(alpha)
    if not frontier.points:
        if not frontier.complete:
            # stopped by the time limit before the first point: nothing to choose from, which
            # proves nothing about the task (the A* engine raises the same at this point)
            from mega_sat.deadline import TimeLimitReached

            bound = frontier.next_cost_lower_bound
            weighted = frontier.update_costs is not None
            raise TimeLimitReached(detail=needs(bound, weighted) if bound else None)
        from mega_sat.errors import UnsolvableError

        raise UnsolvableError("no MEGA solution found")
    c = frontier.robot_optimal_cost
    a = exact
    best = min(
        frontier.points,
        key=lambda p: (
            p.explanation_cost + a * (p.robot_cost - c),
            p.robot_cost,
            p.explanation_cost,
        ),
    )
    return Solution(alpha, best, best.objective(alpha, c), frontier)


def alpha_ranges(frontier: Frontier) -> list[tuple[Fraction, Fraction | None] | None]:
    """For each point, the alphas for which :func:`choose` picks it: ``(lo, hi)`` meaning
    ``lo <= alpha < hi`` (``hi`` None: no upper end), or None when no alpha picks it.

    Point ``i`` beats a point ``j`` with a dearer explanation and a lower robot cost while
    ``alpha < (x_j - x_i) / (cost_i - cost_j)``, with ``x`` the explanation cost (cost(E), or
    |E| without update costs); at equality ``j`` wins (lower robot cost first).  It beats a
    point with a cheaper explanation from ``(x_i - x_j) / (cost_j - cost_i)`` on (at equality
    ``i`` wins, for the same reason).
    """
    pts = frontier.points
    out: list[tuple[Fraction, Fraction | None] | None] = []
    for i, p in enumerate(pts):
        lo = Fraction(0)
        hi: Fraction | None = None
        for j, q in enumerate(pts):
            if j == i or q.robot_cost == p.robot_cost:
                continue
            cut = Fraction(q.explanation_cost - p.explanation_cost, p.robot_cost - q.robot_cost)
            if q.robot_cost < p.robot_cost:  # j is cheaper for the robot: i wins below cut
                hi = cut if hi is None else min(hi, cut)
            else:  # j explains less: i wins from cut on
                lo = max(lo, cut)
        out.append(None if hi is not None and hi <= lo else (lo, hi))
    return out


def check_alpha(alpha: object) -> float:
    """``alpha`` as a float, or a :class:`~mega_sat.errors.UsageError` in the one wording that
    the CLI (``--alpha TEXT``, shown as typed) and the library (any value, shown by ``repr``)
    share."""
    from mega_sat.errors import UsageError

    try:
        a = float(alpha)  # type: ignore[arg-type]
    except (TypeError, ValueError, OverflowError):  # OverflowError: an int such as 10**400
        a = float("nan")
    if isinstance(alpha, bool | bytes):  # float(True) is 1.0, float(b"1") is 1.0: slips
        a = float("nan")
    if not 0 <= a < float("inf"):
        raise UsageError(f"alpha must be a finite number >= 0, got {alpha!r}")
    return a + 0.0  # -0.0 becomes 0.0, so it is not echoed as "-0.0"


def exact_alpha(alpha: float) -> Fraction:
    """alpha as the exact decimal the user wrote, so ties such as ``1 + 0.1*30 == 3 + 0.1*10``
    are ties, not float noise; an int, a ``Fraction`` or a ``Decimal`` as it is (checked by
    :func:`check_alpha` first)."""
    check_alpha(alpha)
    if isinstance(alpha, int | Fraction | Decimal):
        return Fraction(alpha)
    return Fraction(repr(float(alpha)))
