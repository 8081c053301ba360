"""The SAT oracles of the ``sat`` engine: ``OPT(E)`` and ``JOINT(E, K, c)`` (encodings/joint-and-cores.md).

Two incremental solvers stay alive for the whole task: one holds the family encoding with only
the human copy (OPT), the other the human and robot copies sharing the action variables
(JOINT).  A candidate model ``human + E`` is a set of selector assumptions, so no clause is
ever added per candidate; the encodings only grow (more steps, goal activations, totalizer
outputs).

Exactness (``encodings/sequential.md``): with ``c_min = family.min_cost > 0`` a plan of cost
``<= B`` has at most ``floor(B / c_min)`` steps, so "no plan of cost <= B within that horizon"
is a proof.  Zero-cost actions or a horizon above ``horizon_cap`` make a result inexact; it is
then labelled ``exact=False`` with a reason, never passed off as proven.

:class:`SatOracles` is the facade the engines use; the work is done in
:mod:`mega_sat.sat.opt` (OPT), :mod:`mega_sat.sat.joint` (JOINT), :mod:`mega_sat.sat.cores`
(core shrinking), :mod:`mega_sat.sat.counting` (operator-counting bounds) and
:mod:`mega_sat.sat.solving` (solvers, chunked solves, deadline and interrupt).
"""

from __future__ import annotations

import time
from collections.abc import Callable, Iterable, Sequence

from mega_sat.analysis.invariants import EncodingFacts, encoding_facts
from mega_sat.analysis.monotone import drop_relaxing, restricting_values
from mega_sat.deadline import Deadline
from mega_sat.ground.family import GroundFamily, GroundTask, GuardLit
from mega_sat.model.lifted import PlanStep
from mega_sat.options import DEFAULT, Options
from mega_sat.sat.counting import CountingBounds
from mega_sat.sat.encoding import HUMAN, ROBOT, UNARY_MAX_UNITS, EncodingSize, FamilyEncoding
from mega_sat.sat.joint import JointOracle
from mega_sat.sat.observer import OracleCall, OracleObserver
from mega_sat.sat.opt import OptOracle
from mega_sat.sat.solving import CADICAL_OPTIONS, OracleInterrupted, Solving, new_solver
from mega_sat.sat.stats import OracleStats, add_seconds, bump
from mega_sat.sat.symmetry import object_swaps
from mega_sat.search.answers import JointResult, OptResult
from mega_sat.search.plan_reduction import reduce_plan

__all__ = [
    "CADICAL_OPTIONS",
    "JointResult",
    "OptResult",
    "OracleInterrupted",
    "SatOracles",
    "new_solver",
]


class SatOracles:
    """``OPT`` and ``JOINT`` over one ground family, with live incremental solvers.

    ``options`` holds the budgets and thresholds (:class:`mega_sat.options.Options`); the
    keyword features choose what is encoded and used: ``solver`` (a python-sat name),
    ``symmetry_breaking`` (object swaps and no-op steps last), ``operator_counting`` (the
    integer-program lower bounds of :mod:`mega_sat.analysis.operator_counting`, for OPT and
    for JOINT's cores) and ``unary_max_units`` (unary or binary cost bounds,
    :data:`mega_sat.sat.encoding.UNARY_MAX_UNITS`).  ``observer`` sees every OPT and JOINT
    call (:mod:`mega_sat.sat.observer`).  ``deadline`` stops any call still running at it.
    """

    def __init__(
        self,
        family: GroundFamily,
        *,
        solver: str = "cadical195",
        options: Options = DEFAULT,
        symmetry_breaking: bool = True,
        operator_counting: bool = True,
        unary_max_units: int = UNARY_MAX_UNITS,
        observer: OracleObserver | None = None,
    ):
        t0 = time.perf_counter()
        self.family = family
        self.options = options
        self.observer = observer
        self.c_min = family.min_cost
        self.stats = OracleStats()
        self.solving = Solving(solver, options, self.stats)
        self._shared_facts: EncodingFacts | None = None
        self._tasks: dict[frozenset[int], GroundTask] = {}
        self._max_horizon: int | None = None
        # (K, core): no selection agreeing with core has a plan of human cost <= K
        self.cost_cores: list[tuple[int, frozenset[GuardLit]]] = []
        # the restricting value of each monotone update: cores never need the other one
        self.restricting = restricting_values(family) if options.monotone_cores else {}
        swaps = object_swaps(family) if symmetry_breaking else []  # shared by both encodings
        self.opt_enc = FamilyEncoding(
            family,
            self.solving.opt_solver.add_clause,
            copies=(HUMAN,),
            symmetry_breaking=symmetry_breaking,
            partial_order=options.partial_order,
            invariants=self._facts,
            unary_max_units=unary_max_units,
            swaps=swaps,
        )
        self.joint_enc = FamilyEncoding(
            family,
            self.solving.joint_solver.add_clause,
            copies=(HUMAN, ROBOT),
            symmetry_breaking=symmetry_breaking,
            partial_order=options.partial_order,
            invariants=self._facts,
            unary_max_units=unary_max_units,
            swaps=swaps,
        )
        self.opt_oracle = OptOracle(self)
        self.joint_oracle = JointOracle(self)
        self.counting = CountingBounds(family, options, operator_counting, self.solving, self.stats)
        self.stats.encode_time_s = time.perf_counter() - t0
        self.stats.cost_bits = self.opt_enc.cost_bits
        self._update_size_stats()

    # ------------------------------------------------------------ life cycle
    def close(self) -> None:
        self.solving.close()

    def __enter__(self) -> SatOracles:
        return self

    def __exit__(self, *exc) -> None:
        self.close()

    @property
    def deadline(self) -> Deadline:
        """Any oracle call still running at this deadline raises :class:`OracleInterrupted`,
        and so does every call started after it, until it is moved (``None``: none)."""
        return self.solving.deadline

    @deadline.setter
    def deadline(self, deadline: Deadline | None) -> None:
        self.solving.deadline = deadline

    def interrupt(self) -> None:
        """Stop the running oracle call (from any thread): it raises :class:`OracleInterrupted`.

        If no call is running, the next solver call raises instead.  Solvers with a native
        interrupt (MiniSat/Glucose family) stop at once; CaDiCaL, which pysat cannot interrupt,
        stops at the end of its current conflict chunk (at most ``solve_chunk`` conflicts).
        """
        self.solving.interrupt()

    # ---------------------------------------------------------------- queries
    def robot_optimal(self) -> OptResult:
        """``OPT`` of the robot model (every update selected)."""
        return self.opt(self.family.robot_selection)

    def opt(self, selection: Iterable[int]) -> OptResult:
        """Optimal cost and plan of ``human + selection`` (:mod:`mega_sat.sat.opt`)."""
        sel = frozenset(selection)
        if self.observer is None:
            return self.opt_oracle.opt(sel)
        call = OracleCall("opt", selection=sel, cached=self.opt_oracle.cached(sel) is not None)
        return self._observed(call, lambda: self.opt_oracle.opt(sel))

    def take_invariant(
        self, selection: Iterable[int]
    ) -> tuple[frozenset[tuple[int, bool]], ...] | None:
        """The cubes of the IC3 invariant that proved ``human + selection`` unsolvable, if OPT
        proved it so (:mod:`mega_sat.sat.invariant_core` turns them into a core); handed
        over once, so that a long run does not keep every invariant."""
        return self.opt_oracle.invariants.pop(frozenset(selection), None)

    def plan_within(
        self,
        selection: Iterable[int],
        bound: int,
        budget: int,
        *,
        max_action_steps: int | None = None,
    ) -> tuple[tuple[PlanStep, ...], int] | None:
        """A plan of ``human + selection`` costing at most ``bound`` and its cost, by one SAT
        call of at most ``budget`` conflicts on the OPT solver at the family-wide horizon for
        ``bound``; ``None`` when there is none or the budget ran out.  A proven "none" is
        kept as a cost core (a lower bound for later OPT calls), as in
        :meth:`mega_sat.sat.cores.CoreShrinker.by_dominance`.  ``max_action_steps`` (``None``:
        no limit): no call, and ``None``, when ground actions times that horizon exceed it
        (the encoding would grow to a size where a conflict budget no longer bounds time)."""
        sel = frozenset(selection)
        enc, solver = self.opt_enc, self.solving.opt_solver
        h, exact, _ = self.joint_oracle.horizon(None, bound)
        if max_action_steps and len(self.family.actions) * h > max_action_steps:
            return None
        cost_lits = enc.cost_assumptions(HUMAN, bound, h)
        if cost_lits is None:
            return None
        lits = [(i, i in sel) for i in range(self.family.n_updates)]
        t0 = time.perf_counter()
        ok = self.solving.solve(
            solver, cost_lits + self.goal_assumptions(enc, h) + enc.lits_assumptions(lits), budget
        )
        self.stats.plan_within_calls = bump(self.stats.plan_within_calls)
        self.stats.plan_within_time_s = add_seconds(
            self.stats.plan_within_time_s, time.perf_counter() - t0
        )
        if ok is False and exact:
            got = set(solver.get_core() or [])
            core = drop_relaxing((g for g in lits if enc.guard_lit(g) in got), self.restricting)
            self.cost_cores.append((bound, core))
        if not ok:
            return None
        task = self.task(sel)
        plan, cost = reduce_plan(task, enc.decode_plan(solver.get_model(), h))
        assert cost is not None and cost <= bound, "decoded plan invalid or too dear: bug"
        self.stats.plan_within_found = bump(self.stats.plan_within_found)
        return plan, cost

    def joint(
        self,
        selection: Iterable[int],
        robot_bound: int | None,
        human_bound: int,
        *,
        hints: Iterable[Sequence[PlanStep]] = (),
        robot_lower_bound: int | None = None,
        human_lower_bound: int | None = None,
        conflict_budget: int | None = None,
        max_action_steps: int | None = None,
    ) -> JointResult:
        """Cheapest robot plan valid in the robot model (robot cost <= ``robot_bound``, None =
        unbounded) and in ``human + selection`` with human cost <= ``human_bound``; or a
        minimized core of selector literals when there is none.

        Optional speed-ups, none of which changes the answer:

        * ``hints``: candidate plans (e.g. the human-optimal ``pi*`` from OPT).  Each is
          simulated in both models; the cheapest valid one within both bounds is a witness, so
          the search only has to look for cheaper robot plans.  Invalid hints are ignored.
        * ``robot_lower_bound``: a *proven* lower bound on every robot plan's cost (the robot
          optimum ``C*_R``); a witness meeting it needs no final UNSAT call, and a
          ``robot_bound`` below it is infeasible with the empty core.
        * ``human_lower_bound``: a *proven* lower bound on every plan of ``human + selection``
          (its optimum ``c*``).  When no action costs the robot less than it costs the human
          in this selection, every joint plan has robot cost >= human cost >= this bound.

        ``conflict_budget`` caps each SAT call; when it runs out the result has status
        ``LIMIT`` (nothing proven; ``plan`` is the best witness found so far, if any).
        ``max_action_steps`` (``None``: no limit) caps the size of the encoding SAT may use:
        a call that needs SAT at a horizon ``h`` with ground actions times ``h`` above it has
        status ``LIMIT`` at once, before the encoding grows to ``h``.  Given, it also marks a
        caller with an explicit search of its own (the sat engine's loop): a call whose exact
        horizon is past ``horizon_cap`` is then ``LIMIT`` too, instead of being answered by
        this oracle's paired-state search.
        """
        sel = frozenset(selection)
        lits = [(i, i in sel) for i in range(self.family.n_updates)]
        plan_lb = 0
        if human_lower_bound is not None and self.joint_oracle.robot_dominates(sel):
            plan_lb = human_lower_bound
        return self._joint(
            lits,
            robot_bound,
            human_bound,
            OracleCall("joint", selection=sel, robot_bound=robot_bound, human_bound=human_bound),
            sel=sel,
            hints=hints,
            robot_lower_bound=robot_lower_bound,
            plan_lower_bound=plan_lb,
            human_optimum=human_lower_bound,
            conflict_budget=conflict_budget,
            max_action_steps=max_action_steps,
        )

    def joint_lits(
        self,
        lits: Iterable[GuardLit],
        robot_bound: int | None,
        human_bound: int,
        *,
        robot_lower_bound: int | None = None,
    ) -> JointResult:
        """``JOINT`` under a *partial* assignment of selectors (unassigned ones are free).

        ``joint`` answers the full assignment; a partial one checks that a core alone is
        infeasible.
        """
        lits = list(lits)
        call = OracleCall(
            "joint", lits=tuple(lits), robot_bound=robot_bound, human_bound=human_bound
        )
        return self._joint(
            lits, robot_bound, human_bound, call, robot_lower_bound=robot_lower_bound
        )

    def _joint(self, lits, robot_bound, human_bound, call: OracleCall, **kw) -> JointResult:
        def answer() -> JointResult:
            return self.joint_oracle.answer(lits, robot_bound, human_bound, **kw)

        return answer() if self.observer is None else self._observed(call, answer)

    # ---------------------------------------------------------- shared pieces
    def task(self, selection: Iterable[int]) -> GroundTask:
        """The ground task ``human + selection`` (cached)."""
        sel = frozenset(selection)
        t = self._tasks.get(sel)
        if t is None:
            t = self._tasks[sel] = self.family.specialize(sel)
        return t

    def horizon(self, bound: int, at_least: int = 0) -> tuple[int, bool, str]:
        """Steps needed so that "no plan with cost <= bound" is a proof, capped; with the
        answer's exactness and, if inexact, why.

        With zero-cost actions no horizon is enough; then ``max(bound, at_least)`` steps (a
        known plan's length) are tried, capped, and the answer is marked inexact.
        """
        if self.c_min <= 0:
            return (
                min(max(bound, at_least, 0), self.options.horizon_cap),
                False,
                "zero-cost actions: plan length is not bounded by cost",
            )
        return self.capped(bound // self.c_min, bound)

    def capped(self, need: int, bound: int) -> tuple[int, bool, str]:
        """``need`` steps, or the cap with the answer marked inexact."""
        cap = self.options.horizon_cap
        if need > cap:
            return cap, False, f"horizon cap {cap} < {need} steps needed for cost <= {bound}"
        return need, True, ""

    def goal_assumptions(self, enc: FamilyEncoding, h: int) -> list[int]:
        """``enc.goal_assumptions(h)``, noting the largest horizon a call asks about."""
        if self._max_horizon is None or h > self._max_horizon:
            self._max_horizon = h
        return enc.goal_assumptions(h)

    def finish(self, kind: str, t0: float) -> float:
        """Count a finished OPT or JOINT call started at ``t0``; its seconds."""
        dt = time.perf_counter() - t0
        stats = self.stats
        if kind == "opt":
            stats.opt_calls += 1
            stats.opt_time_s += dt
        else:
            stats.joint_calls += 1
            stats.joint_time_s += dt
        stats.max_call_time_s = max(stats.max_call_time_s, dt)
        self._update_size_stats()
        return dt

    def encoding_sizes(self) -> dict[str, EncodingSize]:
        """The current size of the OPT and the JOINT encoding (``"opt"``, ``"joint"``)."""
        return {"opt": self.opt_enc.size(), "joint": self.joint_enc.size()}

    def _facts(self) -> EncodingFacts:
        """Invariants and layers of the family, computed once for both encodings, on demand."""
        if self._shared_facts is None:
            t0 = time.perf_counter()
            self._shared_facts = encoding_facts(self.family)
            self.stats.facts_time_s = time.perf_counter() - t0
        return self._shared_facts

    def _update_size_stats(self) -> None:
        stats = self.stats
        stats.grow_time_s = self.opt_enc.grow_s + self.joint_enc.grow_s
        opt, joint = self.opt_enc.size(), self.joint_enc.size()
        stats.opt_vars, stats.opt_clauses, stats.opt_horizon = (
            opt.variables, opt.clauses, opt.horizon,
        )  # fmt: skip
        stats.joint_vars, stats.joint_clauses, stats.joint_horizon = (
            joint.variables, joint.clauses, joint.horizon,
        )  # fmt: skip

    # ------------------------------------------------------------- observing
    def _work(self) -> tuple[float, float, float, float]:
        stats = self.stats
        return (
            stats.solve_time_s,
            self.opt_enc.grow_s + self.joint_enc.grow_s,
            stats.search_time_s or 0.0,
            stats.counting_time_s or 0.0,
        )

    def _observed(self, call: OracleCall, answer: Callable[[], object]):
        """Run ``answer`` as ``call``, between the observer's ``begin`` and ``end``."""
        observer = self.observer
        assert observer is not None
        limit = observer.begin(call)
        if limit is not None:
            self.solving.call_deadline = limit
        conflicts = self.solving.conflicts()
        work = self._work()
        self._max_horizon = None
        t0 = time.perf_counter()
        try:
            call.result = answer()  # type: ignore[assignment]
            return call.result
        except BaseException as e:
            call.error = e
            raise
        finally:
            call.seconds = time.perf_counter() - t0
            if limit is not None:
                self.solving.call_deadline = None
            after = self.solving.conflicts()
            call.conflicts = None if conflicts is None or after is None else after - conflicts
            call.max_horizon_asked = self._max_horizon
            call.solve_s, call.grow_s, call.search_s, call.counting_s = (
                b - a for a, b in zip(work, self._work(), strict=True)
            )
            observer.end(call)
