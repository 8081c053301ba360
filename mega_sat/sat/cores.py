"""Shrinking JOINT's cores: the smaller a core, the more selections one learned clause rules
out (``encodings/joint-and-cores.md``).

Two ways: deletion on the JOINT solver's UNSAT core (:meth:`CoreShrinker.minimize`), and, when
robot costs dominate and the robot bound is below the human optimum, deletion on "no human plan
that cheap" (:meth:`CoreShrinker.by_dominance`), which needs only the human copy.  Every result
is a core even when a budget stops the shrinking early; it is then just not minimal.
"""

from __future__ import annotations

import time
from collections.abc import Iterable
from typing import TYPE_CHECKING

from mega_sat.analysis.monotone import split_relaxing
from mega_sat.ground.family import GuardLit
from mega_sat.sat.encoding import HUMAN
from mega_sat.sat.stats import bump
from mega_sat.search.answers import JointResult
from mega_sat.status import Status

if TYPE_CHECKING:
    from mega_sat.sat.oracles import SatOracles


class CoreShrinker:
    """Core shrinking for the JOINT oracle of ``orc``."""

    def __init__(self, orc: SatOracles):
        self.orc = orc
        self.options = orc.options
        self.stats = orc.stats
        # per way of settling a deletion trial below the human optimum: [work, settled]
        self._trial_stats: dict[str, list[float]] = {"sat": [0.0, 0], "counting": [0.0, 0]}

    def minimize(
        self, base: list[int], sel_lits: list[int], raw_core: Iterable[int]
    ) -> tuple[frozenset[GuardLit], int]:
        """Deletion-based shrinking of the selector part of an UNSAT core of the JOINT solver
        under ``base + sel_lits``; the core and the SAT calls spent.

        Literals at their update's relaxing value are left out without a call: the other value
        only removes plans, so the core holds without them (:mod:`mega_sat.analysis.monotone`);
        they stay assumed in the trials, which keeps each call as constrained as the first.
        Each step drops one literal and re-solves (``core_conflict_budget`` conflicts); an
        UNSAT answer keeps the (possibly smaller) new core, SAT or budget-out keeps the literal.
        At most ``core_calls`` calls: the result is always a core, minimal only if the loop
        finished.
        """
        orc, opts = self.orc, self.options
        solver = orc.solving.joint_solver
        in_core = set(raw_core)
        # a literal at its update's relaxing value is never needed in the core: it stays
        # assumed in every trial (a more constrained, cheaper call) and is left out at the end
        enc = orc.joint_enc
        need, relaxing = split_relaxing(((abs(x) - 1, x > 0) for x in sel_lits), orc.restricting)
        base = base + enc.lits_assumptions(relaxing)
        core = [lit for lit in enc.lits_assumptions(need) if lit in in_core]
        calls = 0
        i = 0
        # a one-literal core is kept as is: the empty core (no selection at all) is rare and
        # mostly caught by the robot lower bound before any SAT call
        while len(core) > 1 and i < len(core) and calls < opts.core_calls:
            trial = core[:i] + core[i + 1 :]
            calls += 1
            self.stats.core_min_calls += 1
            r = orc.solving.solve(solver, base + trial, budget=opts.core_conflict_budget)
            if r is False:
                got = set(solver.get_core() or [])
                core = [lit for lit in trial if lit in got]
            else:
                i += 1
        return frozenset((abs(lit) - 1, lit > 0) for lit in core), calls

    def by_dominance(
        self, lits: list[GuardLit], robot_bound: int, conflict_budget: int | None
    ) -> JointResult:
        """JOINT when no action ever costs the robot less than any model of the family and the
        robot bound ``K`` is below the proven optimum of ``human + E``.

        Every joint plan then has human cost <= robot cost <= K, so "no plan of cost <= K in
        ``human + E'``" rules it out; for ``E`` itself that is proven already (``K < c*``), so
        the full assignment is a core and the work is to shrink it to one that generalizes,
        cheapest argument first (after the literals at a relaxing value, which no such core
        needs, :mod:`mega_sat.analysis.monotone`):

        1. an earlier core "no plan of cost <= K' (>= K)" that ``E`` agrees with (no solving);
        2. deletion, while operator counting is on for the task: each trial (the core without
           one literal) is settled by a short SAT call on the OPT solver (the human copy alone)
           at the family-wide horizon for cost ``K`` with ``dominance_trial_conflicts``
           conflicts, or by operator counting on the abstraction of the trial (a lower bound
           above ``K`` needs no horizon; only if it rules out the full assignment, whose
           abstraction is the finest), whichever has taken less work per settled trial on this
           task so far (:meth:`_trial_cost`);
        3. a trial neither settles gets the SAT call with up to ``core_conflict_budget``
           conflicts.  All SAT calls of one JOINT call together spend at most
           ``dominance_conflict_budget`` conflicts (``conflict_budget`` if smaller).
        """
        orc, opts, stats = self.orc, self.options, self.stats
        t0 = time.perf_counter()
        h, exact, _ = orc.joint_oracle.horizon(None, robot_bound)
        stats.joint_by_dominance = bump(stats.joint_by_dominance)

        def done(core: frozenset[GuardLit], why: str, calls: int) -> JointResult:
            return JointResult(
                Status.INFEASIBLE, None, None, None, core, None, True, why, h, calls,
                orc.finish("joint", t0),
            )  # fmt: skip

        given = set(lits)
        for bound, core in orc.cost_cores:
            # "no plan of cost <= bound" for every selection agreeing with core: also <= K
            if bound >= robot_bound and core <= given:
                stats.joint_core_reused = bump(stats.joint_core_reused)
                return done(
                    core, "robot costs dominate: an earlier core rules out every human plan "
                    "this cheap", 0,
                )  # fmt: skip
        enc = orc.opt_enc
        # SAT trials need the horizon to be a proof; past the cap only counting trials run,
        # and the encoding is not grown to the cap for nothing
        base = []
        if exact:
            base = enc.cost_assumptions(HUMAN, robot_bound, h) + orc.goal_assumptions(enc, h)
        left = opts.dominance_conflict_budget
        if conflict_budget is not None:
            left = min(left, conflict_budget)
        counting_bounds = orc.counting
        # literals at a relaxing value are never needed in the core; they stay assumed in the
        # trials (cheaper calls, tighter bounds) and are left out of the result
        core, relaxing = split_relaxing(lits, orc.restricting)
        if exact:
            base = base + enc.lits_assumptions(relaxing)
        calls, i = 0, 0
        counting: bool | None = None if counting_bounds.enabled else False
        # a one-literal core is kept as is (as in minimize)
        while len(core) > 1 and i < len(core) and calls < opts.core_calls:
            trial = core[:i] + core[i + 1 :]
            verdict, smaller = None, trial
            if counting is not False and not counting_bounds.on():
                counting = False
            ways = (
                sorted(("sat", "counting"), key=self._trial_cost) if counting is not False else []
            )
            for way in ways:
                side = orc.solving.side_work
                if way == "sat" and exact and left > 0:  # short: small tasks settle it at once
                    short = min(opts.dominance_trial_conflicts, left)
                    verdict, smaller, spent = self._trial(base, trial, short)
                    left, calls = left - spent, calls + 1
                    work = spent * opts.race_nodes_per_conflict
                elif way == "counting":
                    if counting is None:  # a trial's abstraction is coarser: no better bound
                        got = counting_bounds.bound(lits, above=robot_bound)
                        counting = got is not None and got > robot_bound
                        if not counting:
                            continue
                    got = counting_bounds.bound(relaxing + trial, above=robot_bound)
                    if got is not None and got > robot_bound:
                        verdict, smaller = False, trial
                    work = orc.solving.side_work - side  # 0 for a cached bound
                else:
                    continue
                self._trial_stats[way][0] += work
                self._trial_stats[way][1] += verdict is not None
                if verdict is not None:
                    break
            if verdict is None and exact and left > 0:
                budget = min(opts.core_conflict_budget, left)
                verdict, smaller, spent = self._trial(base, trial, budget)
                left, calls = left - spent, calls + 1
            if verdict is False:  # no plan within K in any model agreeing with the trial
                core = smaller
            else:
                i += 1
        stats.core_min_calls += calls
        why = "robot costs dominate: the robot bound is below the proven human optimum"
        if len(core) < len(lits):
            why = "robot costs dominate: no human plan within the robot bound"
        orc.cost_cores.append((robot_bound, frozenset(core)))
        return done(frozenset(core), why, calls)

    def _trial_cost(self, way: str) -> float:
        """Work per settled deletion trial so far (0 before the first try, so each way is
        tried once): which way is cheaper differs from domain to domain.  Work is counted as
        the OPT portfolio's referee counts it (conflicts at ``race_nodes_per_conflict``
        states each, an integer program at ``race_states_per_lp_action`` states per action),
        not in seconds, so that every run shrinks the same cores."""
        spent, settled = self._trial_stats[way]
        return spent / max(settled, 1)

    def _trial(
        self, base: list[int], trial: list[GuardLit], budget: int
    ) -> tuple[bool | None, list[GuardLit], int]:
        """One deletion trial of :meth:`by_dominance` on the OPT solver: ``False`` with the
        literals of the solver's core if no plan of cost ``<= K`` fits the family-wide horizon
        under ``trial``, ``True`` if one does, ``None`` if ``budget`` conflicts ran out; and
        the conflicts spent."""
        orc = self.orc
        enc, solver = orc.opt_enc, orc.solving.opt_solver
        before = solver.accum_stats().get("conflicts", 0)
        r = orc.solving.solve(solver, base + enc.lits_assumptions(trial), budget=budget)
        spent = max(solver.accum_stats().get("conflicts", 0) - before, 1)
        if r is False:
            got = set(solver.get_core() or [])
            return False, [g for g in trial if enc.guard_lit(g) in got], spent
        return r, trial, spent
