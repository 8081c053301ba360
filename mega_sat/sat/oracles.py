"""The SAT oracles of the ``sat`` engine: ``OPT(E)`` and ``JOINT(E, K, c)`` (encodings/joint-and-cores.md).

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

import threading
import time
from collections.abc import Iterable, Sequence
from dataclasses import dataclass
from functools import cached_property

from pysat.solvers import Solver

from mega_sat.analysis.abstraction import abstract_task
from mega_sat.analysis.invariants import EncodingFacts, encoding_facts
from mega_sat.analysis.operator_counting import operator_counting_bound
from mega_sat.errors import redeliver_sigint
from mega_sat.ground.family import GroundFamily, GroundTask, GuardLit, holds
from mega_sat.ground.simulate import ground_plan_cost
from mega_sat.model.lifted import PlanStep
from mega_sat.sat.encoding import HUMAN, ROBOT, UNARY_MAX_UNITS, FamilyEncoding
from mega_sat.search.plan_reduction import reduce_plan

_INF = float("inf")


class OracleInterrupted(Exception):  # noqa: N818 - the name says what happened
    """A SAT oracle call was stopped by :meth:`SatOracles.interrupt` or its deadline.

    Nothing was proven by the interrupted call; the oracles stay usable for later calls.
    """


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


# Options for CaDiCaL (both versions) as the oracles' solver: bounded variable elimination
# off, because the oracles' many small incremental calls under assumptions need fewer
# conflicts without it (the measurements are in bench/README.md, per-call section).
CADICAL_OPTIONS = {"elim": 0}


def new_solver(name: str) -> Solver:
    """A python-sat solver for the oracles, with :data:`CADICAL_OPTIONS` for CaDiCaL."""
    solver = Solver(name=name)
    if name.startswith("cadical"):
        solver.solver.configure(CADICAL_OPTIONS)
    return solver


def _supports_interrupt(solver: Solver) -> bool:
    try:
        solver.clear_interrupt()
    except NotImplementedError:
        return False
    return True


def extra_cost_bound(task: GroundTask, c_min: int) -> int:
    """LM-cut of ``task`` with every action cost lowered by ``c_min``.

    Every plan of ``N`` steps costs ``N * c_min + (its cost under the lowered costs)``, and the
    latter is at least this admissible estimate, so a plan of cost ``<= B`` has at most
    ``floor((B - extra) / c_min)`` steps: a tighter horizon than ``floor(B / c_min)`` when
    some actions cost more than the cheapest one.
    """
    from mega_sat.analysis.relaxation import RelaxedTask

    if c_min <= 0 or task.goal <= task.init:
        return 0
    rt = RelaxedTask(task)
    rt.costs = [max(0, c - c_min) for c in rt.costs[:-1]] + [0]
    h = rt.lmcut(sorted(task.init))
    return 0 if h == _INF else int(h)


def extra_cost_search(
    task: GroundTask, c_min: int, node_limit: int
) -> tuple[int, tuple[PlanStep, ...] | None]:
    """:func:`extra_cost_bound`, made exact by an explicit optimal search under the lowered
    costs when it finishes within ``node_limit`` expansions (else the LM-cut estimate), and
    the plan that search found (``None`` if it ran out).

    The plan is a valid plan of ``task`` with the fewest cost units above ``c_min`` per step;
    on barman-bar it is an optimal plan of every model, so OPT starts its descent there."""
    from dataclasses import replace

    from mega_sat.search.astar import astar

    lm = extra_cost_bound(task, c_min)
    if c_min <= 0 or task.goal <= task.init or node_limit <= 0:
        return lm, None
    low = GroundTask(
        task.atoms,
        tuple(replace(a, cost=a.cost - c_min) for a in task.actions),
        task.init,
        task.goal,
    )
    r = astar(low, heuristic="blind", node_limit=node_limit)
    if r.status == "optimal" and r.cost is not None:
        return max(lm, int(r.cost)), tuple(r.plan)
    return lm, None


def extra_cost_exact(task: GroundTask, c_min: int, node_limit: int) -> int:
    """The exact (or LM-cut) extra cost of :func:`extra_cost_search`."""
    return extra_cost_search(task, c_min, node_limit)[0]


def family_relaxation(family: GroundFamily) -> GroundTask:
    """A task whose delete relaxation over-approximates that of *every* family member: every
    action, only unguarded (pre)conditions and goals, every add effect and initial atom, the
    cheapest cost case.  Its admissible estimates are lower bounds for every selection."""
    from mega_sat.ground.family import StripsAction

    acts = []
    for i, a in enumerate(family.actions):
        acts.append(
            StripsAction(
                i,
                a.name,
                a.args,
                frozenset(p for p, g in a.pre if g is None),
                frozenset(),
                frozenset(p for p, _ in a.add),
                frozenset(),
                min((v for _, v in a.cost), default=0),
            )
        )
    return GroundTask(
        family.atoms,
        tuple(acts),
        frozenset(p for p, _ in family.init),
        frozenset(p for p, g in family.goal if g is None),
    )


def relaxed_bounds(task: GroundTask) -> tuple[int, int] | None:
    """``(steps, cost)`` lower bounds from the delete relaxation (unit-cost h^max; LM-cut);
    ``None`` if the goal is not even relaxed-reachable (then the task is provably unsolvable).

    A plan meeting the cost bound is optimal without the (often expensive) final UNSAT call.
    """
    from mega_sat.analysis.relaxation import RelaxedTask

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
    ``fallback_node_limit`` bounds the explicit-state search used when OPT hits the cap;
    ``solve_chunk`` caps the conflict chunk between interrupt/deadline checks;
    ``extra_node_limit`` bounds the explicit search that makes the robot copy's step bound
    exact (:func:`extra_cost_exact`); an OPT proof that is still undecided after
    ``opt_probe_budget`` conflicts gets the same search for its selection, with
    ``opt_extra_node_limit`` expansions, to shorten its horizon (on tasks with several action
    costs the search runs first, and its plan is OPT's first upper bound);
    ``operator_counting`` enables the integer-program lower bounds of
    :mod:`mega_sat.analysis.operator_counting` (CBC, ``counting_time_limit`` seconds each) for OPT and
    for JOINT's cores; ``dominance_conflict_budget`` caps the conflicts spent shrinking one
    core below the human optimum (:meth:`_joint_by_dominance`); ``step_first`` lets OPT's
    descent ask "a plan of at most k steps, any cost" before its cost queries (a proven step
    lower bound settles most hard proofs without the cost totalizer; ``encodings/sequential.md``,
    OPT step 6); ``unary_max_units`` chooses between unary and binary cost bounds in the
    encodings (:data:`mega_sat.sat.encoding.UNARY_MAX_UNITS`).
    """

    def __init__(
        self,
        family: GroundFamily,
        *,
        solver: str = "cadical195",
        horizon_cap: int = 200,
        core_calls: int = 64,
        core_conflict_budget: int = 5000,
        dominance_conflict_budget: int = 3000,
        fallback_node_limit: int = 200000,
        symmetry_breaking: bool = True,
        partial_order: bool = False,
        solve_chunk: int = 5000,
        extra_node_limit: int = 10000,
        opt_probe_budget: int = 3000,
        opt_extra_node_limit: int = 20000,
        operator_counting: bool = True,
        counting_time_limit: float = 2.0,
        step_first: bool = True,
        unary_max_units: int = UNARY_MAX_UNITS,
    ):
        t0 = time.perf_counter()
        self.family = family
        self.solver_name = solver
        self.horizon_cap = horizon_cap
        self.step_first = step_first
        self.core_calls = core_calls
        self.core_conflict_budget = core_conflict_budget
        self.dominance_conflict_budget = dominance_conflict_budget
        self.fallback_node_limit = fallback_node_limit
        self.c_min = family.min_cost
        # JOINT horizon when zero-cost actions make cost bounds useless for plan length
        self._zero_cost_horizon = min(horizon_cap, 2 * len(family.atoms) + 1)
        self._shared_facts: EncodingFacts | None = None
        self._opt_solver = new_solver(solver)
        self._joint_solver = new_solver(solver)
        self.opt_enc = FamilyEncoding(
            family,
            self._opt_solver.add_clause,
            copies=(HUMAN,),
            symmetry_breaking=symmetry_breaking,
            partial_order=partial_order,
            invariants=self._facts,
            unary_max_units=unary_max_units,
        )
        self.joint_enc = FamilyEncoding(
            family,
            self._joint_solver.add_clause,
            copies=(HUMAN, ROBOT),
            symmetry_breaking=symmetry_breaking,
            partial_order=partial_order,
            invariants=self._facts,
            unary_max_units=unary_max_units,
        )
        self._opt_cache: dict[frozenset[int], OptResult] = {}
        self._opt_plans: list[tuple[PlanStep, ...]] = []
        # (K, core): no selection agreeing with core has a plan of human cost <= K
        self._cost_cores: list[tuple[int, frozenset[GuardLit]]] = []
        self._robot_lb: int | None = None
        self._searcher = None  # explicit paired-state search, for JOINT past the horizon cap
        self._tasks: dict[frozenset[int], GroundTask] = {}
        # per-copy minimum action costs for the JOINT horizon: the robot copy always runs in
        # the robot model; the human copy's must hold for every selection (cores generalize)
        robot_costs = [a.cost for a in self.task(family.robot_selection).actions]
        self.c_min_robot = min(robot_costs, default=self.c_min)
        self._dominance: dict[frozenset[int], bool] = {}
        # cost the cheapest plan must spend above N * c_min (tightens the JOINT horizon)
        self.extra_robot = extra_cost_exact(
            self.task(family.robot_selection), self.c_min_robot, extra_node_limit
        )
        self.extra_human = extra_cost_bound(family_relaxation(family), self.c_min)
        self._opt_extra: dict[frozenset[int], tuple[int, int]] = {}
        self._opt_extra_searched: set[frozenset[int]] = set()
        self._searches_hit = 0
        self._searches_missed = 0
        self._search_steps_saved = 0  # horizon steps the hits removed, in all
        self.opt_probe_budget = opt_probe_budget
        self.opt_extra_node_limit = opt_extra_node_limit
        # operator-counting bounds per partial assignment; switched off for the task once
        # they have been tried a few times without ever beating the cheaper bounds
        self.operator_counting = operator_counting
        self.counting_time_limit = counting_time_limit
        if operator_counting:
            # PuLP takes 0.04-0.06 s to import: a once-per-process set-up cost, paid here with
            # the rest of the set-up rather than inside whichever OPT call first needs a bound
            import pulp  # noqa: F401
        self._counting: dict[frozenset[GuardLit], float | None] = {}
        self._counting_tries = 0
        self._counting_gains = 0
        # per way of settling a deletion trial below the human optimum: [seconds, settled]
        self._trial_stats: dict[str, list[float]] = {"sat": [0.0, 0], "counting": [0.0, 0]}
        # interruption: a flag checked between conflict-budget chunks (CaDiCaL holds the GIL
        # and has no native interrupt in pysat), plus the native interrupt where supported
        self._interrupted = False
        self._deadline: float | None = None
        self._timer: threading.Timer | None = None
        self.solve_chunk = solve_chunk
        self._rate: dict[int, float] = {}  # measured seconds per conflict, per solver
        self._native_interrupt = _supports_interrupt(self._joint_solver)
        self.stats: dict[str, float | int] = {
            "sat_opt_calls": 0,
            "sat_joint_calls": 0,
            "sat_solver_calls": 0,
            "sat_solve_time_s": 0.0,
            "sat_opt_time_s": 0.0,
            "sat_joint_time_s": 0.0,
            "sat_core_min_calls": 0,
            "sat_encode_time_s": time.perf_counter() - t0,
            "sat_max_call_time_s": 0.0,
            # how cost bounds are encoded: 0 = unary units, else bits per step (binary)
            "sat_cost_bits": self.opt_enc.cost_bits,
        }
        self._update_size_stats()

    def _facts(self) -> EncodingFacts:
        """Invariants and layers of the family, computed once for both encodings, on demand."""
        if self._shared_facts is None:
            t0 = time.perf_counter()
            self._shared_facts = encoding_facts(self.family)
            self.stats["sat_facts_time_s"] = time.perf_counter() - t0
        return self._shared_facts

    # ------------------------------------------------------------ plumbing
    def close(self) -> None:
        self.set_deadline(None)
        self._opt_solver.delete()
        self._joint_solver.delete()

    # ---------------------------------------------------------- interruption
    def interrupt(self) -> None:
        """Stop the running oracle call (from any thread): it raises :class:`OracleInterrupted`.

        If no call is running, the next solver call raises instead.  Solvers with a native
        interrupt (MiniSat/Glucose family) stop at once; CaDiCaL, which pysat cannot interrupt,
        stops at the end of its current conflict chunk (at most ``solve_chunk`` conflicts,
        0.2-0.5 s on the shipped problems).
        """
        self._interrupted = True
        if self._native_interrupt:
            for s in (self._opt_solver, self._joint_solver):
                s.interrupt()

    @property
    def deadline(self) -> float | None:
        """The deadline of :meth:`set_deadline` (``None``: none)."""
        return self._deadline

    def set_deadline(self, deadline: float | None) -> None:
        """Interrupt any oracle call still running at ``deadline`` (a ``time.perf_counter()``
        value; ``None`` clears it).  Every solver call started after the deadline raises
        :class:`OracleInterrupted` until the deadline is cleared or moved.  A deadline beyond
        what a timer can wait for (``threading.TIMEOUT_MAX``) is no deadline: the timer thread
        would die of an OverflowError."""
        if self._timer is not None:
            self._timer.cancel()
            self._timer = None
        delay = None if deadline is None else max(0.0, deadline - time.perf_counter())
        if delay is not None and not delay < threading.TIMEOUT_MAX / 2:
            deadline = delay = None
        self._deadline = deadline
        self._clear_interrupt()
        if delay is not None:
            self._timer = threading.Timer(delay, self.interrupt)
            self._timer.daemon = True
            self._timer.start()

    def _clear_interrupt(self) -> None:
        self._interrupted = False
        if self._native_interrupt:
            for s in (self._opt_solver, self._joint_solver):
                s.clear_interrupt()

    def _check_interrupt(self) -> None:
        left = self._time_left()
        late = left is not None and left <= 0
        if self._interrupted or late:
            self._clear_interrupt()
            raise OracleInterrupted("deadline reached" if late else "interrupted")

    def __enter__(self) -> SatOracles:
        return self

    def __exit__(self, *exc) -> None:
        self.close()

    def _update_size_stats(self) -> None:
        self.stats["sat_grow_time_s"] = self.opt_enc.grow_s + self.joint_enc.grow_s
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
        return self._capped(need, bound)

    def _capped(self, need: int, bound: int) -> tuple[int, bool, str]:
        """``need`` steps, or the cap with the answer marked inexact."""
        if need > self.horizon_cap:
            return (
                self.horizon_cap,
                False,
                f"horizon cap {self.horizon_cap} < {need} steps needed for cost <= {bound}",
            )
        return need, True, ""

    def _opt_horizon(self, sel: frozenset[int], bound: int, at_least: int = 0):
        """:meth:`_horizon` for OPT of one selection: ``floor((bound - extra) / c)`` with the
        selection's own cheapest action cost ``c`` and :func:`extra_cost_bound` (OPT gives no
        cores, so the horizon may depend on the selection)."""
        got = self._opt_extra.get(sel)
        if got is None:
            task = self.task(sel)
            c = min((a.cost for a in task.actions), default=0)
            got = self._opt_extra[sel] = (c, extra_cost_bound(task, c))
        c, extra = got
        if c <= 0 or self.c_min <= 0:
            return self._horizon(bound, at_least)
        need = max((bound - extra) // c, 0)
        return self._capped(need, bound)

    def _tighten_extra(self, sel: frozenset[int]) -> tuple[PlanStep, ...] | None:
        """Replace the LM-cut estimate of :meth:`_opt_horizon` by the exact optimum under the
        lowered costs when an explicit search finds it within ``opt_extra_node_limit``
        expansions (:func:`extra_cost_search`), and return the plan it found.  barman-bar/p3's
        human model: 2 -> 7 in 14,089 expansions, so the proof runs at 23 steps instead of 28.
        Once per selection."""
        self._opt_horizon(sel, 0)  # makes sure the LM-cut estimate is there
        self._opt_extra_searched.add(sel)
        c, extra = self._opt_extra[sel]
        if c <= 0:
            return None
        t0 = time.perf_counter()
        x, plan = extra_cost_search(self.task(sel), c, self.opt_extra_node_limit)
        self._add_seconds("sat_search_time_s", t0)
        self._opt_extra[sel] = (c, max(extra, x))
        self._searches_hit += plan is not None
        self._searches_missed += plan is None
        self._search_steps_saved += max(x - extra, 0) // c
        self.stats["sat_search_hits"] = self._searches_hit
        self.stats["sat_search_misses"] = self._searches_missed
        self.stats["sat_search_steps_saved"] = self._search_steps_saved
        return plan

    def _search_first(self, task: GroundTask, have_plan: bool) -> bool:
        """Whether OPT runs the lowered-cost search (:meth:`_tighten_extra`): only with more
        than one action cost (else the lowered costs are all zero), not once most searches on
        this task have run out of expansions, and, when OPT already has a plan to descend
        from, only while the searches shorten the horizon by two steps each on average.

        Without a plan, the search's plan is the cheap first upper bound.  With one, a search
        only pays if the SAT proof gets shorter: on barman-bar/p3 each hit removes 5 steps
        (28 -> 23); on rover-martian/p3 each removes one, which the step queries of the
        descent make worth little (the cost query after a step bound takes 0.01-0.08 s there).
        ``bench-calls`` on rover-martian/p3, two runs each: 1 call >= 0.5 s and 6.1-7.2 s for
        all calls with "two steps", against 3 and 7.8-8.0 s with "one step"."""
        costs = {a.cost for a in task.actions}
        if len(costs) < 2 or min(costs) <= 0:
            return False
        if self._searches_missed >= 2 and self._searches_missed > self._searches_hit:
            return False
        return (
            not have_plan
            or self._searches_hit < 4
            or self._search_steps_saved >= 2 * self._searches_hit
        )

    def _solve(self, solver: Solver, assumptions: list[int], budget: int | None = None):
        """One SAT call: ``True``/``False``, or ``None`` if ``budget`` conflicts ran out.

        Runs in conflict chunks (``solve_limited(expect_interrupt=True)``) and checks for an
        interrupt or a passed deadline before and between chunks; an interrupted call raises
        :class:`OracleInterrupted` and proves nothing.  Chunk sizes follow a fixed schedule
        (:meth:`_chunk`), cut to the time left before a deadline: CaDiCaL holds the GIL, so the
        deadline timer can only act between chunks, and a fixed 20,000-conflict chunk overran
        ``--timeout`` by 5 s on barman-bar Δ=20 p2.  Chunk sizes do not change the answers.
        """
        self._check_interrupt()
        if budget is not None and budget <= 0:
            return None
        self.stats["sat_solver_calls"] += 1
        left = budget
        index = 0
        while True:
            chunk = self._chunk(solver, index)
            index += 1
            if left is not None:
                chunk = min(chunk, left)
            solver.conf_budget(chunk)
            t0 = time.perf_counter()
            try:
                r = solver.solve_limited(assumptions=assumptions, expect_interrupt=True)
            except Exception as e:
                redeliver_sigint(e)  # pysat's "Caught keyboard interrupt" is a Ctrl-C
                raise
            self._add_seconds("sat_solve_time_s", t0)
            if r is not None:
                return r
            self._rate[id(solver)] = (time.perf_counter() - t0) / chunk
            self._check_interrupt()
            if left is not None:
                left -= chunk
                if left <= 0:
                    return None

    FIRST_CHUNK = 1000

    def _chunk(self, solver: Solver, index: int) -> int:
        """Conflicts for chunk ``index`` (0, 1, ...) of one call on ``solver``:
        ``FIRST_CHUNK * (index + 1)``, at most ``solve_chunk``; the same on every run.  Only
        within reach of a deadline is a chunk cut to the time left, at the solver's measured
        seconds per conflict.

        Chunk boundaries steer CaDiCaL's search (each chunk is a new ``solve`` call).  When
        chunks were sized by the clock to last 0.2 s, the learned clauses, cores and plans, and
        with them the loop's path through the models, differed from run to run: barman-bar/p3
        made 32, 32 and 38 oracle calls in three runs (same frontier).  With this schedule
        it makes 34 every time."""
        size = min(self.solve_chunk, self.FIRST_CHUNK * (index + 1))
        rate = self._rate.get(id(solver))
        left = self._time_left()
        if rate is not None and left is not None:
            size = min(size, int(max(left, 0.01) / max(rate, 1e-9)))
        return max(1, size)

    def _time_left(self) -> float | None:
        """Seconds until the deadline (negative once passed); ``None`` without one."""
        return None if self._deadline is None else self._deadline - time.perf_counter()

    def _add_seconds(self, key: str, t0: float) -> None:
        """Add the seconds since ``t0`` to the timing stat ``key``."""
        self.stats[key] = self.stats.get(key, 0.0) + time.perf_counter() - t0

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
        (2) a first plan: an earlier optimal plan, the lowered-cost search's plan, else SAT
        with a horizon doubling from the step lower bound (cost unbounded); the
        operator-counting bound may prove it optimal at once;
        (3) linear descent: with best simulated cost ``C`` ask for cost ``<= C - 1`` at the
        horizon that makes the answer exact, until UNSAT (or the relaxed lower bound is met);
        step queries first raise the step lower bound to the fewest steps of a known plan,
        which alone proves ``C`` optimal when the horizon is below it.
        """
        sel = frozenset(selection)
        cached = self._opt_cache.get(sel)
        if cached is not None:
            return cached
        t0 = time.perf_counter()
        res = self._opt(sel, t0)
        self._opt_cache[sel] = res
        if res.status == "optimal" and res.plan and res.plan not in self._opt_plans:
            self._opt_plans.append(res.plan)
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
        # an earlier core "no plan of cost <= K" that this selection agrees with
        lits = {(i, i in sel) for i in range(self.family.n_updates)}
        core_lb = max((k + 1 for k, core in self._cost_cores if core <= lits), default=0)
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
        if best is None or best > lb_cost:
            got = self._counting_bound(lits, above=lb_cost)
            if got is not None and got > lb_cost:
                if got == _INF:
                    assert best is None, "operator counting found no plan, but there is one: bug"
                    return done("unsolvable", None, None, True, "operator counting: no plan")
                assert best is None or got <= best, "operator-counting bound above a plan's cost"
                lb_cost, why_lb = int(got), "meets the operator-counting lower bound"
        if (best is None or best > lb_cost) and self._search_first(task, best is not None):
            plan, best = self._cheaper(task, self._tighten_extra(sel), plan, best)
        h = min(max(lb_steps, 1), self.horizon_cap)
        while plan is None:
            calls += 1
            if self._solve(solver, sel_lits + enc.goal_assumptions(h)):
                plan = enc.decode_plan(solver.get_model(), h)
                break
            if h >= self.horizon_cap:
                break
            h = min(2 * h, self.horizon_cap)
        if plan is None:
            return self._opt_fallback(task, calls, t0)
        if best is None:
            plan, best = reduce_plan(task, plan)

        # (3) descend: cost <= best - 1 until UNSAT
        # min_len: no plan of this model has fewer steps (relaxed, then raised by step queries)
        min_len, len_by_sat = lb_steps, False
        shortest = len(plan)  # the fewest steps of a plan known to run in this model
        while True:
            if best <= lb_cost:
                return done("optimal", best, plan, True, why_lb)
            h, exact, reason = self._opt_horizon(sel, best - 1, at_least=len(plan))
            if not exact and self.c_min > 0:
                # the horizon cap (large costs over a small cheapest one): first make the
                # extra cost exact, which may shorten the horizon below the cap; else an
                # explicit search is the proof, and SAT at the cap only the best effort
                if sel not in self._opt_extra_searched:
                    plan, best = self._cheaper(task, self._tighten_extra(sel), plan, best)
                    continue
                got = self._opt_by_search(task, reason)
                if got is not None:
                    return done("optimal", got[1], got[0], True, got[2])
            if exact and h < min_len:
                why = (
                    f"proven by SAT: no plan has fewer than {min_len} steps, and cost "
                    f"<= {best - 1} needs at most {h}"
                    if len_by_sat
                    else "no cheaper plan fits the relaxed step lower bound"
                )
                return done("optimal", best, plan, True, why)
            k = min(shortest - 1, h)
            if self.step_first and exact and min_len <= k:
                # (3a) the step query: a plan of at most k steps, at any cost
                calls += 1
                self.stats["sat_step_queries"] = self.stats.get("sat_step_queries", 0) + 1
                if not self._solve(solver, sel_lits + enc.goal_assumptions(k)):
                    self.stats["sat_step_bounds"] = self.stats.get("sat_step_bounds", 0) + 1
                    min_len, len_by_sat = k + 1, True
                    continue
                found = enc.decode_plan(solver.get_model(), k)
                assert ground_plan_cost(task, found) is not None, "decoded plan invalid"
                plan, best = self._cheaper(task, found, plan, best)
                shortest = min(shortest, len(found), len(plan))
                continue
            goal_lits = enc.goal_assumptions(h)
            cost_lits = enc.cost_assumptions(HUMAN, best - 1, h)
            assert cost_lits is not None
            # no plan has fewer than min_len steps: say so (no-op steps only come last)
            at_least = [enc.act[min_len - 1]] if 0 < min_len <= h and enc.symmetry_breaking else []
            calls += 1
            probe = sel not in self._opt_extra_searched and self._search_first(task, True)
            budget = self.opt_probe_budget if probe else None
            ok = self._solve(solver, sel_lits + goal_lits + at_least + cost_lits, budget)
            if ok is None:
                # a hard query: an exact lower bound on the cost above N * c may shorten it
                plan, best = self._cheaper(task, self._tighten_extra(sel), plan, best)
                continue
            if not ok:
                return done("optimal", best, plan, exact, reason or "proven by SAT")
            plan = enc.decode_plan(solver.get_model(), h)
            cost = ground_plan_cost(task, plan)
            assert cost is not None and cost < best, "decoded plan invalid or not cheaper"
            plan, best = reduce_plan(task, plan)
            shortest = min(shortest, len(plan))

    def _opt_by_search(
        self, task: GroundTask, reason: str
    ) -> tuple[tuple[PlanStep, ...], int, str] | None:
        """``(plan, cost, reason)`` of an optimal plan by explicit-state search (within
        ``fallback_node_limit`` expansions), for OPT when the horizon that would make a SAT
        answer a proof is above the cap; ``None`` if the search gave up.  Once per selection
        (OPT answers are cached)."""
        from mega_sat.search.astar import astar

        left = self._time_left()
        if left is not None and left <= 0:
            raise OracleInterrupted("deadline reached")
        t0 = time.perf_counter()
        r = astar(task, heuristic="blind", node_limit=self.fallback_node_limit, time_limit=left)
        self._add_seconds("sat_search_time_s", t0)
        if r.status == "timeout" and left is not None and self._time_left() <= 0:
            raise OracleInterrupted("deadline reached")  # proves nothing; not cached
        if r.status != "optimal" or ground_plan_cost(task, r.plan) != r.cost:
            return None
        self.stats["sat_opt_by_search"] = self.stats.get("sat_opt_by_search", 0) + 1
        return tuple(r.plan), int(r.cost), reason + "; solved by explicit-state search"

    @staticmethod
    def _cheaper(task: GroundTask, found, plan, best):
        """``(plan, best)``, or ``found`` after action elimination if it is cheaper."""
        if found is None:
            return plan, best
        found, cost = reduce_plan(task, found)
        return (found, cost) if best is None or cost < best else (plan, best)

    def _counting_bound(self, lits: Iterable[GuardLit], above: float) -> float | None:
        """Operator-counting lower bound (:mod:`mega_sat.analysis.operator_counting`) on the cost of
        every plan of every ``human + E'`` agreeing with ``lits`` (their two-fact abstraction),
        cached per partial assignment; ``None`` when unknown or switched off.

        It is switched off for the task after four bounds none of which was above the bound
        the caller already had (``above``): on barman the integer program stays at 10 while
        plans cost 21-31, and each try would only cost time."""
        key = frozenset(lits)
        if key in self._counting:
            return self._counting[key]
        if not self._counting_on():
            return None
        t0 = time.perf_counter()
        sel = frozenset(i for i, v in key if v)
        task = abstract_task(self.family, sel, [i for i, _ in key])
        limit, left = self.counting_time_limit, self._time_left()
        cut = left is not None and left < limit
        if cut:
            limit = max(left, 0.01)
        got = operator_counting_bound(task, time_limit=limit)
        if not (cut and got is None):  # a bound cut short by the deadline may be found later
            self._counting[key] = got
        self._counting_tries += 1
        self._counting_gains += got is not None and got > above
        self.stats["sat_counting_calls"] = self.stats.get("sat_counting_calls", 0) + 1
        self._add_seconds("sat_counting_time_s", t0)
        return got

    def _counting_on(self) -> bool:
        return self.operator_counting and (self._counting_tries < 4 or self._counting_gains > 0)

    def _known_plan(self, task: GroundTask) -> tuple[PlanStep, ...] | None:
        """The cheapest plan of an earlier OPT answer that is valid in ``task`` (an upper
        bound to descend from: neighbouring candidate models often share optimal plans)."""
        best = None
        for plan in self._opt_plans:
            c = ground_plan_cost(task, plan)
            if c is not None and (best is None or c < best[0]):
                best = (c, plan)
        return None if best is None else best[1]

    def _opt_fallback(self, task: GroundTask, calls: int, t0: float) -> OptResult:
        """No plan within the horizon cap: only an exhaustive explicit search can decide."""
        from mega_sat.search.astar import astar

        reason = f"no plan within the horizon cap {self.horizon_cap}"
        left = self._time_left()
        if left is not None and left <= 0:
            raise OracleInterrupted("deadline reached")
        r = astar(task, heuristic="blind", node_limit=self.fallback_node_limit, time_limit=left)
        if r.status == "timeout" and left is not None and self._time_left() <= 0:
            raise OracleInterrupted("deadline reached")  # proves nothing; not cached
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
            cost = ground_plan_cost(task, r.plan)
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
        self,
        selection: Iterable[int],
        robot_bound: int | None,
        human_bound: int,
        *,
        hints: Iterable[Sequence[PlanStep]] = (),
        robot_lower_bound: int | None = None,
        human_lower_bound: int | None = None,
        conflict_budget: int | None = None,
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
        ``unknown`` (nothing proven; ``plan`` is the best witness found so far, if any).
        """
        sel = frozenset(selection)
        lits = [(i, i in sel) for i in range(self.family.n_updates)]
        plan_lb = 0
        if human_lower_bound is not None and self._robot_dominates(sel):
            plan_lb = human_lower_bound
        return self._joint(
            lits,
            robot_bound,
            human_bound,
            sel=sel,
            hints=hints,
            robot_lower_bound=robot_lower_bound,
            plan_lower_bound=plan_lb,
            human_optimum=human_lower_bound,
            conflict_budget=conflict_budget,
        )

    def _joint_by_dominance(
        self,
        lits: list[GuardLit],
        robot_bound: int,
        conflict_budget: int | None,
    ) -> JointResult:
        """JOINT when no action ever costs the robot less than any model of the family and the
        robot bound ``K`` is below the proven optimum of ``human + E``.

        Every joint plan then has human cost <= robot cost <= K, so "no plan of cost <= K in
        ``human + E'``" rules it out; for ``E`` itself that is proven already (``K < c*``), so
        the full assignment is a core and the work is to shrink it to one that generalizes
        (``encodings/joint-and-cores.md``), cheapest argument first:

        1. an earlier core "no plan of cost <= K' (>= K)" that ``E`` agrees with (no solving);
        2. deletion, while operator counting is on for the task: each trial (the core without
           one literal) is settled by a short SAT call on the OPT solver (the human copy alone)
           at the family-wide horizon for cost ``K`` with 300 conflicts, or by operator
           counting on the abstraction of the trial (a lower bound above ``K`` needs no
           horizon, :mod:`mega_sat.analysis.operator_counting`; only if it rules out the full
           assignment, whose abstraction is the finest), whichever has taken less time per
           settled trial on this task so far;
        3. a trial neither settles gets the SAT call with up to ``core_conflict_budget``
           conflicts.  All SAT calls of one JOINT call together spend at most
           ``dominance_conflict_budget`` conflicts (``conflict_budget`` if smaller).
        """
        t0 = time.perf_counter()
        h, exact, reason = self._joint_horizon(None, robot_bound)
        self.stats["sat_joint_by_dominance"] = self.stats.get("sat_joint_by_dominance", 0) + 1

        def done(core: frozenset[GuardLit], why: str, calls: int) -> JointResult:
            return JointResult(
                "infeasible", None, None, None, core, None, True, why, h, calls,
                self._finish("joint", t0),
            )  # fmt: skip

        given = set(lits)
        for bound, core in self._cost_cores:
            # "no plan of cost <= bound" for every selection agreeing with core: also <= K
            if bound >= robot_bound and core <= given:
                self.stats["sat_joint_core_reused"] = self.stats.get("sat_joint_core_reused", 0) + 1
                return done(
                    core, "robot costs dominate: an earlier core rules out every human plan "
                    "this cheap", 0,
                )  # fmt: skip
        enc = self.opt_enc
        # SAT trials need the horizon to be a proof; past the cap only counting trials run,
        # and the encoding is not grown to the cap for nothing
        base = []
        if exact:
            base = enc.cost_assumptions(HUMAN, robot_bound, h) + enc.goal_assumptions(h)
        left = self.dominance_conflict_budget
        if conflict_budget is not None:
            left = min(left, conflict_budget)
        core, calls, i = list(lits), 0, 0
        counting: bool | None = None if self.operator_counting else False
        # a one-literal core is kept as is (as in _minimize_core)
        while len(core) > 1 and i < len(core) and calls < self.core_calls:
            trial = core[:i] + core[i + 1 :]
            verdict, smaller = None, trial
            if counting is not False and not self._counting_on():
                counting = False
            ways = (
                sorted(("sat", "counting"), key=self._trial_cost) if counting is not False else []
            )
            for way in ways:
                started = time.perf_counter()
                if way == "sat" and exact and left > 0:  # short: small tasks settle it at once
                    verdict, smaller, spent = self._dominance_trial(base, trial, min(300, left))
                    left, calls = left - spent, calls + 1
                elif way == "counting":
                    if counting is None:  # a trial's abstraction is coarser: no better bound
                        got = self._counting_bound(lits, above=robot_bound)
                        counting = got is not None and got > robot_bound
                        if not counting:
                            continue
                    got = self._counting_bound(trial, above=robot_bound)
                    if got is not None and got > robot_bound:
                        verdict, smaller = False, trial
                else:
                    continue
                self._trial_stats[way][0] += time.perf_counter() - started
                self._trial_stats[way][1] += verdict is not None
                if verdict is not None:
                    break
            if verdict is None and exact and left > 0:
                budget = min(self.core_conflict_budget, left)
                verdict, smaller, spent = self._dominance_trial(base, trial, budget)
                left, calls = left - spent, calls + 1
            if verdict is False:  # no plan within K in any model agreeing with the trial
                core = smaller
            else:
                i += 1
        self.stats["sat_core_min_calls"] += calls
        why = "robot costs dominate: the robot bound is below the proven human optimum"
        if len(core) < len(lits):
            why = "robot costs dominate: no human plan within the robot bound"
        self._cost_cores.append((robot_bound, frozenset(core)))
        return done(frozenset(core), why, calls)

    def _trial_cost(self, way: str) -> float:
        """Seconds per settled deletion trial so far (0 before the first try, so each way is
        tried once): usar-fetch settles a trial by a short SAT call in about a millisecond,
        rover-martian by operator counting in about 15 ms after 50-100 ms of SAT."""
        spent, settled = self._trial_stats[way]
        return spent / max(settled, 1)

    def _dominance_trial(
        self, base: list[int], trial: list[GuardLit], budget: int
    ) -> tuple[bool | None, list[GuardLit], int]:
        """One deletion trial of :meth:`_joint_by_dominance` on the OPT solver: ``False`` with
        the literals of the solver's core if no plan of cost ``<= K`` fits the family-wide
        horizon under ``trial``, ``True`` if one does, ``None`` if ``budget`` conflicts ran
        out; and the conflicts spent."""
        enc, solver = self.opt_enc, self._opt_solver
        before = solver.accum_stats().get("conflicts", 0)
        r = self._solve(solver, base + enc.lits_assumptions(trial), budget=budget)
        spent = max(solver.accum_stats().get("conflicts", 0) - before, 1)
        if r is False:
            got = set(solver.get_core() or [])
            return False, [g for g in trial if enc.guard_lit(g) in got], spent
        return r, trial, spent

    @cached_property
    def _always_dominates(self) -> bool:
        """No action the robot model has costs the robot less than in any model of the family
        (then robot cost >= human cost for every joint plan and every selection)."""
        robot = self.family.robot_selection
        for a in self.family.actions:
            if not holds(a.exists, robot):
                continue
            rc = a.cost_in(robot)
            if any(v > rc for _, v in a.cost):
                return False
        return True

    def joint_lits(
        self,
        lits: Iterable[GuardLit],
        robot_bound: int | None,
        human_bound: int,
        *,
        robot_lower_bound: int | None = None,
    ) -> JointResult:
        """``JOINT`` under a *partial* assignment of selectors (unassigned ones are free).

        ``joint`` calls it with the full assignment; tests use it to check that a core alone is
        infeasible.
        """
        return self._joint(lits, robot_bound, human_bound, robot_lower_bound=robot_lower_bound)

    def _joint_horizon(self, robot_bound: int | None, human_bound: int) -> tuple[int, bool, str]:
        """Steps that every joint plan within the bounds fits in: ``min`` over the copies of
        ``floor(bound / c_min of that copy)`` (robot copy: the robot model's cheapest action;
        human copy: the family's, valid for every selection), capped."""
        need = []
        if robot_bound is not None and self.c_min_robot > 0:
            need.append((robot_bound - self.extra_robot) // self.c_min_robot)
        if self.c_min > 0:
            need.append((human_bound - self.extra_human) // self.c_min)
        if not need:
            bmin = human_bound if robot_bound is None else min(robot_bound, human_bound)
            return self._horizon(bmin, at_least=self._zero_cost_horizon)
        h = max(min(need), 0)
        if h > self.horizon_cap:
            return (
                self.horizon_cap,
                False,
                f"horizon cap {self.horizon_cap} < {h} steps needed for the joint bounds",
            )
        return h, True, ""

    def _joint(
        self,
        lits: Iterable[GuardLit],
        robot_bound: int | None,
        human_bound: int,
        *,
        sel: frozenset[int] | None = None,
        hints: Iterable[Sequence[PlanStep]] = (),
        robot_lower_bound: int | None = None,
        plan_lower_bound: int = 0,
        human_optimum: int | None = None,
        conflict_budget: int | None = None,
    ) -> JointResult:
        lits = list(dict.fromkeys(lits))
        if (
            robot_bound is not None
            and human_optimum is not None
            and max(self._robot_lower_bound(), robot_lower_bound or 0)
            <= robot_bound
            < human_optimum
            and self._always_dominates
        ):
            return self._joint_by_dominance(lits, robot_bound, conflict_budget)
        t0 = time.perf_counter()
        enc, solver = self.joint_enc, self._joint_solver
        calls = 0
        h, exact, reason = self._joint_horizon(robot_bound, human_bound)
        rlb = max(self._robot_lower_bound(), robot_lower_bound or 0)
        lb = max(rlb, plan_lower_bound)

        def done(status, plan=None, rc=None, hc=None, core=None, sel=None, why="") -> JointResult:
            return JointResult(
                status,
                plan,
                rc,
                hc,
                core,
                sel,
                (exact or bool(why)) and status != "unknown",
                why or reason or "proven by SAT",
                h,
                calls,
                self._finish("joint", t0),
            )

        if human_bound < 0 or (robot_bound is not None and robot_bound < 0):
            h = 0
            return done("infeasible", core=frozenset(), why="negative bound")
        if robot_bound is not None and robot_bound < rlb:
            return done(
                "infeasible",
                core=frozenset(),
                why=f"robot cost bound {robot_bound} < robot lower bound {rlb}",
            )
        if not exact and self.c_min > 0 and sel is not None:
            return self._joint_by_search(sel, robot_bound, human_bound, reason, t0)
        sel_lits = enc.lits_assumptions(lits)
        robot_task = self.task(self.family.robot_selection)
        best = None if sel is None else self._best_hint(hints, sel, robot_bound, human_bound, h)
        if best is None:
            base = (
                enc.cost_assumptions(HUMAN, human_bound, h)
                + enc.cost_assumptions(ROBOT, robot_bound, h)
                + enc.goal_assumptions(h)
            )
            calls += 1
            ok = self._solve(solver, base + sel_lits, budget=conflict_budget)
            if ok is None:
                return done("unknown", why=f"conflict budget {conflict_budget} ran out")
            if not ok:
                core = self._minimize_core(base, sel_lits, solver.get_core() or [])
                calls += self._last_core_calls
                return done("infeasible", core=core)
            plan, rc, hc, sel = self._decode_joint(solver.get_model(), h, robot_task)
        else:
            plan, rc, hc = best
            self.stats["sat_joint_hint_used"] = self.stats.get("sat_joint_hint_used", 0) + 1
        assert hc <= human_bound and (robot_bound is None or rc <= robot_bound)
        while True:
            if rc <= lb:
                why = (
                    "meets the robot lower bound"
                    if rc <= rlb
                    else "meets the human lower bound (robot costs dominate)"
                )
                return done("plan", plan, rc, hc, sel=sel, why=why)
            # robot cost <= rc - 1 also bounds the plan length; the horizon may shrink
            h2 = min(self._joint_horizon(rc - 1, human_bound)[0], h)
            calls += 1
            ok = self._solve(
                solver,
                enc.cost_assumptions(HUMAN, human_bound, h2)
                + enc.cost_assumptions(ROBOT, rc - 1, h2)
                + enc.goal_assumptions(h2)
                + sel_lits,
                budget=conflict_budget,
            )
            if ok is None:
                return done(
                    "unknown",
                    plan,
                    rc,
                    hc,
                    sel=sel,
                    why=f"conflict budget {conflict_budget} ran out",
                )
            if not ok:
                return done("plan", plan, rc, hc, sel=sel)
            h = h2
            plan, rc, hc, sel = self._decode_joint(solver.get_model(), h, robot_task)
            assert robot_bound is None or rc <= robot_bound

    def _joint_by_search(
        self,
        sel: frozenset[int],
        robot_bound: int | None,
        human_bound: int,
        reason: str,
        t0: float,
    ) -> JointResult:
        """JOINT by the explicit paired-state search (:func:`mega_sat.search.joint.search_joint`,
        cores proven on abstractions) when the horizon that would make SAT exact is above the
        cap: with large costs over a small cheapest one, ``floor(c / c_min)`` steps can be any
        number, while the search's work does not grow with the cost values."""
        from dataclasses import replace

        from mega_sat.search.joint import JointSearcher, search_joint

        self._check_interrupt()
        if self._searcher is None:
            self._searcher = JointSearcher(self.task(self.family.robot_selection))
        r = search_joint(
            self._searcher, self.family, sel, robot_bound, human_bound, deadline=self._deadline
        )
        if r is None:
            raise OracleInterrupted("deadline reached")  # proves nothing
        self.stats["sat_joint_by_search"] = self.stats.get("sat_joint_by_search", 0) + 1
        return replace(r, reason=f"{reason}; {r.reason}", time_s=self._finish("joint", t0))

    def _decode_joint(self, model, h: int, robot_task: GroundTask):
        enc = self.joint_enc
        sel = enc.decode_selection(model)
        plan = enc.decode_plan(model, h)
        rc = ground_plan_cost(robot_task, plan)
        hc = ground_plan_cost(self.task(sel), plan)
        assert rc is not None and hc is not None, "decoded joint plan invalid: encoding bug"
        return plan, rc, hc, sel

    def _best_hint(self, hints, sel, robot_bound, human_bound, h):
        """The hint plan of least robot cost that is a JOINT witness, or ``None``."""
        best = None
        robot_task, task = self.task(self.family.robot_selection), self.task(sel)
        for raw in hints:
            if raw is None:
                continue
            plan = tuple(tuple(str(x).lower() for x in step) for step in raw)
            if len(plan) > h:
                continue  # only possible with an inexact horizon; keep answers within it
            rc = ground_plan_cost(robot_task, plan)
            if rc is None or (robot_bound is not None and rc > robot_bound):
                continue
            hc = ground_plan_cost(task, plan)
            if hc is None or hc > human_bound:
                continue
            if best is None or rc < best[1]:
                best = (plan, rc, hc)
        return best

    def _robot_dominates(self, sel: frozenset[int]) -> bool:
        """Whether no action usable by a joint plan costs less in the robot model than in
        ``human + sel`` (then robot cost >= human cost for every joint plan)."""
        r = self._dominance.get(sel)
        if r is None:
            robot, task = self.task(self.family.robot_selection), self.task(sel)
            hc = {a.index: a.cost for a in task.actions}
            r = all(a.cost >= hc[a.index] for a in robot.actions if a.index in hc)
            self._dominance[sel] = r
        return r

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
        self,
        base: list[int],
        sel_lits: list[int],
        raw_core: Iterable[int],
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
        # a one-literal core is kept as is: the empty core (no selection at all) is rare and
        # mostly caught by the robot lower bound before any SAT call
        while len(core) > 1 and i < len(core) and self._last_core_calls < self.core_calls:
            trial = core[:i] + core[i + 1 :]
            self._last_core_calls += 1
            self.stats["sat_core_min_calls"] += 1
            if self._solve(solver, base + trial, budget=self.core_conflict_budget) is False:
                got = set(solver.get_core() or [])
                core = [lit for lit in trial if lit in got]
            else:
                i += 1
        return frozenset((abs(lit) - 1, lit > 0) for lit in core)
