"""What an engine has proven so far, published as it goes.

A run can be stopped anywhere: by its time limit (cooperatively, or by the CLI's backstop timer
between any two bytecodes) or by SIGINT/SIGTERM.  The engines write each proven fact here the
moment it is proven (the robot optimum, each frontier point, the current lower bound on the
explanation cost),
so the caller that catches the stop can still report them, marked incomplete.
"""

from __future__ import annotations

import time
from dataclasses import dataclass, field

from mega_sat.results import Frontier, FrontierPoint, pareto_filter


@dataclass
class Progress:
    """Facts proven by one engine run; mutable on purpose (the engine appends to it).

    ``points`` are real MEGA solutions (for the ``sat`` engine each with the smallest cost(E)
    for its robot cost level); ``lower_bound`` is a proven lower bound on cost(E) (``|E|``
    without update costs) of any solution cheaper than the last point (``sat`` engine only);
    ``notes`` are the engine's reasons why its result is not exact (shared with the engine, so
    they are current); ``update_costs``: the cost per update when update costs are in use.
    """

    engine: str = ""
    model_difference: tuple[str, ...] = ()
    update_costs: tuple[int, ...] | None = None
    robot_optimal_cost: int | None = None
    points: list[FrontierPoint] = field(default_factory=list)
    lower_bound: int | None = None
    notes: list[str] = field(default_factory=list)
    stats: dict = field(default_factory=dict)
    t0: float = field(default_factory=time.perf_counter)

    def start(
        self,
        engine: str,
        model_difference: tuple[str, ...],
        update_costs: tuple[int, ...] | None = None,
    ) -> None:
        """Forget an earlier run and start recording a new one."""
        self.engine, self.model_difference = engine, model_difference
        self.update_costs = update_costs
        self.robot_optimal_cost, self.lower_bound = None, None
        self.points, self.notes, self.stats = [], [], {}
        self.t0 = time.perf_counter()

    def frontier(self, reason: str) -> Frontier | None:
        """The proven part as an incomplete, inexact :class:`Frontier` (``reason`` says why it
        stopped), or ``None`` before the robot optimum was known (nothing to report)."""
        if self.robot_optimal_cost is None:
            return None
        notes = [*self.notes, reason]
        weighted = self.update_costs is not None
        if self.lower_bound is not None:
            notes[-1] += (
                f"; any solution cheaper than the last point needs "
                f"{'cost(E)' if weighted else '|E|'} >= {self.lower_bound}"
            )
        return Frontier(
            engine=self.engine,
            robot_optimal_cost=self.robot_optimal_cost,
            model_difference=self.model_difference,
            points=pareto_filter(self.points),
            exact=False,
            complete=False,
            notes=tuple(dict.fromkeys(notes)),
            next_size_lower_bound=None if weighted else self.lower_bound,
            time_s=time.perf_counter() - self.t0,
            stats=dict(self.stats),
            update_costs=self.update_costs,
            next_cost_lower_bound=self.lower_bound,
        )
