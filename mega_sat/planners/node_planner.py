"""One optimal planning call on one model of the family, by a chosen planner.

The A* baseline calls this at every node of its model-space search, MCE and verification use it
too.  Three planners answer the same question (optimal cost and one optimal plan of
``human + E``):

* ``builtin`` — explicit-state search on the ground task: uniform-cost, then A* with LM-cut
  (:func:`mega_sat.search.astar.solve_optimal`);
* ``sat``     — the OPT oracle of the SAT encoding (:mod:`mega_sat.sat.oracles`);
* ``fd``      — Fast Downward ``astar(lmcut())`` on PDDL files of the model, the paper's set-up;
* ``portfolio`` — ``builtin`` and ``sat`` in turns of doubling length, the method that answered
  the last call first; the first to decide answers.  Both are exact, so the cost is the same
  whichever answers; the answer's ``planner`` says which did.  Past the SAT horizon cap only
  the explicit search can decide, and it runs on alone: it is complete (it exhausts the finite
  state space of an unsolvable model), so every model gets decided, given time.
"""

from __future__ import annotations

import os
import time

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
            from mega_sat.planners.fast_downward import fd_available

            if not fd_available():
                raise UsageError("planner 'fd' needs Fast Downward: pip install 'mega-sat[fd]'")
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
        self._slice = options.race_slice

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

            r = solve_optimal(task, deadline=call, blind_nodes=self.options.blind_nodes)
            return answer(r.status, r.plan, r.cost, reason=r.reason)
        if self.kind == "sat":
            r = self.oracles.opt(sel)
            return answer(r.status, r.plan, r.cost, r.exact, r.reason)
        if self.kind == "portfolio":
            if self.options.race_processes and hasattr(os, "fork"):
                return self._race_forked(sel, task, call, t0)
            return self._race(sel, task, call, t0)
        from mega_sat.pddl.writer import domain_to_pddl, problem_to_pddl
        from mega_sat.planners.fast_downward import fd_plan

        model = self.task.updated_model(sel)
        r = None
        if not any(s.negpre for s in model.schemas.values()):
            try:
                r = fd_plan(domain_to_pddl(model), problem_to_pddl(model), deadline=call)
            except PlannerError as e:
                if "exit code 34" not in str(e):
                    raise
        if r is None:
            # FD compiles negative preconditions (and some add/delete overlaps) into axioms or
            # conditional effects, which LM-cut rejects: hand it the ground model with those
            # compiled away instead (same plans, same costs)
            dom, prob, names = ground_strips_pddl(task)
            r = fd_plan(dom, prob, deadline=call)
            if r.status == Status.OPTIMAL and r.plan is not None:
                return answer(Status.OPTIMAL, tuple(names[s[0]] for s in r.plan), r.cost)
        if r.status == Status.OPTIMAL and r.plan is not None:
            # FD may print names in another case or order; map back onto the family's steps
            plan = tuple(tuple(x.lower() for x in s) for s in r.plan)
            missing = [s for s in plan if s not in self.family.action_index]
            if missing:
                raise PlannerError(
                    f"Fast Downward returned an action outside the ground family: "
                    f"({' '.join(missing[0])})"
                )
            return answer(Status.OPTIMAL, plan, r.cost)
        return answer(r.status, reason=r.reason)

    def _race_forked(
        self, sel: frozenset[int], task: GroundTask, call: Deadline, t0: float
    ) -> PlanResult:
        """The portfolio on both cores: uniform-cost search in a forked child process while
        the SAT OPT oracle runs here.  The oracle polls the child's pipe between solver
        chunks and stops once the child has answered; a SAT answer ends the child.  Past the
        horizon cap SAT cannot decide and the search runs on until ``call``."""
        from mega_sat.sat.oracles import OracleInterrupted

        child = ForkedSearch(task)
        try:
            orc = self.oracles
            orc.solving.stop_probe = child.ready
            r = None
            try:
                r = orc.opt(sel)
            except OracleInterrupted:
                if call.expired() or not child.ready():
                    raise
            finally:
                orc.solving.stop_probe = None
            if r is not None and r.status.decided:
                self._first = "sat"
                return PlanResult(
                    r.status, r.plan, r.cost, r.exact, "sat", time.perf_counter() - t0, r.reason
                )
            got = child.result(call.remaining())
            if got is None:  # the search died (memory) or ran out of time
                if r is not None:
                    return PlanResult(r.status, None, None, False, "sat", 0.0, r.reason)
                if call.expired():
                    return PlanResult(Status.TIMEOUT, None, None, False, "builtin", 0.0)
                return self._race(sel, task, call, t0)
            status, plan, cost = got
            self._first = "builtin"
            elapsed = time.perf_counter() - t0
            return PlanResult(status, plan, cost, True, "builtin", elapsed, "uniform-cost search")
        finally:
            child.stop()

    def _race(self, sel: frozenset[int], task: GroundTask, call: Deadline, t0: float) -> PlanResult:
        """The portfolio: uniform-cost search and the SAT OPT oracle in turns, each round's
        turns twice as long as the last, until one decides.  The search is paused and resumed,
        never restarted; SAT OPT restarts, but its solver keeps what it learned.  SAT past its
        horizon cap cannot decide and drops out; the search then runs on alone until ``call``
        (it is complete: it exhausts the state space of an unsolvable model).  The method that
        answered goes first next time, with a first turn of 1.5 times the time it needed (at
        least ``race_slice``)."""
        from mega_sat.sat.oracles import OracleInterrupted
        from mega_sat.search.astar import uniform_cost_steps

        init = sum(1 << p for p in task.init)
        goal = sum(1 << p for p in task.goal)
        search = uniform_cost_steps(task, init, goal)
        methods = [self._first] + [m for m in ("builtin", "sat") if m != self._first]
        used = dict.fromkeys(methods, 0.0)
        turn = self._slice
        why = "time limit"
        while True:
            for m in list(methods):
                alone = len(methods) == 1
                sub = call if alone else within(call, turn)
                t1 = time.perf_counter()
                r = None
                if m == "builtin":
                    stop_at = sub.at
                    try:
                        while True:
                            next(search)
                            if stop_at is not None and time.perf_counter() > stop_at:
                                break
                    except StopIteration as done:
                        status, plan, cost, _ = done.value
                        r = PlanResult(status, plan, cost, True, m, 0.0, "uniform-cost search")
                else:
                    orc = self.oracles
                    orc.solving.call_deadline = None if alone else sub
                    try:
                        r = orc.opt(sel)
                    except OracleInterrupted:
                        if call.expired():
                            raise
                    finally:
                        orc.solving.call_deadline = None
                    if r is not None and not r.status.decided:
                        methods.remove(m)  # past the horizon cap: only the search decides
                        why, r = r.reason, None
                used[m] += time.perf_counter() - t1
                if r is not None and r.status.decided:
                    self._first = m
                    self._slice = max(self.options.race_slice, 1.5 * used[m])
                    elapsed = time.perf_counter() - t0
                    return PlanResult(r.status, r.plan, r.cost, r.exact, m, elapsed, r.reason)
                if call.expired():
                    return PlanResult(Status.TIMEOUT, None, None, False, m, 0.0, why)
            turn *= 2


class ForkedSearch:
    """Uniform-cost search of ``task`` in a forked child process; its answer ``(status, plan,
    cost)`` comes back pickled through a pipe.  The child ignores Ctrl-C (the parent stops
    it) and leaves by ``os._exit``, so it never flushes the parent's buffered output."""

    def __init__(self, task: GroundTask):
        import warnings

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

                from mega_sat.search.astar import _uniform_cost

                signal.signal(signal.SIGINT, signal.SIG_IGN)
                os.close(self._read)
                init = sum(1 << p for p in task.init)
                goal = sum(1 << p for p in task.goal)
                status, plan, cost, _ = _uniform_cost(task, init, goal, None, None)
                data = pickle.dumps((status, plan, cost))
                view = memoryview(data)
                while view:
                    view = view[os.write(write, view) :]
                code = 0
            finally:
                os._exit(code)
        os.close(write)
        self._data = b""
        self._done = False

    def ready(self) -> bool:
        """Whether the child has answered (or died): reading will not block."""
        import select

        return self._done or bool(select.select([self._read], [], [], 0)[0])

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

        with contextlib.suppress(ProcessLookupError):
            os.kill(self.pid, signal.SIGKILL)
        os.waitpid(self.pid, 0)
        os.close(self._read)


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
