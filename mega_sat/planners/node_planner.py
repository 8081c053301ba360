"""One optimal planning call on one model of the family, by a chosen planner.

The A* baseline calls this at every node of its model-space search, MCE and verification use it
too.  Three planners answer the same question (optimal cost and one optimal plan of
``human + E``):

* ``builtin`` — explicit-state search on the ground task: uniform-cost, then A* with LM-cut
  (:func:`mega_sat.search.astar.solve_optimal`);
* ``sat``     — the OPT oracle of the SAT encoding (:mod:`mega_sat.sat.oracles`);
* ``fd``      — Fast Downward ``astar(lmcut())`` on PDDL files of the model, the paper's set-up;
* ``portfolio`` — explicit search (uniform-cost and A* with LM-cut by turns, in a forked
  process) and ``sat`` at once, refereed by work (search work against solver conflicts), so
  every run gives the same answer; the answer's ``planner`` says which method gave it
  (``builtin`` for either search, its ``reason`` which one).  Past the SAT horizon cap only
  the explicit search can decide, and it runs on alone: it is complete (it exhausts the finite
  state space of an unsolvable model), so every model gets decided, given time.  With
  Fast Downward installed, a forked race still open after ``Options.race_fd_after_work`` units
  of SAT work (a point no race of the paper grid reaches), with a plan of the model in hand
  (SAT's, or a greedy search's), is handed to ``fd``.
"""

from __future__ import annotations

import os
import time
from dataclasses import replace

from mega_sat.deadline import NO_DEADLINE, Deadline, TimeLimitReached
from mega_sat.errors import PlannerError, UsageError
from mega_sat.ground.family import GroundFamily, GroundTask
from mega_sat.model.lifted import PlanStep
from mega_sat.model.task import TwoModelTask
from mega_sat.options import DEFAULT, Options
from mega_sat.search.astar import PlanResult, within
from mega_sat.status import Status

PLANNERS = ("builtin", "sat", "fd", "portfolio")


def sat_solver_names() -> tuple[str, ...]:
    """The SAT solvers python-sat offers by name (``cadical195``, ``glucose4``, ...)."""
    from pysat.solvers import SolverNames

    return tuple(
        sorted(n for names in vars(SolverNames).values() if isinstance(names, tuple) for n in names)
    )


NodePlan = PlanResult
"""The earlier name of a planner call's answer, kept for code that imports it."""


def checked_run_arguments(
    planner: str | None,
    solver: str,
    options: Options | None,
    timeout: float | None,
    deadline: Deadline | None,
) -> tuple[Deadline, Options]:
    """The arguments every solver front end shares, checked: the planner and SAT solver names,
    the options object and one time limit (``timeout`` or ``deadline``, not both)."""
    if planner is not None and planner not in PLANNERS:
        raise UsageError(f"unknown planner {planner!r} (choose from {', '.join(PLANNERS)})")
    if not isinstance(solver, str) or solver not in sat_solver_names():
        raise UsageError(
            f"unknown SAT solver {solver!r} (choose from {', '.join(sat_solver_names())})"
        )
    if options is None:
        options = DEFAULT
    elif not isinstance(options, Options):
        raise UsageError(
            f"options must be a mega_sat.options.Options, got {type(options).__name__}"
        )
    if deadline is None:
        deadline = Deadline.after(timeout)
    elif timeout is not None:
        raise UsageError("give either timeout or deadline, not both")
    elif not isinstance(deadline, Deadline):
        raise UsageError(
            f"deadline must be a mega_sat.deadline.Deadline (or give timeout= seconds), got "
            f"{deadline!r}"
        )
    return deadline, options


class NodePlanner:
    """Answers ``optimal(selection)`` for one task with one planner; keeps what it can alive
    (the SAT oracles, the ground family) across calls.

    Every call runs within ``deadline``, the run's one time limit, and within ``time_limit``
    seconds of its own when given (a limit per call, for measuring one call); a call that the
    deadline cuts short raises :class:`TimeLimitReached` (it proved nothing), one that runs out
    of its own ``time_limit`` answers ``TIMEOUT`` and one that runs out of a budget (the SAT
    horizon cap) ``LIMIT``.  ``options``: the tuning knobs
    (``blind_nodes`` of the built-in planner).
    """

    def __init__(
        self,
        task: TwoModelTask,
        family: GroundFamily,
        kind: str = "builtin",
        *,
        time_limit: float | None = None,
        oracles=None,
        solver: str = "cadical195",
        deadline: Deadline | None = None,
        options: Options = DEFAULT,
    ):
        if kind not in PLANNERS:
            raise UsageError(f"unknown planner {kind!r} (choose from {', '.join(PLANNERS)})")
        if kind == "fd":
            from mega_sat.planners.fast_downward import family_cost_problem, fd_available

            if not fd_available():
                raise UsageError("planner 'fd' needs Fast Downward: pip install 'mega-sat[fd]'")
            problem = family_cost_problem(family)
            if problem is not None:
                raise UsageError(f"planner 'fd': {problem}; use --planner builtin or sat")
        self.task, self.family, self.kind = task, family, kind
        self.time_limit = time_limit
        self.deadline = deadline if deadline is not None else NO_DEADLINE
        self.options = options
        self._oracles = oracles
        self._solver = solver
        self.calls = 0
        self.time_s = 0.0
        # portfolio: the method to try first (the last winner) and its first turn's seconds
        self._first = "builtin"
        self._has_fd: bool | None = None  # Fast Downward installed (looked up once)
        # FD runs started by prepare() ahead of their optimal() calls: selection -> (run, names)
        self._pending: dict[frozenset[int], tuple] = {}

    @property
    def oracles(self):
        if self._oracles is None:
            from mega_sat.sat.oracles import SatOracles

            self._oracles = SatOracles(self.family, solver=self._solver, options=self.options)
            if self.deadline.limited:
                self._oracles.deadline = self.deadline
        return self._oracles

    def optimal(self, selection: frozenset[int]) -> PlanResult:
        from mega_sat.sat.oracles import OracleInterrupted

        t0 = time.perf_counter()
        self.calls += 1
        self.deadline.check()
        try:
            r = self._optimal(frozenset(selection), t0)
        except OracleInterrupted:
            if self.deadline.expired():
                raise TimeLimitReached(self.deadline.seconds) from None
            raise
        finally:
            self.time_s += time.perf_counter() - t0
        if not r.status.decided and self.deadline.expired():
            raise TimeLimitReached(self.deadline.seconds)  # cut short: nothing proven
        return r

    def _optimal(self, sel: frozenset[int], t0: float) -> PlanResult:
        call = within(self.deadline, self.time_limit)
        task = self.family.specialize(sel)

        def answer(status: Status, plan=None, cost=None, exact=None, reason="") -> PlanResult:
            exact = status.decided if exact is None else exact
            elapsed = time.perf_counter() - t0
            return PlanResult(status, plan, cost, exact, self.kind, elapsed, reason)

        if task.goal <= task.init:
            # the empty plan is optimal (costs are >= 0); some planners refuse such tasks
            return answer(Status.OPTIMAL, (), 0)
        if self.kind == "builtin":
            from mega_sat.search.astar import solve_optimal

            fd = self.options.builtin_fd_after_blind and self._fd_installed()
            r = solve_optimal(
                task,
                deadline=call,
                blind_nodes=self.options.blind_nodes,
                hand_over=(lambda limit: self._fd_or_none(sel, task, limit)) if fd else None,
            )
            return answer(r.status, r.plan, r.cost, reason=r.reason)
        if self.kind == "sat":
            r = self.oracles.opt(sel)
            return answer(r.status, r.plan, r.cost, r.exact, r.reason)
        if self.kind == "portfolio":
            if self.options.race_processes and hasattr(os, "fork"):
                return self._race_forked(sel, task, call, t0)
            return self._race(sel, task, call, t0)
        r = self._fd(sel, task, call)
        return answer(r.status, r.plan, r.cost, reason=r.reason)

    def prepare(self, selection: frozenset[int]) -> None:
        """Start Fast Downward on ``human + selection`` now, for an :meth:`optimal` call that
        may follow (OPT's quick search runs meanwhile on this core); :meth:`discard` ends it
        when the call is not needed.  The answer is the one :meth:`optimal` gives without it.
        Only the ``fd`` planner starts anything."""
        sel = frozenset(selection)
        if self.kind != "fd" or sel in self._pending:
            return
        t0 = time.perf_counter()
        try:
            task = self.family.specialize(sel)
            if task.goal <= task.init:
                return
            call = within(self.deadline, self.time_limit)
            self._pending[sel] = self._fd_start(sel, task, call)
        finally:
            self.time_s += time.perf_counter() - t0

    def discard(self, selection: frozenset[int] | None = None) -> None:
        """End the run :meth:`prepare` started for ``selection`` (``None``: every one)."""
        if selection is None:
            runs = list(self._pending.values())
            self._pending.clear()
        else:
            got = self._pending.pop(frozenset(selection), None)
            runs = [] if got is None else [got]
        for run, _ in runs:
            run.cancel()

    def _fd_start(self, sel: frozenset[int], task: GroundTask, call: Deadline):
        """``(run, names)``: Fast Downward started on ``human + sel`` (``task``), on the lifted
        model when it has no negative preconditions (``names`` None), else on the ground model
        with those compiled away (``names``: its action names to the family's steps)."""
        from mega_sat.pddl.writer import domain_to_pddl, problem_to_pddl
        from mega_sat.planners.fast_downward import FdRun

        # a planner made for a ground family alone (no lifted task) hands FD the ground model
        model = self.task.updated_model(sel) if self.task is not None else None
        if model is not None and not any(s.negpre for s in model.schemas.values()):
            return FdRun(
                domain_to_pddl(model, plain_variables=True), problem_to_pddl(model), deadline=call
            ), None
        dom, prob, names = ground_strips_pddl(task)
        return FdRun(dom, prob, deadline=call), names

    def _fd(self, sel: frozenset[int], task: GroundTask, call: Deadline) -> PlanResult:
        """Fast Downward's optimum of ``human + sel`` (``task``), its plan in the family's
        steps (from the run :meth:`prepare` started, if it is for ``sel``); raises
        :class:`PlannerError` when FD fails."""
        from mega_sat.planners.fast_downward import fd_plan

        pending = self._pending.pop(sel, None)
        run, names = pending if pending is not None else self._fd_start(sel, task, call)
        try:
            r = run.result()
        except PlannerError as e:
            if names is not None or "exit code 34" not in str(e):
                raise
            # FD compiles negative preconditions (and some add/delete overlaps) into axioms or
            # conditional effects, which LM-cut rejects: hand it the ground model with those
            # compiled away instead (same plans, same costs)
            dom, prob, names = ground_strips_pddl(task)
            r = fd_plan(dom, prob, deadline=call)
        if names is not None:
            if r.status == Status.OPTIMAL and r.plan is not None:
                return replace(r, plan=tuple(names[s[0]] for s in r.plan))
            return r
        if r.status == Status.OPTIMAL and r.plan is not None:
            # FD may print names in another case or order; map back onto the family's steps
            plan = tuple(tuple(x.lower() for x in s) for s in r.plan)
            missing = [s for s in plan if s not in self.family.action_index]
            if missing:
                raise PlannerError(
                    f"Fast Downward returned an action outside the ground family: "
                    f"({' '.join(missing[0])})"
                )
            return replace(r, plan=plan)
        return r

    def _race_forked(
        self, sel: frozenset[int], task: GroundTask, call: Deadline, t0: float
    ) -> PlanResult:
        """The portfolio on both cores: the explicit searches of :func:`explicit_steps` in a
        forked child while the SAT OPT oracle runs here, refereed by work, not by the clock,
        so that every run gives the same answer (and the same plan).

        Work is the child's (expansions, LM-cut evaluations weighted) and the oracle's solver
        conflicts plus the clauses its encoding grew by (``race_clauses_per_conflict``
        clauses count as one conflict), converted at ``race_nodes_per_conflict``, plus the
        oracle's own search and integer-program work (``Solving.side_work``).  The search wins when it ends
        with fewer states than that many times the work SAT has spent (checked between
        solver chunks, whose schedule is fixed); SAT wins when it ends first by that
        measure.  Where one side is
        ahead in work and behind on the clock, the referee waits for the other to catch up,
        which costs wall time, never the answer.  Past the horizon cap SAT drops out and the
        search runs on until ``call``.

        With ``race_fd_after_work`` set and Fast Downward installed, a race in which neither
        side is done once SAT's side has spent that much (in the referee's units), while a
        plan of the model is in hand (SAT's, or one the greedy search of
        :mod:`mega_sat.search.greedy` finds), stops there and FD answers the call: its LM-cut
        search in C++ proves optima that take SAT minutes and the child's pure-Python LM-cut
        hours.  Both the stopping point and FD's answer follow from work, not the clock, so
        runs still repeat.  FD's plans lead the loop other ways, which can cost as much as
        they save, hence a default point past every race of the paper grid and of most
        larger tasks: only a proof that dwarfs the rest is handed over (bench/README.md)."""
        from mega_sat.sat.oracles import OracleInterrupted

        opts = self.options
        rate, per_clause = opts.race_nodes_per_conflict, 1 / opts.race_clauses_per_conflict
        orc = self.oracles
        solving, enc = orc.solving, orc.opt_enc
        start, clauses, side = solving.conflicts(), enc.n_clauses, solving.side_work
        if start is None:  # a solver that does not count conflicts: no referee possible
            return self._race(sel, task, call, t0)
        child = ForkedSearch(*explicit_side(task, opts))
        fd_after = (
            opts.race_fd_after_work if opts.race_fd_after_work and self._fd_installed() else 0
        )
        to_fd: list[float] = []  # SAT's work when the race handed the call to FD

        def sat_work() -> float:
            spent = solving.conflicts() - start + (enc.n_clauses - clauses) * per_clause
            return rate * spent + solving.side_work - side

        def search_wins() -> bool:
            limit = sat_work()
            done, n = child.progress(limit, call)
            return done and n < limit

        def held():
            """The plan of this model SAT holds and its cost, if any."""
            reached = orc.opt_oracle.descent
            return reached[1:] if reached is not None and reached[0] == sel else None

        greedy: list[bool] = []  # whether the greedy search found a plan (asked once)

        def solvable() -> bool:
            """The model has a plan: SAT holds one, or the greedy search finds one within
            ``race_fd_greedy_evaluations`` (deterministic, so the hand-over is too).  Only
            then does FD get the call (proving an optimum is its strength): an unsolvable
            model stays with SAT's side proofs, which FD's search, exhausting every state
            with LM-cut, does not match (blocksworld Δ30 p2: 10 and 38 s)."""
            if held() is not None:
                return True
            if not greedy:
                from mega_sat.search.greedy import greedy_plan

                budget = opts.race_fd_greedy_evaluations
                greedy.append(budget > 0 and greedy_plan(task, budget, call) is not None)
            return greedy[0]

        def stop_sat() -> bool:
            if search_wins():
                return True
            if fd_after and (work := sat_work()) >= fd_after and solvable():
                to_fd.append(work)
                return True
            return False

        try:
            solving.stop_probe = stop_sat
            r = None
            try:
                r = orc.opt(sel)
            except OracleInterrupted:
                if call.expired():
                    raise
            finally:
                solving.stop_probe = None
            # "no plan" is the same answer whoever proves it: no need to wait for the search
            # to catch up in work and see whether it would have said so first
            if (
                r is not None
                and r.status.decided
                and (r.status == Status.UNSOLVABLE or not search_wins())
            ):
                self._first = "sat"
                return PlanResult(
                    r.status, r.plan, r.cost, r.exact, "sat", time.perf_counter() - t0, r.reason
                )
            if to_fd:
                try:
                    fd = self._fd(sel, task, call)
                except PlannerError:
                    fd = None  # FD failed on this model: the search answers, as without FD
                if fd is not None and fd.status.decided:
                    why = f"Fast Downward, after {to_fd[0]:.0f} units of the race"
                    plan, kept = fd.plan, held()
                    if kept is not None and kept[1] == fd.cost:
                        # SAT already holds an optimal plan and lacked only the proof: keep
                        # its plan, the one SAT's own answer would carry
                        plan, why = kept[0], why + " (proof), SAT's plan"
                    elapsed = time.perf_counter() - t0
                    return PlanResult(fd.status, plan, fd.cost, True, "fd", elapsed, why)
            got = child.result(call.remaining())
            if got is None:  # the search died (memory) or ran out of time
                if call.expired():
                    return PlanResult(Status.TIMEOUT, None, None, False, "builtin", 0.0)
                if r is not None:
                    return PlanResult(r.status, None, None, False, "sat", 0.0, r.reason)
                return self._race(sel, task, call, t0)
            status, plan, cost, method = got
            self._first = "builtin"
            elapsed = time.perf_counter() - t0
            return PlanResult(status, plan, cost, True, "builtin", elapsed, method)
        finally:
            child.stop()

    def _fd_or_none(self, sel: frozenset[int], task: GroundTask, call: Deadline):
        """Fast Downward's A* with LM-cut on a call the built-in blind search did not settle
        (``Options.builtin_fd_after_blind``): the optimum the built-in LM-cut would find,
        without paying for LM-cut in pure Python per state.  ``None`` when FD fails: the
        built-in LM-cut answers instead."""
        try:
            return self._fd(sel, task, call)
        except PlannerError:
            return None

    def _fd_installed(self) -> bool:
        if self._has_fd is None:
            from mega_sat.planners.fast_downward import family_cost_problem, fd_available

            self._has_fd = fd_available() and family_cost_problem(self.family) is None
        return self._has_fd

    def _race(self, sel: frozenset[int], task: GroundTask, call: Deadline, t0: float) -> PlanResult:
        """The portfolio in one process: the explicit searches and the SAT OPT oracle in turns
        of fixed work, doubling each round (search: ``race_nodes_per_conflict`` states per
        conflict of the SAT turn), until one decides.  The search is paused and resumed;
        SAT OPT restarts, its solver keeping what it learned.  SAT past its horizon cap drops
        out and the search runs on until ``call``.  The method that answered the last call
        goes first.  Turns are counted in work, not seconds, so every run answers alike."""
        from mega_sat.sat.oracles import OracleInterrupted

        search = explicit_steps(*explicit_side(task, self.options))
        methods = [self._first] + [m for m in ("builtin", "sat") if m != self._first]
        conflicts = self.options.race_first_conflicts
        why = "time limit"
        while True:
            for m in list(methods):
                alone = len(methods) == 1
                r = None
                if m == "builtin":
                    nodes = None if alone else self.options.race_nodes_per_conflict * conflicts
                    try:
                        while True:
                            n = next(search)
                            if (nodes is not None and n >= nodes) or call.expired():
                                break
                    except StopIteration as done:
                        status, plan, cost, _, method = done.value
                        r = PlanResult(status, plan, cost, True, m, 0.0, method)
                else:
                    solving = self.oracles.solving
                    solving.stop_probe = None if alone else _spent(solving, conflicts)
                    try:
                        r = self.oracles.opt(sel)
                    except OracleInterrupted:
                        if call.expired():
                            raise
                    finally:
                        solving.stop_probe = None
                    if r is not None and not r.status.decided:
                        methods.remove(m)  # past the horizon cap: only the search decides
                        why, r = r.reason, None
                if r is not None and r.status.decided:
                    self._first = m
                    elapsed = time.perf_counter() - t0
                    return PlanResult(r.status, r.plan, r.cost, r.exact, m, elapsed, r.reason)
                if call.expired():
                    return PlanResult(Status.TIMEOUT, None, None, False, m, 0.0, why)
            conflicts *= 2


def _spent(solving, allowed: int):
    """A stop probe: true once the solvers have spent ``allowed`` conflicts from now."""
    start = solving.conflicts() or 0
    return lambda: (solving.conflicts() or 0) - start >= allowed


def explicit_side(task: GroundTask, options: Options) -> tuple[GroundTask, float, float]:
    """What the race's explicit side searches for the model ``task`` and how its work
    counts: the task itself, or its relevant part with ``Options.race_search_relevant_part``
    (:func:`mega_sat.ground.relevance.relevant_part`: the same optimum, plans that run
    unchanged in ``task``, and often far fewer states, since atoms no goal or condition reads
    no longer tell states apart); the weight of an LM-cut evaluation (from ``task``); and the
    weight of a vectorised expansion (:func:`vector_weight`, from the task searched)."""
    searched = task
    if options.race_search_relevant_part:
        from mega_sat.ground.relevance import relevant_part

        searched = relevant_part(task)
    return searched, lmcut_weight(task, options), vector_weight(searched, options)


def explicit_steps(task: GroundTask, lmcut_weight: float, vector_weight: float = 1.0):
    """The portfolio's explicit side on ``task``: uniform-cost search and A* with LM-cut by
    turns (:func:`mega_sat.search.astar.blind_and_lmcut_steps`); a generator of work done,
    returning ``(status, plan, cost, work, method)``."""
    from mega_sat.search.astar import blind_and_lmcut_steps

    init = sum(1 << p for p in task.init)
    goal = sum(1 << p for p in task.goal)
    return blind_and_lmcut_steps(task, init, goal, lmcut_weight, vector_weight=vector_weight)


def vector_weight(task: GroundTask, options: Options) -> float:
    """The work of one vectorised uniform-cost expansion of ``task`` on the explicit side: its
    numpy passes test every action against every word of the state, so their time grows with
    actions times words (``Options.race_search_vector_work``; 1 when that is 0)."""
    per_test = options.race_search_vector_work
    if per_test <= 0:
        return 1.0
    # numpy's import is paid only by runs that set the option
    from mega_sat.search.vector_search import mutable_atoms, state_words

    words = state_words(len(mutable_atoms(task)))
    return min(1.0, per_test * len(task.actions) * words)


def lmcut_weight(task: GroundTask, options: Options) -> float:
    """The work of one LM-cut evaluation in uniform-cost expansions: it grows with the
    number of actions the relaxation walks (``Options.race_lmcut_per_action``)."""
    return max(1.0, options.race_lmcut_per_action * len(task.actions))


class ForkedSearch:
    """The explicit searches of :func:`explicit_steps` in a forked child process.  Their
    progress (work done; negative once done) is one shared 8-byte counter, the answer
    ``(status, plan, cost, method)`` comes back pickled through a pipe.  The child ignores
    Ctrl-C (the parent stops it) and leaves by ``os._exit``, so it never flushes the parent's
    buffered output."""

    def __init__(self, task: GroundTask, lmcut_weight: float, vector_weight: float = 1.0):
        import mmap
        import warnings

        self._counter = mmap.mmap(-1, 8)  # shared with the child (MAP_SHARED)
        self._read, write = os.pipe()
        with warnings.catch_warnings():
            # the child runs pure Python and touches no lock another thread may hold
            warnings.simplefilter("ignore", DeprecationWarning)
            self.pid = os.fork()
        if self.pid == 0:  # pragma: no cover - the child; its work is checked through the parent
            code = 1
            try:
                import pickle
                import signal
                import struct

                signal.signal(signal.SIGINT, signal.SIG_IGN)
                os.close(self._read)
                steps = explicit_steps(task, lmcut_weight, vector_weight)
                try:
                    while True:
                        struct.pack_into("<q", self._counter, 0, int(next(steps)))
                except StopIteration as done:
                    status, plan, cost, work, method = done.value
                view = memoryview(pickle.dumps((status, plan, cost, method)))
                while view:
                    view = view[os.write(write, view) :]
                struct.pack_into("<q", self._counter, 0, -int(work) - 1)
                code = 0
            finally:
                os._exit(code)
        os.close(write)
        self._data = b""
        self._done = False

    def progress(self, at_least: float, deadline: Deadline) -> tuple[bool, int]:
        """``(done, expanded)`` once the child is done or has expanded ``at_least`` states
        (waiting for it, until ``deadline``); a dead child counts as done."""
        import struct

        while True:
            (v,) = struct.unpack_from("<q", self._counter, 0)
            if v < 0:
                return True, -v - 1
            if v >= at_least or deadline.expired():
                return False, v
            pid, _ = os.waitpid(self.pid, os.WNOHANG)
            if pid:  # died without answering: it will never catch up
                self.pid = 0
                return True, 1 << 62
            time.sleep(0.0005)

    def result(self, timeout: float | None):
        """The child's ``(status, plan, cost)``, waiting up to ``timeout`` seconds (None:
        without limit); ``None`` if it did not answer."""
        import pickle
        import select

        if not self._done:
            end = None if timeout is None else time.perf_counter() + timeout
            while True:
                left = None if end is None else max(0.0, end - time.perf_counter())
                if not select.select([self._read], [], [], left)[0]:
                    return None
                chunk = os.read(self._read, 1 << 16)
                if not chunk:
                    break
                self._data += chunk
            self._done = True
        try:
            return pickle.loads(self._data)
        except Exception:
            return None

    def stop(self) -> None:
        import contextlib
        import signal

        if self.pid:
            with contextlib.suppress(ProcessLookupError):
                os.kill(self.pid, signal.SIGKILL)
            with contextlib.suppress(ChildProcessError):
                os.waitpid(self.pid, 0)
        os.close(self._read)
        self._counter.close()


def require_robot_plan(task: TwoModelTask, r: PlanResult) -> None:
    """Refuse a task whose robot problem has no plan (``r``: the call on the robot model);
    every engine starts from the robot optimum."""
    from mega_sat.errors import UnsolvableError

    src = task.sources.get("robot_problem", "robot problem")
    if r.status == Status.UNSOLVABLE:
        raise UnsolvableError("the robot problem has no plan", path=src)
    if r.status != Status.OPTIMAL:
        raise UnsolvableError(f"no plan found for the robot problem ({r.reason})", path=src)


def ground_strips_pddl(task: GroundTask) -> tuple[str, str, dict[str, PlanStep]]:
    """``task`` as ground STRIPS PDDL without negative preconditions.

    Every atom ``p`` tested negatively gets a complement atom kept exactly in sync per ground
    action (an action that adds and deletes ``p`` adds it, as PDDL says).  Returns the domain,
    the problem and a map from action names back to plan steps.
    """
    neg = sorted({p for a in task.actions for p in a.negpre})
    comp = {p: len(task.atoms) + k for k, p in enumerate(neg)}
    n_atoms = len(task.atoms) + len(neg)

    def atom(i: int) -> str:
        return f"(a{i})"

    actions, names = [], {}
    for k, a in enumerate(task.actions):
        adds = set(a.add)
        dels = set(a.delete) - adds
        pre = [atom(p) for p in sorted(a.pre)] + [atom(comp[p]) for p in sorted(a.negpre)]
        eff = [atom(p) for p in sorted(adds)] + [f"(not {atom(p)})" for p in sorted(dels)]
        eff += [f"(not {atom(comp[p])})" for p in sorted(adds) if p in comp]
        eff += [atom(comp[p]) for p in sorted(dels) if p in comp]
        eff.append(f"(increase (total-cost) {a.cost})")
        name = f"act{k}"
        names[name] = a.step
        actions.append(
            f"  (:action {name}\n    :parameters ()\n"
            f"    :precondition (and {' '.join(pre)})\n"
            f"    :effect (and {' '.join(eff)}))"
        )
    preds = " ".join(f"(a{i})" for i in range(n_atoms))
    domain = (
        "(define (domain ground)\n  (:requirements :strips :action-costs)\n"
        f"  (:predicates {preds})\n  (:functions (total-cost) - number)\n"
        + "\n".join(actions)
        + ")\n"
    )
    init = [atom(p) for p in sorted(task.init)]
    init += [atom(comp[p]) for p in neg if p not in task.init]
    goal = " ".join(atom(p) for p in sorted(task.goal))
    problem = (
        "(define (problem ground-p) (:domain ground)\n"
        f"  (:init {' '.join(init)} (= (total-cost) 0))\n"
        f"  (:goal (and {goal}))\n  (:metric minimize (total-cost)))\n"
    )
    return domain, problem, names
