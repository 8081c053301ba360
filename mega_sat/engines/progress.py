"""What an engine has proven so far, published as it goes, and a live view of it.

A run can be stopped anywhere: by its time limit (cooperatively, or by the CLI's backstop timer
between any two bytecodes) or by SIGINT/SIGTERM.  The engines write each proven fact here the
moment it is proven (the robot optimum, each frontier point, the current lower bound on the
explanation cost),
so the caller that catches the stop can still report them, marked incomplete.

The same record feeds :class:`LiveProgress`, the CLI's status line on stderr (iteration, the
|E| being searched, points found, time used of the limit): a background thread reads it, so
the engines only keep their fields current and never wait for the display.
"""

from __future__ import annotations

import contextlib
import os
import sys
import threading
import time
from dataclasses import dataclass, field
from typing import TextIO

from mega_sat.deadline import Deadline
from mega_sat.results import Frontier, FrontierPoint, needs, pareto_filter


def lower_bound_note(bound: int, have_points: bool, weighted: bool = False) -> str:
    """What a lower bound on the explanation cost (|E|, or cost(E) with update costs) from the
    hitting set proves: with points, about the solutions cheaper than the last one (the loop's
    robot-cost bound); without, about every solution."""
    if bound <= 0:  # true of every solution, so it says nothing
        return "" if have_points else "no point found yet"
    if have_points:
        what = "cost(E)" if weighted else "|E|"
        return f"any solution cheaper than the last point needs {what} >= {bound}"
    return f"no point found yet; {needs(bound, weighted)}"


@dataclass
class Progress:
    """Facts proven by one engine run; mutable on purpose (the engine appends to it).

    ``points`` are real MEGA solutions (for the ``sat`` engine each with the smallest cost(E)
    for its robot cost level); ``lower_bound`` is a proven lower bound on cost(E) (``|E|``
    without update costs) of any solution cheaper than the last point (``sat`` engine only);
    ``notes`` are the engine's reasons why its result is not exact (shared with the engine, so
    they are current); ``update_costs``: the cost per update when update costs are in use.
    """

    engine: str = ""
    model_difference: tuple[str, ...] = ()
    update_costs: tuple[int, ...] | None = None
    robot_optimal_cost: int | None = None
    points: list[FrontierPoint] = field(default_factory=list)
    lower_bound: int | None = None
    notes: list[str] = field(default_factory=list)
    stats: dict = field(default_factory=dict)
    t0: float = field(default_factory=time.perf_counter)
    iteration: int = 0
    size: int | None = None

    def start(
        self,
        engine: str,
        model_difference: tuple[str, ...],
        update_costs: tuple[int, ...] | None = None,
    ) -> None:
        """Forget an earlier run and start recording a new one."""
        self.engine, self.model_difference = engine, model_difference
        self.update_costs = update_costs
        self.robot_optimal_cost, self.lower_bound = None, None
        self.points, self.notes, self.stats = [], [], {}
        self.iteration, self.size = 0, None
        self.t0 = time.perf_counter()

    def step(self, size: int) -> None:
        """A new candidate explanation of ``size`` updates is being checked (for the display
        only: ``iteration`` and ``size`` prove nothing)."""
        self.iteration += 1
        self.size = size

    def frontier(self, reason: str) -> Frontier | None:
        """The proven part as an incomplete, inexact :class:`Frontier` (``reason`` says why it
        stopped), or ``None`` before the robot optimum was known (nothing to report)."""
        if self.robot_optimal_cost is None:
            return None
        notes = [*self.notes, reason]
        weighted = self.update_costs is not None
        if self.lower_bound is not None:
            note = lower_bound_note(self.lower_bound, bool(self.points), weighted)
            notes[-1] += f"; {note}" if note else ""
        return Frontier(
            engine=self.engine,
            robot_optimal_cost=self.robot_optimal_cost,
            model_difference=self.model_difference,
            points=pareto_filter(self.points),
            exact=False,
            complete=False,
            notes=tuple(dict.fromkeys(notes)),
            next_size_lower_bound=None if weighted else self.lower_bound,
            time_s=time.perf_counter() - self.t0,
            stats=dict(self.stats),
            update_costs=self.update_costs,
            next_cost_lower_bound=self.lower_bound,
        )


PROGRESS_ENV = "MEGA_SAT_PROGRESS"
"""``always``: show the live progress even when stderr is not a terminal (tests, recordings);
``never``: do not show it.  Unset: shown on a terminal only."""

SHOW_AFTER = 1.0
"""Seconds of run time before the status line appears (shorter runs print nothing extra)."""

REFRESH = 0.25
"""Seconds between two redraws of the status line."""


def progress_wanted(quiet: bool = False, stream: TextIO | None = None) -> bool:
    """Whether to show live progress on ``stream`` (default stderr): not with ``--quiet``, and
    only on a terminal, so logs and pipes get no carriage-return redraws."""
    if quiet:
        return False
    forced = os.environ.get(PROGRESS_ENV, "").strip().lower()
    if forced in ("always", "never"):
        return forced == "always"
    stream = sys.stderr if stream is None else stream
    try:
        return bool(stream.isatty())
    except (AttributeError, ValueError):  # no stream, or a closed one
        return False


def _seconds(s: float) -> str:
    return f"{s:.0f}s" if s >= 100 else f"{s:.1f}s"


class LiveProgress:
    """A status line on stderr, redrawn by a daemon thread through tqdm while a command runs.

    It appears after :data:`SHOW_AFTER` seconds of run time and is cleared by :meth:`stop`
    before the answer is printed.  Without tqdm installed it shows nothing (tqdm is a core
    dependency; an install without it only loses the display).
    """

    def __init__(
        self,
        command: str,
        deadline: Deadline,
        *,
        started: float | None = None,
        stream: TextIO | None = None,
    ):
        self.command = command
        self.deadline = deadline
        self.started = time.perf_counter() if started is None else started
        self.stream = sys.stderr if stream is None else stream
        self.progress: Progress | None = None
        self._stop = threading.Event()
        self._thread: threading.Thread | None = None

    def watch(self, progress: Progress) -> None:
        """Show the state of ``progress`` from now on."""
        self.progress = progress

    def elapsed(self) -> float:
        return time.perf_counter() - self.started

    def text(self) -> str:
        """The status line, e.g. ``frontier: iteration 7, searching |E| = 2, 1 point found,
        3.2s of 60s``."""
        p = self.progress
        if p is None or not p.engine:
            what = "reading and grounding the models"
        elif p.iteration == 0:
            what = "computing the robot optimum"
        else:
            what = f"iteration {p.iteration}, searching |E| = {p.size}"
            if p.engine != "mce":  # an MCE has no point before its answer
                # astar publishes every node the robot can run: count the Pareto-optimal ones
                n = len(pareto_filter(list(p.points)))
                what += f", {n} point{'' if n == 1 else 's'} found"
        used = _seconds(self.elapsed())
        if self.deadline.seconds is not None:
            used += f" of {self.deadline.seconds:g}s"
        return f"{self.command}: {what}, {used}"

    def start(self) -> None:
        if self._thread is None:
            self._thread = threading.Thread(target=self._run, name="mega-sat-progress", daemon=True)
            self._thread.start()

    def stop(self) -> None:
        """Clear the line and end the thread (idempotent; the answer follows on stdout)."""
        self._stop.set()
        thread, self._thread = self._thread, None
        if thread is not None and thread is not threading.current_thread():
            thread.join(timeout=1.0)

    def _run(self) -> None:
        if self._stop.wait(max(0.0, SHOW_AFTER - self.elapsed())):
            return
        try:
            from tqdm import tqdm
        except ImportError:
            return
        limit = self.deadline.seconds
        bar = tqdm(
            desc=self.text(),
            file=self.stream,
            total=limit,
            bar_format="{desc}" if limit is None else "{desc} |{bar:12}|",
            leave=False,
            dynamic_ncols=True,
        )
        try:
            while True:
                if limit is not None:
                    bar.n = min(self.elapsed(), limit)
                bar.set_description_str(self.text(), refresh=False)
                bar.refresh()
                if self._stop.wait(REFRESH):
                    break
        except (OSError, ValueError):
            pass  # stderr closed or full: the display is not worth an error
        finally:
            with contextlib.suppress(OSError, ValueError):
                bar.close()
