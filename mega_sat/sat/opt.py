"""The OPT oracle: the optimal cost and plan of one model ``human + E`` by SAT.

(1) relaxed reachability proves unsolvability and gives step/cost lower bounds;
(2) a first plan: an earlier optimal plan, the lowered-cost search's plan, else SAT with a
horizon doubling from the step lower bound (cost unbounded); the operator-counting bound may
prove it optimal at once;
(3) linear descent: with best simulated cost ``C`` ask for cost ``<= C - 1`` at the horizon
that makes the answer exact, until UNSAT (or a lower bound is met); step queries first raise
the step lower bound to the fewest steps of a known plan, which alone proves ``C`` optimal
when the horizon is below it (``encodings/sequential.md``).

Past the horizon cap an explicit search is the proof.  Every reported cost comes from
simulating the decoded plan, never from the solver's counters.
"""

from __future__ import annotations

import time
from collections.abc import Iterable
from typing import TYPE_CHECKING

from mega_sat.analysis.extra_cost import extra_cost_bound, relaxed_bounds
from mega_sat.ground.family import GroundTask
from mega_sat.ground.simulate import ground_plan_cost
from mega_sat.model.lifted import PlanStep
from mega_sat.sat.encoding import HUMAN
from mega_sat.sat.solving import OracleInterrupted
from mega_sat.sat.stats import add_seconds, bump
from mega_sat.search.answers import OptResult
from mega_sat.search.astar import astar, uniform_cost_work
from mega_sat.search.lowered_cost import extra_cost_search
from mega_sat.search.plan_reduction import reduce_plan
from mega_sat.status import Status

if TYPE_CHECKING:
    from mega_sat.sat.oracles import SatOracles

_INF = float("inf")


class _LazyPdr:
    """IC3 on one model, built at its first use and kept for the next (its frames are the
    work done so far); ``solvable`` once it found the goal reachable."""

    def __init__(self, task: GroundTask, lemmas: Iterable[frozenset[tuple[int, bool]]] = ()):
        self.task = task
        self.lemmas = lemmas
        self.pdr = None
        self.solvable = False

    def get(self):
        if self.pdr is None:
            from mega_sat.search.pdr import Pdr

            self.pdr = Pdr(self.task)
            self.pdr.seed(self.lemmas)
        return self.pdr

    def __enter__(self) -> _LazyPdr:
        return self

    def __exit__(self, *exc) -> None:
        if self.pdr is not None:
            self.pdr.close()


_BY_INVARIANT = "an inductive invariant (IC3) excludes the goal"


class _Unreachable(Exception):
    """Raised between solver chunks when the model is proven to have no plan (the message
    says by which proof)."""


def cheaper(task: GroundTask, found, plan, best):
    """``(plan, best)``, or ``found`` after action elimination if it is cheaper."""
    if found is None:
        return plan, best
    found, cost = reduce_plan(task, found)
    return (found, cost) if best is None or cost < best else (plan, best)


class OptOracle:
    """OPT on the OPT solver of ``orc`` (the family encoding with the human copy only); answers
    are cached per selection, and their plans are upper bounds for later selections."""

    def __init__(self, orc: SatOracles):
        self.orc = orc
        self.options = orc.options
        self.stats = orc.stats
        self._cache: dict[frozenset[int], OptResult] = {}
        self._plans: list[tuple[PlanStep, ...]] = []
        # the selection, the cheapest plan known and its cost in the latest call, once it has
        # one: the plan it returns if no cheaper one exists (read after an interrupted call)
        self.descent: tuple[frozenset[int], tuple[PlanStep, ...], int] | None = None
        # per selection: (cheapest action cost, cost every plan spends above N times it)
        self._extra: dict[frozenset[int], tuple[int, int]] = {}
        self._extra_searched: set[frozenset[int]] = set()
        # per selection proven unsolvable by IC3: the invariant's cubes (for its core)
        self.invariants: dict[frozenset[int], tuple[frozenset[tuple[int, bool]], ...]] = {}
        # the cubes of the latest invariants, most recent last: IC3's seeds for the next model
        self._lemmas: dict[frozenset[tuple[int, bool]], None] = {}
        # per side proof that shares SAT's time: [OPT calls it proved, OPT calls it ran in]
        self._side_yield: dict[str, list[int]] = {"probe": [0, 0], "ic3 turns": [0, 0]}
        self.searches_hit = 0
        self.searches_missed = 0
        self.search_steps_saved = 0

    def cached(self, sel: frozenset[int]) -> OptResult | None:
        """The cached answer for ``sel``, if OPT was asked before."""
        return self._cache.get(sel)

    def opt(self, sel: frozenset[int]) -> OptResult:
        """Optimal cost and plan of ``human + sel`` (see the module docstring)."""
        cached = self._cache.get(sel)
        if cached is not None:
            return cached
        t0 = time.perf_counter()
        res = self._opt(sel, t0)
        self._cache[sel] = res
        if res.status == Status.OPTIMAL and res.plan and res.plan not in self._plans:
            self._plans.append(res.plan)
        return res

    # ------------------------------------------------------------- horizons
    def horizon(self, sel: frozenset[int], bound: int, at_least: int = 0):
        """:meth:`SatOracles.horizon` for OPT of one selection: ``floor((bound - extra) / c)``
        with the selection's own cheapest action cost ``c`` and :func:`extra_cost_bound` (OPT
        gives no cores, so the horizon may depend on the selection)."""
        orc = self.orc
        got = self._extra.get(sel)
        if got is None:
            task = orc.task(sel)
            c = min((a.cost for a in task.actions), default=0)
            got = self._extra[sel] = (c, extra_cost_bound(task, c))
        c, extra = got
        if c <= 0 or orc.c_min <= 0:
            return orc.horizon(bound, at_least)
        need = max((bound - extra) // c, 0)
        return orc.capped(need, bound)

    def tighten_extra(self, sel: frozenset[int]) -> tuple[PlanStep, ...] | None:
        """Replace the LM-cut estimate of :meth:`horizon` by the exact optimum under the
        lowered costs when an explicit search finds it within ``opt_extra_node_limit``
        expansions (:func:`extra_cost_search`), and return the plan it found.  A larger extra
        cost shortens the horizon of the proof.  Once per selection."""
        self.horizon(sel, 0)  # makes sure the LM-cut estimate is there
        self._extra_searched.add(sel)
        c, extra = self._extra[sel]
        if c <= 0:
            return None
        t0 = time.perf_counter()
        spent: list[int] = []
        x, plan = extra_cost_search(self.orc.task(sel), c, self.options.opt_extra_node_limit, spent)
        vector_weight = self.options.race_side_vector_weight
        self.orc.solving.side_work += sum(uniform_cost_work(n, vector_weight) for n in spent)
        stats = self.stats
        stats.search_time_s = add_seconds(stats.search_time_s, time.perf_counter() - t0)
        self._extra[sel] = (c, max(extra, x))
        self.searches_hit += plan is not None
        self.searches_missed += plan is None
        self.search_steps_saved += max(x - extra, 0) // c
        stats.search_hits = self.searches_hit
        stats.search_misses = self.searches_missed
        stats.search_steps_saved = self.search_steps_saved
        return plan

    def search_first(self, task: GroundTask, have_plan: bool) -> bool:
        """Whether OPT runs the lowered-cost search (:meth:`tighten_extra`): only with more
        than one action cost (else the lowered costs are all zero), not once most searches on
        this task have run out of expansions, and, when OPT already has a plan to descend
        from, only while the searches shorten the horizon by ``search_first_steps`` steps each
        on average.

        Without a plan, the search's plan is the cheap first upper bound.  With one, a search
        only pays if the SAT proof gets shorter: a search that removes a single step saves
        little, since the step queries of the descent already make the cost query after a step
        bound cheap."""
        opts = self.options
        costs = {a.cost for a in task.actions}
        if len(costs) < 2 or min(costs) <= 0:
            return False
        if (
            self.searches_missed >= opts.search_first_misses
            and self.searches_missed > self.searches_hit
        ):
            return False
        return (
            not have_plan
            or self.searches_hit < opts.search_first_hits
            or self.search_steps_saved >= opts.search_first_steps * self.searches_hit
        )

    # ------------------------------------------------------------------ OPT
    def _opt(self, sel: frozenset[int], t0: float) -> OptResult:
        self.descent = None
        orc = self.orc
        task = orc.task(sel)
        enc, solving = orc.opt_enc, orc.solving
        solver = solving.opt_solver
        calls = 0

        def done(status, cost, plan, exact, reason) -> OptResult:
            return OptResult(status, cost, plan, exact, reason, calls, orc.finish("opt", t0))

        bounds = relaxed_bounds(task)
        if bounds is None:
            return done(Status.UNSOLVABLE, None, None, True, "goal not relaxed-reachable")
        lb_steps, lb_cost = bounds
        if lb_steps == 0:
            return done(Status.OPTIMAL, 0, (), True, "goal holds initially")
        # an earlier core "no plan of cost <= K" that this selection agrees with
        lits = {(i, i in sel) for i in range(orc.family.n_updates)}
        core_lb = max((k + 1 for k, core in orc.cost_cores if core <= lits), default=0)
        why_lb = "meets the relaxed lower bound"
        if core_lb > lb_cost:
            lb_cost, why_lb = core_lb, "meets the lower bound of an earlier core"
        sel_lits = enc.selection_assumptions(sel)

        # (2) a first plan and lower bounds, cheapest first: the cheapest earlier optimal plan
        # valid here; the operator-counting bound; the lowered-cost search (exact extra cost
        # for the horizon, and its plan); else SAT with a doubling horizon and no cost bound.
        # Every plan is shortened by action elimination.
        plan, best = self._known_plan(task), None
        if plan is not None:
            plan, best = reduce_plan(task, plan)
            self.descent = (sel, plan, best)
        if best is None or best > lb_cost:
            got = orc.counting.bound(lits, above=lb_cost)
            solving.check()  # the portfolio's referee may end the call here
            if got is not None and got > lb_cost:
                if got == _INF:
                    assert best is None, "operator counting found no plan, but there is one: bug"
                    return done(Status.UNSOLVABLE, None, None, True, "operator counting: no plan")
                assert best is None or got <= best, "operator-counting bound above a plan's cost"
                lb_cost, why_lb = int(got), "meets the operator-counting lower bound"
        if (best is None or best > lb_cost) and self.search_first(task, best is not None):
            plan, best = cheaper(task, self.tighten_extra(sel), plan, best)
            if plan is not None:
                self.descent = (sel, plan, best)
            solving.check()
        opts = self.options
        cap = opts.horizon_cap
        h = min(max(lb_steps, 1), cap)
        reach = None  # the model's reachable states, explored once SAT needs long
        start = solving.conflicts()
        probe_share: float | None = None  # the probe's share in this call, once it starts

        def reachable(limit: int) -> Status:
            nonlocal reach
            if reach is None:
                # numpy's import (about 60 ms) is paid only by the runs that need the proof
                from mega_sat.search.vector_search import Reachability

                reach = Reachability(task)
            return self._reachability(reach, limit)

        def probe() -> None:
            """Between solver chunks, once the first-plan search has spent
            ``opt_reachability_conflicts`` conflicts: exhaust the model's reachable states
            alongside, ``opt_reachability_probe_rate`` states per conflict spent (at most
            ``opt_reachability_nodes``), and build an inductive invariant (IC3),
            ``opt_invariant_probe_rate`` of its SAT calls per conflict spent (at most
            ``pdr_queries``), so that each check costs about what SAT spends.  The relevant
            part of a model whose unsolvable horizons are hard for SAT is often small, and
            where it is not, an invariant may still be; neither check touches the solver,
            so a model with a plan is answered as before.  Both rates are scaled by the
            probe's record on this task (:meth:`_side_share`)."""
            nonlocal probe_share
            spent = None if start is None else solving.conflicts() - start
            if spent is None or spent < opts.opt_reachability_conflicts:
                return
            if probe_share is None:
                probe_share = self._side_share("probe")
                self._side_yield["probe"][1] += 1
            limit = min(
                int(opts.opt_reachability_probe_rate * spent * probe_share),
                opts.opt_reachability_nodes,
            )
            if reachable(limit) == Status.UNSOLVABLE:
                self._side_yield["probe"][0] += 1
                raise _Unreachable("no reachable state satisfies the goal")
            queries = min(
                int(opts.opt_invariant_probe_rate * spent * probe_share), opts.pdr_queries
            )
            if ic3.solvable or queries <= 0 or (ic3.pdr is not None and ic3.pdr.queries >= queries):
                return
            if self._ic3_turn(sel, ic3, queries):
                self._side_yield["probe"][0] += 1
                raise _Unreachable(_BY_INVARIANT)

        def side_proofs() -> str | None:
            """Once no plan fits ``opt_reachability_steps`` steps: exhaust the reachable
            states and build an invariant (IC3) in turns, each turn doubling both limits
            (from ``opt_side_proof_states`` states up to ``opt_reachability_nodes``; IC3 gets
            ``opt_side_proof_ic3_per_1000`` SAT calls per 1000 states, about the same time;
            none if ``opt_invariant_probe_rate`` is 0; scaled by IC3's record in the turns on
            this task, :meth:`_side_share`).  Which proof is cheaper differs
            from model to model (a small state space, or a large one with a short
            invariant); in turns each costs at most about twice what it needs plus as much
            of the other.  The reason of the proof, or ``None`` (SAT goes on, and the probe
            with it)."""
            limit = min(opts.opt_side_proof_states, opts.opt_reachability_nodes)
            share = self._side_share("ic3 turns")
            turning = False  # IC3 has had a turn in this call
            while True:
                got = reachable(limit)
                if got == Status.UNSOLVABLE:
                    return "no reachable state satisfies the goal"
                if got == Status.PLAN:
                    return None  # some state satisfies the goal: SAT will find the plan
                queries = min(
                    int(limit * opts.opt_side_proof_ic3_per_1000 * share) // 1000,
                    opts.pdr_queries,
                )
                ic3_on = not ic3.solvable and opts.opt_invariant_probe_rate > 0 and queries > 0
                if ic3_on and not turning:
                    turning = True
                    self._side_yield["ic3 turns"][1] += 1
                if ic3_on and self._ic3_turn(sel, ic3, queries):
                    self._side_yield["ic3 turns"][0] += 1
                    return _BY_INVARIANT
                if ic3.solvable or limit >= opts.opt_reachability_nodes:
                    return None
                limit = min(2 * limit, opts.opt_reachability_nodes)

        sided = False  # the side proofs have had their turn
        with _LazyPdr(task, self._lemmas) as ic3:
            solving.between_chunks = probe
            try:
                while plan is None:
                    calls += 1
                    if solving.solve(solver, sel_lits + orc.goal_assumptions(enc, h)):
                        plan = enc.decode_plan(solver.get_model(), h)
                        break
                    if h >= cap:
                        break
                    if h >= opts.opt_reachability_steps and not sided:
                        sided = True
                        why = side_proofs()
                        if why is not None:
                            return done(
                                Status.UNSOLVABLE, None, None, True,
                                f"no plan within {h} steps, and {why}",
                            )  # fmt: skip
                    h = min(2 * h, cap)
            except _Unreachable as e:
                return done(
                    Status.UNSOLVABLE, None, None, True,
                    f"{e} (checked while SAT looked for a plan)",
                )  # fmt: skip
            finally:
                solving.between_chunks = None
            if plan is None:
                return self._fallback(sel, task, calls, t0, ic3)
        if best is None:
            plan, best = reduce_plan(task, plan)

        # (3) descend: cost <= best - 1 until UNSAT
        # min_len: no plan of this model has fewer steps (relaxed, then raised by step queries)
        min_len, len_by_sat = lb_steps, False
        shortest = len(plan)  # the fewest steps of a plan known to run in this model
        while True:
            self.descent = (sel, plan, best)
            if best <= lb_cost:
                return done(Status.OPTIMAL, best, plan, True, why_lb)
            h, exact, reason = self.horizon(sel, best - 1, at_least=len(plan))
            if not exact and orc.c_min > 0:
                # the horizon cap (large costs over a small cheapest one): first make the
                # extra cost exact, which may shorten the horizon below the cap; else an
                # explicit search is the proof, and SAT at the cap only the best effort
                if sel not in self._extra_searched:
                    plan, best = cheaper(task, self.tighten_extra(sel), plan, best)
                    solving.check()
                    continue
                got = self._by_search(task, reason)
                if got is not None:
                    return done(Status.OPTIMAL, got[1], got[0], True, got[2])
            if exact and h < min_len:
                why = (
                    f"proven by SAT: no plan has fewer than {min_len} steps, and cost "
                    f"<= {best - 1} needs at most {h}"
                    if len_by_sat
                    else "no cheaper plan fits the relaxed step lower bound"
                )
                return done(Status.OPTIMAL, best, plan, True, why)
            k = min(shortest - 1, h)
            if self.options.step_first and exact and min_len <= k:
                # (3a) the step query: a plan of at most k steps, at any cost
                calls += 1
                self.stats.step_queries = bump(self.stats.step_queries)
                if not solving.solve(solver, sel_lits + orc.goal_assumptions(enc, k)):
                    self.stats.step_bounds = bump(self.stats.step_bounds)
                    min_len, len_by_sat = k + 1, True
                    continue
                found = enc.decode_plan(solver.get_model(), k)
                assert ground_plan_cost(task, found) is not None, "decoded plan invalid"
                plan, best = cheaper(task, found, plan, best)
                shortest = min(shortest, len(found), len(plan))
                continue
            goal_lits = orc.goal_assumptions(enc, h)
            cost_lits = enc.cost_assumptions(HUMAN, best - 1, h)
            assert cost_lits is not None
            # no plan has fewer than min_len steps: say so (no-op steps only come last)
            at_least = [enc.act[min_len - 1]] if 0 < min_len <= h and enc.symmetry_breaking else []
            calls += 1
            probe = sel not in self._extra_searched and self.search_first(task, True)
            budget = self.options.opt_probe_budget if probe else None
            ok = solving.solve(solver, sel_lits + goal_lits + at_least + cost_lits, budget)
            if ok is None:
                # a hard query: an exact lower bound on the cost above N * c may shorten it
                plan, best = cheaper(task, self.tighten_extra(sel), plan, best)
                solving.check()
                continue
            if not ok:
                return done(Status.OPTIMAL, best, plan, exact, reason or "proven by SAT")
            plan = enc.decode_plan(solver.get_model(), h)
            cost = ground_plan_cost(task, plan)
            assert cost is not None and cost < best, "decoded plan invalid or not cheaper"
            plan, best = reduce_plan(task, plan)
            shortest = min(shortest, len(plan))

    def _known_plan(self, task: GroundTask) -> tuple[PlanStep, ...] | None:
        """The cheapest plan of an earlier OPT answer that is valid in ``task`` (an upper
        bound to descend from: neighbouring candidate models often share optimal plans)."""
        best = None
        for plan in self._plans:
            c = ground_plan_cost(task, plan)
            if c is not None and (best is None or c < best[0]):
                best = (c, plan)
        return None if best is None else best[1]

    def _reachability(self, reach, node_limit: int) -> Status:
        """Go on exhausting the reachable states of ``reach``
        (:class:`mega_sat.search.vector_search.Reachability`) up to ``node_limit`` in all:
        ``UNSOLVABLE`` proves the model has no plan, ``PLAN`` that some reachable state
        satisfies the goal, ``LIMIT`` nothing yet.  Asked alongside SAT's search for a first
        plan and once no plan fits ``opt_reachability_steps`` steps: an unsolvable model has
        no horizon that proves it, and its SAT calls grow harder up to the cap.  Its states
        do not count as work for the portfolio's referee: a proof ends the call at once (the
        answer is the same whoever gives it), and a check that proves nothing should not make
        the referee wait for the search to catch up with it."""
        verdict = self._side_proof(
            lambda deadline: reach.run(node_limit, deadline=deadline), "opt_by_reachability"
        )
        if verdict != Status.UNSOLVABLE:
            self.orc.solving.check()
        return verdict

    def _side_proof(self, prove, counter: str) -> Status:
        """``prove(deadline)``, a proof outside the solver, within the call's deadline: its
        seconds count as ``search_time_s``, a proof of "no plan" as ``counter``, and running
        out of time raises :class:`OracleInterrupted` (nothing proven)."""
        t0 = time.perf_counter()
        verdict = prove(self.orc.solving.effective())
        stats = self.stats
        stats.search_time_s = add_seconds(stats.search_time_s, time.perf_counter() - t0)
        if verdict == Status.TIMEOUT:
            raise OracleInterrupted("deadline reached")
        if verdict == Status.UNSOLVABLE:  # the answer; the referee need not weigh it
            setattr(stats, counter, bump(getattr(stats, counter)))
        return verdict

    # ------------------------------------------------------ past the horizon cap
    def _blind_search(self, task: GroundTask, *, timed: bool):
        """Blind A* within ``fallback_node_limit`` expansions and the time left; a search the
        deadline cuts short raises :class:`OracleInterrupted` (it proves nothing, so nothing
        is cached).  ``timed``: its seconds count as ``search_time_s``."""
        solving = self.orc.solving
        left = solving.time_left()
        if left is not None and left <= 0:
            raise OracleInterrupted("deadline reached")
        t0 = time.perf_counter()
        r = astar(
            task, heuristic="blind", node_limit=self.options.fallback_node_limit, time_limit=left
        )
        if timed:
            stats = self.stats
            stats.search_time_s = add_seconds(stats.search_time_s, time.perf_counter() - t0)
        if r.status == "timeout" and left is not None and solving.time_left() <= 0:
            raise OracleInterrupted("deadline reached")
        return r

    def _by_search(
        self, task: GroundTask, reason: str
    ) -> tuple[tuple[PlanStep, ...], int, str] | None:
        """``(plan, cost, reason)`` of an optimal plan by explicit-state search, for OPT when
        the horizon that would make a SAT answer a proof is above the cap; ``None`` if the
        search gave up."""
        r = self._blind_search(task, timed=True)
        if r.status != "optimal" or ground_plan_cost(task, r.plan) != r.cost:
            return None
        self.stats.opt_by_search = bump(self.stats.opt_by_search)
        return tuple(r.plan), int(r.cost), reason + "; solved by explicit-state search"

    def _fallback(
        self, sel: frozenset[int], task: GroundTask, calls: int, t0: float, ic3: _LazyPdr
    ) -> OptResult:
        """No plan within the horizon cap: only an exhaustive explicit search can decide, or
        an invariant (``ic3``: the IC3 run alongside SAT so far, continued here)."""
        orc = self.orc
        reason = f"no plan within the horizon cap {self.options.horizon_cap}"
        r = self._blind_search(task, timed=False)
        if r.status == "unsolvable":
            return OptResult(
                Status.UNSOLVABLE, None, None, True,
                reason + "; explicit search exhausted the state space", calls,
                orc.finish("opt", t0),
            )  # fmt: skip
        if r.status == "optimal":
            cost = ground_plan_cost(task, r.plan)
            if cost == r.cost:
                return OptResult(
                    Status.OPTIMAL, cost, tuple(r.plan), True,
                    reason + "; solved by explicit-state search", calls, orc.finish("opt", t0),
                )  # fmt: skip
        reason += f"; explicit search gave {r.status}"
        verdict = (
            Status.PLAN if ic3.solvable else self._invariant(ic3.get(), self.options.pdr_queries)
        )
        if verdict == Status.UNSOLVABLE:
            self._keep_invariant(sel, ic3.pdr)
            return OptResult(
                Status.UNSOLVABLE, None, None, True,
                f"{reason}; {_BY_INVARIANT}", calls,
                orc.finish("opt", t0),
            )  # fmt: skip
        return OptResult(
            Status.LIMIT, None, None, False, reason + f"; IC3 gave {verdict.value}",
            calls, orc.finish("opt", t0),
        )  # fmt: skip

    def _side_share(self, kind: str) -> float:
        """The share of its full rate that the side proof ``kind`` gets in this OPT call:
        ``min(1, 2 (proofs + 1) / (calls + 1))`` over the earlier OPT calls it ran in, at
        least ``opt_side_proof_min_share`` (and at most 1).  It stays whole while the proof
        ends about half of the calls it runs in or more; on a task whose models it never
        proves unsolvable, the time it takes from SAT (and, in the turns, IC3's from
        reachability) shrinks.  Counts, not seconds, so every run makes the same calls."""
        proved, ran = self._side_yield[kind]
        return min(1.0, max(2 * (proved + 1) / (ran + 1), self.options.opt_side_proof_min_share))

    def _ic3_turn(self, sel: frozenset[int], ic3: _LazyPdr, queries: int) -> bool:
        """Go on with IC3 up to ``queries`` SAT calls in all: ``True`` once it has proven
        ``sel`` unsolvable (its invariant is kept); ``ic3.solvable`` once it found the goal
        reachable (SAT will find the plan)."""
        verdict = self._invariant(ic3.get(), queries)
        if verdict == Status.UNSOLVABLE:
            self._keep_invariant(sel, ic3.pdr)
            return True
        ic3.solvable = verdict == Status.PLAN
        self.orc.solving.check()  # the portfolio's referee may end the call here
        return False

    def _keep_invariant(self, sel: frozenset[int], pdr) -> None:
        """Hand the invariant that proved ``sel`` unsolvable to the loop (for its core), and
        keep its cubes as lemmas to seed IC3 on later models, at most ``ic3_seed_lemmas`` of
        the most recent (:meth:`mega_sat.search.pdr.Pdr.seed`)."""
        cubes = pdr.invariant()
        self.invariants[sel] = cubes
        limit = self.options.ic3_seed_lemmas
        if limit <= 0:
            return
        for cube in cubes:
            self._lemmas.pop(cube, None)
            self._lemmas[cube] = None
        for cube in list(self._lemmas)[: max(len(self._lemmas) - limit, 0)]:
            del self._lemmas[cube]

    def _invariant(self, pdr, query_limit: int) -> Status:
        """Go on with IC3 (:mod:`mega_sat.search.pdr`) up to ``query_limit`` SAT calls in all,
        within the call's deadline: a model that no horizon proves unsolvable may have an
        invariant that does."""
        return self._side_proof(
            lambda deadline: pdr.run(query_limit, deadline=deadline), "opt_by_invariant"
        )
