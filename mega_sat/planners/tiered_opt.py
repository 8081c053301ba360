"""OPT of a candidate model, cheapest proof first (the ``sat`` engine's OPT step).

The hitting-set loop asks for the optimal cost of many models ``human + E`` that differ in a
few updates.  Most answers can be proven without a planner call:

1. **relaxed**: LM-cut of the initial state is infinite, so the goal is unreachable even
   without deletes: *unsolvable*;  **pairs**: some pair of goal facts is not h^2-reachable
   (:mod:`mega_sat.analysis.pair_reachability`; asked only when no remembered plan runs in
   ``human + E``, since a model with a plan cannot be proven unsolvable): *unsolvable*;
2. **cached**: some optimal plan of an earlier candidate runs in ``human + E`` at a cost equal
   to LM-cut of the initial state; LM-cut is admissible, so no plan is cheaper: *optimal*;
   **reachable states**: once some candidate had no plan, and no earlier plan runs in
   ``human + E``, breadth-first reachability on the model's relevant atoms
   (:class:`mega_sat.search.vector_search.Reachability`) within
   ``Options.unsolvable_probe_states`` states: all of them expanded without a goal state is
   *unsolvable*.  The budget halves after each model it does not prove unsolvable and doubles
   after each it does, so where candidates have plans it soon costs little.  Such models
   otherwise reach the planner, where the same proof takes far more work: the portfolio's
   referee lets the search's proof count only once SAT has spent the matching work;
3. **quick search**: uniform-cost search that finishes within ``Options.quick_nodes``
   expansions (exact: an exhausted space proves unsolvability, the first goal popped is
   optimal); the budget halves after each miss (down to 1/64) and doubles after each hit,
   so on tasks where it never answers it costs little.  With Fast Downward as the planner,
   FD starts on the model once the search has made ``Options.fd_alongside_quick_nodes``
   expansions, and runs alongside it on the other core;
4. **planner**: the configured optimal planner (built-in, SAT, Fast Downward, or the
   portfolio of built-in and SAT); ``opt_planner_<name>`` counts which one answered.

Every tier is a proof, so the answers are exactly the planner's costs; only which plan is
returned among equally cheap ones may differ, which the engine's correctness does not depend
on (JOINT looks at all plans within the cost).  ``stats`` counts the answers per tier.
"""

from __future__ import annotations

import time
from dataclasses import dataclass

from mega_sat.analysis.abstraction import abstract_task
from mega_sat.analysis.pair_reachability import goal_pair_unreachable
from mega_sat.analysis.relaxation import RelaxedTask
from mega_sat.ground.family import GroundFamily
from mega_sat.ground.simulate import ground_plan_cost
from mega_sat.model.lifted import PlanStep
from mega_sat.options import Options
from mega_sat.planners.node_planner import NodePlanner
from mega_sat.search.astar import VECTOR_AFTER, PlanResult, astar
from mega_sat.status import Status

_INF = float("inf")


@dataclass(frozen=True)
class Bounds:
    """What :meth:`TieredOpt.bounds` knows about an undecided model without search:
    ``lower`` (LM-cut of the initial state) <= optimum <= ``upper``, the cost of ``plan``,
    a plan of the model (both ``None`` when no remembered plan runs in it)."""

    lower: int
    plan: tuple[PlanStep, ...] | None
    upper: int | None


class NodeBudget:
    """A node budget for searches that may run out: it halves after each miss (down to 1/64
    of ``nodes``) and doubles after each hit (up to ``nodes``), so a search that keeps
    missing on a task costs little there."""

    def __init__(self, nodes: int):
        self.nodes = nodes
        self.now = nodes

    def record(self, hit: bool) -> None:
        if hit:
            self.now = min(self.nodes, 2 * self.now)
        else:
            self.now = max(self.nodes // 64, self.now // 2, 1)


class TieredOpt:
    """``optimal(selection)`` through the tiers above, then ``planner`` (whose options the
    tiers share; the planner call runs within its deadline)."""

    def __init__(
        self, family: GroundFamily, planner: NodePlanner, *, options: Options | None = None
    ):
        self.family = family
        self.planner = planner
        opts = options or planner.options
        quick_nodes = opts.quick_nodes
        self.fd_early = opts.fd_alongside_quick_nodes
        # models FD also starts on the next time it starts early (the loop's first candidate)
        self.fd_ahead: list[frozenset[int]] = []
        # the built-in planner starts with the same uniform-cost search: no quick tier then
        self.quick_nodes = 0 if planner.kind == "builtin" else quick_nodes
        self.quick_budget = NodeBudget(self.quick_nodes)
        self.probe_budget = NodeBudget((options or planner.options).unsolvable_probe_states)
        self._unsolvable_seen = False  # the reachable-states tier waits for a model without plan
        self._plans: list[tuple[PlanStep, ...]] = []
        self._seen: set[tuple[PlanStep, ...]] = set()
        self.stats = {
            f"opt_by_{k}": 0
            for k in ("relaxed", "pairs", "cached", "reachable_states", "quick_search", "planner")
        }
        self.time_s = 0.0

    def optimal(self, selection: frozenset[int], *, searched_only: bool = False) -> PlanResult:
        """The optimum of ``human + selection``; ``searched_only``: skip tiers 1-2 (the
        caller has just asked :meth:`bounds`, which answered nothing)."""
        t0 = time.perf_counter()
        sel = frozenset(selection)
        try:
            r = self._search(sel, t0) if searched_only else self._optimal(sel, t0)
        finally:
            self.time_s += time.perf_counter() - t0
        if r.status == Status.OPTIMAL and r.plan is not None:
            self.remember(r.plan)
        self._unsolvable_seen |= r.status == Status.UNSOLVABLE
        return r

    def remember(self, plan: tuple[PlanStep, ...]) -> None:
        """Keep ``plan`` (of any model of the family) for tier 2 and :meth:`bounds`."""
        if plan not in self._seen:
            self._seen.add(plan)
            self._plans.append(plan)

    def bounds(self, selection: frozenset[int]) -> PlanResult | Bounds:
        """Tiers 1 and 2 alone: a decided answer when they give one, else what they know
        without search: LM-cut of the initial state (a proven lower bound on the optimum) and
        the cheapest remembered plan that runs in ``human + selection`` (an upper bound), if
        any.  The loop asks JOINT at that upper bound before it pays for a proof of the
        optimum (encodings/hitting-set.md, "JOINT before OPT")."""
        t0 = time.perf_counter()
        try:
            r = self._cheap(frozenset(selection), t0)
        finally:
            self.time_s += time.perf_counter() - t0
        if isinstance(r, PlanResult):
            self._unsolvable_seen |= r.status == Status.UNSOLVABLE
        return r

    def _cheap(self, sel: frozenset[int], t0: float) -> PlanResult | Bounds:
        task = self.family.specialize(sel)

        def done(status, plan, cost, how) -> PlanResult:
            return self._done(status, plan, cost, how, t0)

        bound = RelaxedTask(task).lmcut(sorted(task.init))
        if bound == _INF:
            return done(Status.UNSOLVABLE, None, None, "relaxed")
        best = None
        for plan in self._plans:
            c = ground_plan_cost(task, plan)
            if c is not None and (best is None or c < best[0]):
                best = (c, plan)
        # a model a remembered plan runs in has a plan, so the pair check could not prove it
        # unsolvable: skip it (h^2 over the model is most of this tier's time on small tasks)
        if best is None and goal_pair_unreachable(
            abstract_task(self.family, sel, range(self.family.n_updates))
        ):
            return done(Status.UNSOLVABLE, None, None, "pairs")
        if best is not None and best[0] <= bound:
            return done(Status.OPTIMAL, best[1], best[0], "cached")
        if best is None and self._unsolvable_seen and self.probe_budget.nodes > 0:
            # numpy's import is paid only by tasks with a model that has no plan
            from mega_sat.search.vector_search import Reachability

            verdict = Reachability(task).run(self.probe_budget.now)
            self.probe_budget.record(verdict == Status.UNSOLVABLE)
            if verdict == Status.UNSOLVABLE:
                return done(Status.UNSOLVABLE, None, None, "reachable_states")
        lower = int(bound)
        return Bounds(lower, None, None) if best is None else Bounds(lower, best[1], best[0])

    def _optimal(self, sel: frozenset[int], t0: float) -> PlanResult:
        cheap = self._cheap(sel, t0)
        if isinstance(cheap, PlanResult):
            return cheap
        return self._search(sel, t0)

    def _done(self, status: Status, plan, cost, how: str, t0: float) -> PlanResult:
        self.stats[f"opt_by_{how}"] += 1
        return PlanResult(status, plan, cost, True, how, time.perf_counter() - t0, how)

    def _search(self, sel: frozenset[int], t0: float) -> PlanResult:
        """Tiers 3 and 4: the optimum of ``human + sel`` by search."""
        try:
            return self._searched(sel, t0)
        finally:
            if self.planner.kind == "fd":
                self.planner.discard(sel)  # a run started alongside the search and not used

    def _start_fd(self, sel: frozenset[int]) -> None:
        self.planner.prepare(sel)
        for other in self.fd_ahead:
            self.planner.prepare(other)
        self.fd_ahead = []

    def _searched(self, sel: frozenset[int], t0: float) -> PlanResult:
        task = self.family.specialize(sel)
        if self.quick_nodes:
            # Fast Downward, a process of its own, starts alongside a search that has not
            # answered after a few expansions: where the search then gives up, FD is that
            # much further on (ended if the search answers; the answers are the same)
            after = None
            if self.planner.kind == "fd" and self.fd_early > 0:
                after = (self.fd_early, lambda: self._start_fd(sel))
            # no deadline: the node budget bounds it, and a proof it finds is kept even at the
            # deadline (the loop then still reports the robot optimum and a lower bound)
            r = astar(task, heuristic="blind", node_limit=self.quick_budget.now, after=after)
            # where it keeps running out, it is mostly overhead: try it smaller next time
            self.quick_budget.record(r.status.decided)
            if r.status.decided:
                return self._done(r.status, r.plan, r.cost, "quick_search", t0)
            if (
                self.planner.kind == "portfolio"
                and r.expanded is not None
                and r.expanded >= VECTOR_AFTER
            ):
                # the planner's uniform-cost search will pass the same states and go on in
                # numpy: imported here once, a forked race starts with it instead of paying
                # the import in the child, where every run waits for it (times, not answers)
                import mega_sat.search.vector_search  # noqa: F401
        if self.planner.kind == "fd":
            self._start_fd(sel)  # with the models to start alongside, if not started yet
        self.stats["opt_by_planner"] += 1
        r = self.planner.optimal(sel)
        if r.status.decided:  # which planner answered (the portfolio's winner)
            key = f"opt_planner_{r.planner}"
            self.stats[key] = self.stats.get(key, 0) + 1
        return r
