"""The ``astar`` engine: the paper's Algorithm 1 (MEGA-Search), reproduced as the baseline.

Model-space search keyed by |E|: every node is a model ``human + E``; popping it calls an optimal
planner for one optimal plan ``pi*`` of that model; ``OBJ_VAL = |E| + alpha * |C(pi*, M^R) -
C*_R|`` (infinite when ``pi*`` is not executable by the robot); with update costs, |E| is
their sum cost(E) both as the queue's key and in ``OBJ_VAL``; the minimum node is kept (``<=``,
so a later node wins ties, as in the paper); the search stops at the first node whose ``pi*`` is
optimal in the robot model.  Successors flip one update not yet in ``E``; a closed list stops
re-expansion.

Deliberately *not* fixed: the search judges a model by the one optimal plan its planner happens
to return, so when a model has several optimal plans it can miss MEGA's best answer.  The
``sat`` engine is compared against it, never the other way round.  A node popped again after it
was closed is skipped without a planner call (the paper's closed list is checked at push time;
skipping a repeat cannot change the answer, only save time, which favours the baseline).
"""

from __future__ import annotations

import heapq
import itertools
import math
import time

from mega_sat.deadline import Deadline, TimeLimitReached
from mega_sat.engines.progress import Progress
from mega_sat.errors import UnsolvableError
from mega_sat.ground.family import GroundFamily
from mega_sat.ground.simulate import simulate_ground
from mega_sat.model.task import TwoModelTask
from mega_sat.options import DEFAULT, Options
from mega_sat.pddl.update_costs import explanation_cost
from mega_sat.planners.node_planner import NodePlanner, require_robot_plan
from mega_sat.results import Frontier, FrontierPoint, Solution, exact_alpha, pareto_filter
from mega_sat.status import Status

DISCLAIMER = (
    "A* baseline: each model is judged by one optimal plan of its planner; ties "
    "between optimal plans can hide better answers, so no optimality is claimed"
)


class _Search:
    """State of one run of MEGA-Search, shared by ``solve`` and ``frontier``.

    The planner's calls are cut at ``planner.deadline``; the search then stops and keeps the
    nodes evaluated so far.  Each evaluated node the robot can execute is also published to
    ``progress``, for a caller whose run is stopped from outside.
    """

    def __init__(
        self,
        task: TwoModelTask,
        family: GroundFamily,
        planner: NodePlanner,
        progress: Progress | None = None,
        update_costs: tuple[int, ...] | None = None,
    ):
        self.task, self.family, self.planner = task, family, planner
        self.update_costs = update_costs
        self.t0 = time.perf_counter()
        self.deadline = planner.deadline
        self.progress = progress if progress is not None else Progress()
        self.progress.start("astar", tuple(u.name for u in task.delta), update_costs)
        self.progress.notes.append(DISCLAIMER)
        self.robot_task = family.specialize(family.robot_selection)
        self.nodes: list[tuple[frozenset[int], tuple, int | None, int | None]] = []
        self.expanded = 0
        self.duplicates = 0
        self.notes: list[str] = []
        self.exact_planner = True
        self.timed_out = False

        r = planner.optimal(family.robot_selection)
        require_robot_plan(task, r)
        self.c_robot = r.cost
        self.exact_planner &= r.exact
        self.progress.robot_optimal_cost = r.cost

    def point(self, sel: frozenset[int], plan, rc: int, hc: int | None) -> FrontierPoint:
        """A node as a frontier point (with its cost(E) when update costs are in use)."""
        weighted = None if self.update_costs is None else self.cost_of(sel)
        return FrontierPoint(tuple(self.task.names(sel)), sel, tuple(plan), rc, hc, weighted)

    def cost_of(self, sel: frozenset[int]) -> int:
        return explanation_cost(sel, self.update_costs)

    def run(self, alpha: float) -> tuple[frozenset[int], tuple, int | None, int | None, float]:
        """Algorithm 1; returns the minimum node ``(E, pi*, robot cost, human cost, obj)``."""
        a = exact_alpha(alpha)
        counter = itertools.count()
        fringe = [(0, next(counter), frozenset())]
        closed: set[frozenset[int]] = set()
        best = None
        best_obj = math.inf
        n = len(self.task.delta)
        costs = self.update_costs or (1,) * n
        while fringe:
            if self.deadline.expired():
                self._time_out()
                break
            c, _, sel = heapq.heappop(fringe)
            if sel in closed:
                self.duplicates += 1
                continue
            self.expanded += 1
            self.progress.step(len(sel))
            try:
                r = self.planner.optimal(sel)
            except TimeLimitReached as e:
                if e.forced:
                    raise
                self._time_out()
                break
            self.exact_planner &= r.exact
            rc = hc = None
            obj = math.inf
            plan = ()
            if r.status == Status.OPTIMAL:
                plan, hc = r.plan, r.cost
                sim = simulate_ground(self.robot_task, plan)
                if sim.valid:
                    rc = sim.cost
                    obj = self.cost_of(sel) + a * abs(rc - self.c_robot)
            self.nodes.append((sel, plan, rc, hc))
            if rc is not None:
                self.progress.points.append(self.point(sel, plan, rc, hc))
            if obj <= best_obj:
                best, best_obj = (sel, plan, rc, hc), obj
            if rc is not None and rc == self.c_robot:
                return (*best, best_obj)
            closed.add(sel)
            for f in range(n):
                if f not in sel:
                    nxt = sel | {f}
                    if nxt not in closed:
                        heapq.heappush(fringe, (c + costs[f], next(counter), nxt))
        if best is None or best_obj == math.inf:
            return (frozenset(), (), None, None, math.inf)
        return (*best, best_obj)

    def _time_out(self) -> None:
        self.timed_out = True
        self.notes.append("time limit reached before the stopping node")

    def frontier(self) -> Frontier:
        pts = [self.point(sel, plan, rc, hc) for sel, plan, rc, hc in self.nodes if rc is not None]
        notes = [DISCLAIMER, *self.notes]
        if not self.exact_planner:
            notes.append("some per-node planner calls were not proven optimal")
        return Frontier(
            engine="astar",
            robot_optimal_cost=self.c_robot,
            model_difference=tuple(u.name for u in self.task.delta),
            points=pareto_filter(pts),
            exact=False,
            complete=not self.timed_out,
            notes=tuple(dict.fromkeys(notes)),
            time_s=time.perf_counter() - self.t0,
            stats={
                "nodes_expanded": self.expanded,
                "duplicate_pops": self.duplicates,
                "planner": self.planner.kind,
                "planner_calls": self.planner.calls,
                "planner_time_s": round(self.planner.time_s, 6),
            },
            update_costs=self.update_costs,
        )


def astar_solve(
    task: TwoModelTask,
    family: GroundFamily,
    alpha: float,
    *,
    planner: str = "builtin",
    timeout: float | None = None,
    oracles=None,
    deadline: Deadline | None = None,
    progress: Progress | None = None,
    update_costs: tuple[int, ...] | None = None,
    options: Options = DEFAULT,
) -> Solution:
    """Algorithm 1 for one ``alpha``: the paper's answer, with the explored nodes as frontier.

    ``deadline`` (or ``timeout`` seconds from now): the search stops there with the best node
    so far; before any node the robot can execute it raises :class:`TimeLimitReached`.
    ``update_costs``: a cost per update; the queue is then keyed by cost(E) instead of |E|.
    Every per-node planner call runs within ``deadline``, with the knobs of ``options``."""
    deadline = deadline if deadline is not None else Deadline.after(timeout)
    np_ = NodePlanner(task, family, planner, oracles=oracles, deadline=deadline, options=options)
    s = _Search(task, family, np_, progress, update_costs)
    sel, plan, rc, hc, obj = s.run(alpha)
    fr = s.frontier()
    if rc is None:
        if s.timed_out:
            raise TimeLimitReached(deadline.seconds)
        raise UnsolvableError("MEGA-Search found no plan executable by the robot")
    chosen = s.point(sel, plan, rc, hc)
    return Solution(alpha, chosen, chosen.objective(alpha, fr.robot_optimal_cost), fr)


def astar_frontier(
    task: TwoModelTask,
    family: GroundFamily,
    *,
    planner: str = "builtin",
    timeout: float | None = None,
    oracles=None,
    deadline: Deadline | None = None,
    progress: Progress | None = None,
    update_costs: tuple[int, ...] | None = None,
    options: Options = DEFAULT,
) -> Frontier:
    """Paper property 4: one MEGA-Search, its explored nodes re-scored for every alpha
    (``deadline``, ``timeout``, ``update_costs``, ``options``: as for :func:`astar_solve`)."""
    deadline = deadline if deadline is not None else Deadline.after(timeout)
    np_ = NodePlanner(task, family, planner, oracles=oracles, deadline=deadline, options=options)
    s = _Search(task, family, np_, progress, update_costs)
    s.run(0.0)
    return s.frontier()
