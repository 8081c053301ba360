"""SAT solver plumbing of the oracles: the two live solvers, chunked solves, and stopping.

A solver call runs in conflict chunks; between chunks it checks for an interrupt or a passed
deadline.  CaDiCaL holds the GIL and pysat cannot interrupt it, so a deadline can only act
between chunks, and the chunks near a deadline are cut to the time left.  Solvers with a
native interrupt (MiniSat/Glucose family) are also interrupted at once by a timer thread.
"""

from __future__ import annotations

import threading
import time
from collections.abc import Callable

from pysat.solvers import Solver

from mega_sat.deadline import NO_DEADLINE, Deadline
from mega_sat.errors import redeliver_sigint
from mega_sat.options import Options
from mega_sat.sat.stats import OracleStats

CADICAL_OPTIONS = {"elim": 0}
"""Options for CaDiCaL (both versions) as the oracles' solver: bounded variable elimination
off, because the oracles' many small incremental calls under assumptions need fewer conflicts
without it (the measurements are in bench/README.md, per-call section)."""


class OracleInterrupted(Exception):  # noqa: N818 - the name says what happened
    """A SAT oracle call was stopped by :meth:`Solving.interrupt` or its deadline.

    Nothing was proven by the interrupted call; the oracles stay usable for later calls.
    """


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


def _usable(deadline: Deadline) -> Deadline:
    """``deadline``, or none if a timer cannot wait that long (``threading.TIMEOUT_MAX``): the
    timer thread would die of an OverflowError."""
    left = deadline.remaining()
    if left is not None and not left < threading.TIMEOUT_MAX / 2:
        return NO_DEADLINE
    return deadline


class Solving:
    """The OPT solver and the JOINT solver, with one deadline and one interrupt for both.

    ``deadline`` is the run's; ``call_deadline`` a tighter one for the current call only (an
    observer's per-call limit).  Every solver call started after the earlier of the two raises
    :class:`OracleInterrupted` until the deadline is moved.
    """

    def __init__(self, name: str, options: Options, stats: OracleStats):
        self.name = name
        self.opt_solver = new_solver(name)
        self.joint_solver = new_solver(name)
        self.options = options
        self.stats = stats
        self.rate: dict[int, float] = {}
        """Measured seconds per conflict, per solver (``id``)."""
        self._interrupted = False
        self._deadline = NO_DEADLINE
        self._call_deadline = NO_DEADLINE
        self.stop_probe: Callable[[], bool] | None = None  # the portfolio's "search is done"
        # called between the chunks of a call, after check(): a caller's side proof (it may
        # raise to end the call); it never touches the solver, so the search path is the same
        self.between_chunks: Callable[[], None] | None = None
        # work done outside the solvers (searches, integer programs), in search states, for
        # the portfolio's referee; it only grows, and counts the same on every run
        self.side_work = 0
        self._at: float | None = None  # the earlier of the two, as a perf_counter value
        self._timer: threading.Timer | None = None
        self._native_interrupt = _supports_interrupt(self.joint_solver)

    def close(self) -> None:
        self._deadline = self._call_deadline = NO_DEADLINE
        self._arm()
        self.opt_solver.delete()
        self.joint_solver.delete()

    # ---------------------------------------------------------------- stopping
    @property
    def deadline(self) -> Deadline:
        return self._deadline

    @deadline.setter
    def deadline(self, deadline: Deadline | None) -> None:
        self._deadline = _usable(deadline if deadline is not None else NO_DEADLINE)
        self._arm()

    @property
    def call_deadline(self) -> Deadline:
        return self._call_deadline

    @call_deadline.setter
    def call_deadline(self, deadline: Deadline | None) -> None:
        self._call_deadline = _usable(deadline if deadline is not None else NO_DEADLINE)
        self._arm()

    def effective(self) -> Deadline:
        """The earlier of the run's and the call's deadline."""
        run, call = self._deadline, self._call_deadline
        if run.at is None or (call.at is not None and call.at < run.at):
            return call
        return run

    def _arm(self) -> None:
        """Clear any interrupt and start a timer that interrupts at the effective deadline."""
        if self._timer is not None:
            self._timer.cancel()
            self._timer = None
        self._at = self.effective().at
        self._clear_interrupt()
        if self._at is not None:
            self._timer = threading.Timer(max(0.0, self._at - time.perf_counter()), self.interrupt)
            self._timer.daemon = True
            self._timer.start()

    def interrupt(self) -> None:
        """Stop the running solver call (from any thread); see :meth:`SatOracles.interrupt`."""
        self._interrupted = True
        if self._native_interrupt:
            for s in (self.opt_solver, self.joint_solver):
                s.interrupt()

    def _clear_interrupt(self) -> None:
        self._interrupted = False
        if self._native_interrupt:
            for s in (self.opt_solver, self.joint_solver):
                s.clear_interrupt()

    def time_left(self) -> float | None:
        """Seconds until the effective deadline (negative once passed); ``None`` without one."""
        return None if self._at is None else self._at - time.perf_counter()

    def check(self) -> None:
        """Raise :class:`OracleInterrupted` after an interrupt, past the deadline, or once
        ``stop_probe`` (when set) says another method has answered the question."""
        left = self.time_left()
        late = left is not None and left <= 0
        if self._interrupted or late:
            self._clear_interrupt()
            raise OracleInterrupted("deadline reached" if late else "interrupted")
        if self.stop_probe is not None and self.stop_probe():
            raise OracleInterrupted("answered by another method")

    # ----------------------------------------------------------------- solving
    def solve(self, solver: Solver, assumptions: list[int], budget: int | None = None):
        """One SAT call: ``True``/``False``, or ``None`` if ``budget`` conflicts ran out.

        Runs in conflict chunks (``solve_limited(expect_interrupt=True)``) and checks for an
        interrupt or a passed deadline before and between chunks; an interrupted call raises
        :class:`OracleInterrupted` and proves nothing.  Chunk sizes follow :meth:`chunk` and do
        not change the answers.
        """
        self.check()
        if budget is not None and budget <= 0:
            return None
        self.stats.solver_calls += 1
        left = budget
        index = 0
        while True:
            chunk = self.chunk(solver, index)
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
            self.stats.solve_time_s += time.perf_counter() - t0
            if r is not None:
                return r
            self.rate[id(solver)] = (time.perf_counter() - t0) / chunk
            self.check()
            if self.between_chunks is not None:
                self.between_chunks()
            if left is not None:
                left -= chunk
                if left <= 0:
                    return None

    def chunk(self, solver: Solver, index: int) -> int:
        """Conflicts for chunk ``index`` (0, 1, ...) of one call on ``solver``:
        ``first_chunk * (index + 1)``, at most ``solve_chunk``; the same on every run.  Only
        within reach of a deadline is a chunk cut to the time left, at the solver's measured
        seconds per conflict.

        The schedule does not follow the clock because chunk boundaries steer CaDiCaL's search
        (each chunk is a new ``solve`` call): chunks sized by the clock make the learned
        clauses, cores and plans, and with them the loop's path through the models, differ
        from run to run."""
        opts = self.options
        size = min(opts.solve_chunk, opts.first_chunk * (index + 1))
        rate = self.rate.get(id(solver))
        left = self.time_left()
        if rate is not None and left is not None:
            size = min(size, int(max(left, 0.01) / max(rate, 1e-9)))
        return max(1, size)

    def conflicts(self) -> int | None:
        """Conflicts spent so far by both solvers (``None`` if a solver does not count them)."""
        total = 0
        for solver in (self.opt_solver, self.joint_solver):
            got = (solver.accum_stats() or {}).get("conflicts")
            if got is None:
                return None
            total += int(got)
        return total
