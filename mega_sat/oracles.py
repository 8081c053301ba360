"""The SAT oracles of the ``sat`` engine: ``OPT(E)`` and ``JOINT(E, K, c)`` (SPEC section 2).

Two incremental solvers stay alive for the whole task: one holds the family encoding with only
the human copy (OPT), the other the human and robot copies sharing the action variables
(JOINT).  A candidate model ``human + E`` is a set of selector assumptions, so no clause is
ever added per candidate; the encodings only grow (more steps, goal activations, totalizer
outputs).

Exactness (``encodings/sequential.md``): with ``c_min = family.min_cost > 0`` a plan of cost
``<= B`` has at most ``floor(B / c_min)`` steps, so "no plan of cost <= B within that horizon"
is a proof.  Zero-cost actions or a horizon above ``horizon_cap`` make a result inexact; it is
then labelled ``exact=False`` with a reason, never passed off as proven.  Every reported cost
comes from simulating the decoded plan, never from the solver's counters.
"""

from __future__ import annotations

import inspect
import time
from collections.abc import Iterable, Sequence
from dataclasses import dataclass

from pysat.solvers import Solver

from mega_sat.family import GroundFamily, GroundTask, GuardLit, PlanStep
from mega_sat.sat_encoding import HUMAN, ROBOT, FamilyEncoding

_INF = float("inf")


@dataclass(frozen=True)
class OptResult:
    """Outcome of ``OPT(E)``.

    ``status``: ``optimal`` (``cost``/``plan`` set), ``unsolvable`` (no plan at all) or
    ``unknown`` (nothing proven).  ``exact`` is false when the answer is not a proof (then
    ``reason`` says why; an ``optimal`` that is not exact is only the best plan found).
    """

    status: str
    cost: int | None
    plan: tuple[PlanStep, ...] | None
    exact: bool
    reason: str
    calls: int
    time_s: float


@dataclass(frozen=True)
class JointResult:
    """Outcome of ``JOINT(E, K, c)``.

    ``status``: ``plan`` (``plan``, ``robot_cost`` (minimal), ``human_cost`` set) or
    ``infeasible`` (``core`` set: selector literals of the assumptions that alone rule out every
    joint plan within the bounds; ``frozenset()`` means no selection at all has one).
    ``selection`` is the model ``human + E`` the human copy was evaluated in (for a call on a
    partial assignment, the one the solver picked).  ``exact`` as in :class:`OptResult`; an
    inexact core is only valid up to the horizon used (``horizon``).
    """

    status: str
    plan: tuple[PlanStep, ...] | None
    robot_cost: int | None
    human_cost: int | None
    core: frozenset[GuardLit] | None
    selection: frozenset[int] | None
    exact: bool
    reason: str
    horizon: int
    calls: int
    time_s: float


def _simulate_cost(task: GroundTask, plan: Sequence[PlanStep]) -> int | None:
    """Cost of ``plan`` in ``task`` if valid (the shared simulator)."""
    from mega_sat.simulate import simulate_ground

    sim = simulate_ground(task, plan)
    return sim.cost if sim.valid else None


def relaxed_bounds(task: GroundTask) -> tuple[int, int] | None:
    """``(steps, cost)`` lower bounds from the delete relaxation (unit-cost h^max; LM-cut);
    ``None`` if the goal is not even relaxed-reachable (then the task is provably unsolvable).

    A plan meeting the cost bound is optimal without the (often expensive) final UNSAT call.
    """
    from mega_sat.search import RelaxedTask

    if task.goal <= task.init:
        return 0, 0
    rt = RelaxedTask(task)
    state = sorted(task.init)
    h_cost = rt.hmax(state, rt.costs)[0][rt.goal_atom]
    if h_cost == _INF:
        return None
    units = [1] * len(task.actions) + [0]  # the artificial goal action is free
    h_steps = rt.hmax(state, units)[0][rt.goal_atom]
    return int(h_steps), int(max(h_cost, rt.lmcut(state)))


class SatOracles:
    """``OPT`` and ``JOINT`` over one ground family, with live incremental solvers.

    ``horizon_cap`` bounds the number of steps ever encoded; ``core_calls`` bounds the SAT
    calls spent minimizing one core (a core that is not fully minimized is still sound);
    ``fallback_node_limit`` bounds the explicit-state search used when OPT hits the cap.
    """

    def __init__(
        self,
        family: GroundFamily,
        *,
        solver: str = "cadical195",
        horizon_cap: int = 200,
        core_calls: int = 64,
        core_conflict_budget: int = 20000,
        fallback_node_limit: int = 200000,
        symmetry_breaking: bool = True,
        partial_order: bool = False,
    ):
        t0 = time.perf_counter()
        self.family = family
        self.solver_name = solver
        self.horizon_cap = horizon_cap
        self.core_calls = core_calls
        self.core_conflict_budget = core_conflict_budget
        self.fallback_node_limit = fallback_node_limit
        self.c_min = family.min_cost
        # JOINT horizon when zero-cost actions make cost bounds useless for plan length
        self._zero_cost_horizon = min(horizon_cap, 2 * len(family.atoms) + 1)
        self._opt_solver = Solver(name=solver)
        self._joint_solver = Solver(name=solver)
        self.opt_enc = FamilyEncoding(
            family,
            self._opt_solver.add_clause,
            copies=(HUMAN,),
            symmetry_breaking=symmetry_breaking,
            partial_order=partial_order,
        )
        self.joint_enc = FamilyEncoding(
            family,
            self._joint_solver.add_clause,
            copies=(HUMAN, ROBOT),
            symmetry_breaking=symmetry_breaking,
            partial_order=partial_order,
        )
        self._opt_cache: dict[frozenset[int], OptResult] = {}
        self._robot_lb: int | None = None
        self._tasks: dict[frozenset[int], GroundTask] = {}
        self.stats: dict[str, float | int] = {
            "sat_opt_calls": 0,
            "sat_joint_calls": 0,
            "sat_solver_calls": 0,
            "sat_opt_time_s": 0.0,
            "sat_joint_time_s": 0.0,
            "sat_core_min_calls": 0,
            "sat_encode_time_s": time.perf_counter() - t0,
            "sat_max_call_time_s": 0.0,
        }
        self._update_size_stats()

    # ------------------------------------------------------------ plumbing
    def close(self) -> None:
        self._opt_solver.delete()
        self._joint_solver.delete()

    def __enter__(self) -> SatOracles:
        return self

    def __exit__(self, *exc) -> None:
        self.close()

    def _update_size_stats(self) -> None:
        for name, enc in (("opt", self.opt_enc), ("joint", self.joint_enc)):
            size = enc.size()
            self.stats[f"sat_{name}_vars"] = size.variables
            self.stats[f"sat_{name}_clauses"] = size.clauses
            self.stats[f"sat_{name}_horizon"] = size.horizon

    def task(self, selection: Iterable[int]) -> GroundTask:
        sel = frozenset(selection)
        t = self._tasks.get(sel)
        if t is None:
            t = self._tasks[sel] = self.family.specialize(sel)
        return t

    def _horizon(self, bound: int, at_least: int = 0) -> tuple[int, bool, str]:
        """Steps needed so that "no plan with cost <= bound" is a proof, capped.

        With zero-cost actions no horizon is enough; then ``max(bound, at_least)`` steps (a
        known plan's length) are tried, capped, and the answer is marked inexact.
        """
        if self.c_min <= 0:
            return (
                min(max(bound, at_least, 0), self.horizon_cap),
                False,
                "zero-cost actions: plan length is not bounded by cost",
            )
        need = bound // self.c_min
        if need > self.horizon_cap:
            return (
                self.horizon_cap,
                False,
                f"horizon cap {self.horizon_cap} < {need} steps needed for cost <= {bound}",
            )
        return need, True, ""

    def _solve(self, solver: Solver, assumptions: list[int], budget: int | None = None):
        self.stats["sat_solver_calls"] += 1
        if budget is None:
            return solver.solve(assumptions=assumptions)
        solver.conf_budget(budget)
        return solver.solve_limited(assumptions=assumptions)

    def _finish(self, kind: str, t0: float) -> float:
        dt = time.perf_counter() - t0
        self.stats[f"sat_{kind}_calls"] += 1
        self.stats[f"sat_{kind}_time_s"] += dt
        self.stats["sat_max_call_time_s"] = max(self.stats["sat_max_call_time_s"], dt)
        self._update_size_stats()
        return dt

    # ------------------------------------------------------------------- OPT
    def robot_optimal(self) -> OptResult:
        """``OPT`` of the robot model (every update selected)."""
        return self.opt(self.family.robot_selection)

    def opt(self, selection: Iterable[int]) -> OptResult:
        """Optimal cost and plan of ``human + selection``.

        (1) relaxed reachability proves unsolvability and gives step/cost lower bounds;
        (2) a first plan by doubling the horizon from the step lower bound (cost unbounded);
        (3) linear descent: with best simulated cost ``C`` ask for cost ``<= C - 1`` at the
        horizon that makes the answer exact, until UNSAT (or the relaxed lower bound is met).
        """
        sel = frozenset(selection)
        cached = self._opt_cache.get(sel)
        if cached is not None:
            return cached
        t0 = time.perf_counter()
        res = self._opt(sel, t0)
        self._opt_cache[sel] = res
        return res

    def _opt(self, sel: frozenset[int], t0: float) -> OptResult:
        task = self.task(sel)
        enc, solver = self.opt_enc, self._opt_solver
        calls = 0

        def done(status, cost, plan, exact, reason) -> OptResult:
            return OptResult(status, cost, plan, exact, reason, calls, self._finish("opt", t0))

        bounds = relaxed_bounds(task)
        if bounds is None:
            return done("unsolvable", None, None, True, "goal not relaxed-reachable")
        lb_steps, lb_cost = bounds
        if lb_steps == 0:
            return done("optimal", 0, (), True, "goal holds initially")
        sel_lits = enc.selection_assumptions(sel)

        # (2) first plan: double the horizon (no cost bound) until SAT or the cap
        h = min(max(lb_steps, 1), self.horizon_cap)
        plan = None
        while True:
            calls += 1
            if self._solve(solver, sel_lits + enc.goal_assumptions(h)):
                plan = enc.decode_plan(solver.get_model(), h)
                break
            if h >= self.horizon_cap:
                break
            h = min(2 * h, self.horizon_cap)
        if plan is None:
            return self._opt_fallback(task, calls, t0)
        best = _simulate_cost(task, plan)
        assert best is not None, "decoded plan does not simulate: encoding bug"

        # (3) descend: cost <= best - 1 until UNSAT
        while True:
            if best <= lb_cost:
                return done("optimal", best, plan, True, "meets the relaxed lower bound")
            h, exact, reason = self._horizon(best - 1, at_least=len(plan))
            if exact and h < lb_steps:
                return done(
                    "optimal", best, plan, True, "no cheaper plan fits the relaxed step lower bound"
                )
            cost_lits = enc.cost_assumptions(HUMAN, best - 1, h)
            assert cost_lits is not None
            calls += 1
            if not self._solve(solver, sel_lits + enc.goal_assumptions(h) + cost_lits):
                return done("optimal", best, plan, exact, reason or "proven by SAT")
            plan = enc.decode_plan(solver.get_model(), h)
            cost = _simulate_cost(task, plan)
            assert cost is not None and cost < best, "decoded plan invalid or not cheaper"
            best = cost

    def _opt_fallback(self, task: GroundTask, calls: int, t0: float) -> OptResult:
        """No plan within the horizon cap: only an exhaustive explicit search can decide."""
        reason = f"no plan within the horizon cap {self.horizon_cap}"
        try:
            from mega_sat.search import astar
        except ImportError:  # pragma: no cover - search.py is part of the package
            return OptResult("unknown", None, None, False, reason, calls, self._finish("opt", t0))
        kwargs = {"heuristic": "blind"}
        if "node_limit" in inspect.signature(astar).parameters:
            kwargs["node_limit"] = self.fallback_node_limit
        r = astar(task, **kwargs)
        if r.status == "unsolvable":
            return OptResult(
                "unsolvable",
                None,
                None,
                True,
                reason + "; explicit search exhausted the state space",
                calls,
                self._finish("opt", t0),
            )
        if r.status == "optimal":
            cost = _simulate_cost(task, r.plan)
            if cost == r.cost:
                return OptResult(
                    "optimal",
                    cost,
                    tuple(r.plan),
                    True,
                    reason + "; solved by explicit-state search",
                    calls,
                    self._finish("opt", t0),
                )
        return OptResult(
            "unknown",
            None,
            None,
            False,
            reason + f"; explicit search gave {r.status}",
            calls,
            self._finish("opt", t0),
        )

    # ----------------------------------------------------------------- JOINT
    def joint(
        self, selection: Iterable[int], robot_bound: int | None, human_bound: int
    ) -> JointResult:
        """Cheapest robot plan valid in the robot model (robot cost <= ``robot_bound``, None =
        unbounded) and in ``human + selection`` with human cost <= ``human_bound``; or a
        minimized core of selector literals when there is none."""
        sel = frozenset(selection)
        lits = [(i, i in sel) for i in range(self.family.n_updates)]
        return self.joint_lits(lits, robot_bound, human_bound)

    def joint_lits(
        self, lits: Iterable[GuardLit], robot_bound: int | None, human_bound: int
    ) -> JointResult:
        """``JOINT`` under a *partial* assignment of selectors (unassigned ones are free).

        ``joint`` calls it with the full assignment; tests use it to check that a core alone is
        infeasible.
        """
        t0 = time.perf_counter()
        enc, solver = self.joint_enc, self._joint_solver
        lits = list(dict.fromkeys(lits))
        calls = 0
        bmin = human_bound if robot_bound is None else min(robot_bound, human_bound)
        h, exact, reason = self._horizon(bmin, at_least=self._zero_cost_horizon)

        def done(status, plan=None, rc=None, hc=None, core=None, sel=None) -> JointResult:
            return JointResult(
                status,
                plan,
                rc,
                hc,
                core,
                sel,
                exact,
                reason or "proven by SAT",
                h,
                calls,
                self._finish("joint", t0),
            )

        if bmin < 0:
            h = 0
            return done("infeasible", core=frozenset())
        sel_lits = enc.lits_assumptions(lits)
        base = (
            enc.cost_assumptions(HUMAN, human_bound, h)
            + enc.cost_assumptions(ROBOT, robot_bound, h)
            + enc.goal_assumptions(h)
        )
        calls += 1
        if not self._solve(solver, base + sel_lits):
            core = self._minimize_core(base, sel_lits, solver.get_core() or [])
            calls += self._last_core_calls
            return done("infeasible", core=core)
        robot_task = self.task(self.family.robot_selection)
        while True:
            model = solver.get_model()
            sel = enc.decode_selection(model)
            plan = enc.decode_plan(model, h)
            rc = _simulate_cost(robot_task, plan)
            hc = _simulate_cost(self.task(sel), plan)
            assert rc is not None and hc is not None, "decoded joint plan invalid: encoding bug"
            assert hc <= human_bound and (robot_bound is None or rc <= robot_bound)
            # robot cost <= rc - 1 also bounds the plan length; the horizon may shrink
            if rc <= self._robot_lower_bound():
                return done("plan", plan, rc, hc, sel=sel)
            h2 = min(self._horizon(rc - 1)[0], h) if self.c_min > 0 else h
            calls += 1
            ok = self._solve(
                solver,
                enc.cost_assumptions(HUMAN, human_bound, h2)
                + enc.cost_assumptions(ROBOT, rc - 1, h2)
                + enc.goal_assumptions(h2)
                + sel_lits,
            )
            if not ok:
                return done("plan", plan, rc, hc, sel=sel)
            h = h2

    def _robot_lower_bound(self) -> int:
        """A proven lower bound on any robot plan's cost: the robot optimum when already
        computed exactly, else LM-cut of the robot task (saves JOINT's final UNSAT call)."""
        r = self._opt_cache.get(self.family.robot_selection)
        if r is not None and r.exact and r.status == "optimal":
            return r.cost
        if self._robot_lb is None:
            b = relaxed_bounds(self.task(self.family.robot_selection))
            self._robot_lb = b[1] if b is not None else 0
        return self._robot_lb

    def _minimize_core(
        self, base: list[int], sel_lits: list[int], raw_core: Iterable[int]
    ) -> frozenset[GuardLit]:
        """Deletion-based shrinking of the selector part of an UNSAT core.

        Each step drops one literal and re-solves (with a conflict budget); an UNSAT answer
        keeps the (possibly smaller) new core, SAT or budget-out keeps the literal.  At most
        ``core_calls`` calls: the result is always a core, minimal only if the loop finished.
        """
        solver = self._joint_solver
        in_core = set(raw_core)
        core = [lit for lit in sel_lits if lit in in_core]
        self._last_core_calls = 0
        i = 0
        while i < len(core) and self._last_core_calls < self.core_calls:
            trial = core[:i] + core[i + 1 :]
            self._last_core_calls += 1
            self.stats["sat_core_min_calls"] += 1
            if self._solve(solver, base + trial, budget=self.core_conflict_budget) is False:
                got = set(solver.get_core() or [])
                core = [lit for lit in trial if lit in got]
            else:
                i += 1
        return frozenset((abs(lit) - 1, lit > 0) for lit in core)
