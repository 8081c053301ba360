"""Fast Downward as an external optimal planner (the paper's per-node planner).

Fast Downward comes from the optional ``up-fast-downward`` package.  Its Python ``__init__``
imports ``unified_planning`` (not a dependency of mega-sat), so the package is only *located*,
never imported, and its ``fast-downward.py`` driver is run in a subprocess in a temporary
directory that is removed afterwards.

Exit codes (``driver/returncodes.py`` of the installed package): 0 solved; 10
``TRANSLATE_UNSOLVABLE`` and 11 ``SEARCH_UNSOLVABLE`` are proofs of unsolvability; 21/23/24
(translator or search out of time) are time-outs; the run's deadline is a wall-clock limit
enforced by killing FD's process group.  12 ``SEARCH_UNSOLVED_INCOMPLETE`` means an
*incomplete* search gave up without a plan, which proves nothing, so it is reported as a
:class:`PlannerError` like every other failure.  ``Status.OPTIMAL`` assumes an optimal search
configuration such as the default ``astar(lmcut())``.
"""

from __future__ import annotations

import contextlib
import importlib.util
import os
import re
import signal
import subprocess
import sys
import tempfile
import time
from pathlib import Path

from mega_sat.deadline import Deadline
from mega_sat.errors import PlannerError
from mega_sat.model.lifted import PlanStep
from mega_sat.search.astar import PlanResult, within
from mega_sat.status import Status

_SOLVED = 0
_UNSOLVABLE = (10, 11)
_TIMEOUT = (21, 23, 24)
_COST_RE = re.compile(r";\s*cost\s*=\s*(-?\d+)")


def fd_script() -> Path | None:
    """Path of Fast Downward's driver script, or None when the package is not installed."""
    spec = importlib.util.find_spec("up_fast_downward")
    if spec is None or not spec.submodule_search_locations:
        return None
    script = Path(list(spec.submodule_search_locations)[0]) / "downward" / "fast-downward.py"
    return script if script.is_file() else None


def fd_search_binary() -> Path | None:
    """Fast Downward's search component (``downward``, which reads a SAS+ task on its
    standard input), or None when the package does not ship it where its driver does."""
    script = fd_script()
    if script is None:
        return None
    binary = script.parent / "builds" / "release" / "bin" / "downward"
    return binary if binary.is_file() else None


def fd_available() -> bool:
    """Whether Fast Downward can be run."""
    return fd_script() is not None


FD_INT_LIMIT = 2**29
"""Fast Downward adds costs in 32-bit integers without overflow checks.  With every action
cost at most ``c`` and ``n`` ground actions, A* with LM-cut meets g-values up to ``C* + c``
and heuristic values up to ``n * c`` (LM-cut is a cost partitioning over the actions), so a
task goes to FD only when ``c * (n + 1) < FD_INT_LIMIT`` (:func:`fd_cost_problem`), and an
answer is kept only when ``C* < FD_INT_LIMIT``: every f-value then stays below 2^31."""


def family_cost_problem(family) -> str | None:
    """:func:`fd_cost_problem` of a :class:`~mega_sat.ground.family.GroundFamily`: its
    largest cost in any model, over all its ground actions."""
    return fd_cost_problem(family.max_cost, len(family.actions))


def fd_cost_problem(max_cost: int, n_actions: int) -> str | None:
    """Why Fast Downward cannot be trusted with these costs (``None``: it can)."""
    if max_cost * (n_actions + 1) < FD_INT_LIMIT:
        return None
    return (
        f"action costs up to {max_cost} over {n_actions} ground actions may overflow Fast "
        "Downward's 32-bit cost sums"
    )


def parse_plan_text(text: str) -> tuple[tuple[PlanStep, ...], int | None]:
    """Steps (lower-case) and the ``; cost = N`` value of a plan file in FD/IPC format."""
    steps: list[PlanStep] = []
    cost = None
    for raw in text.splitlines():
        line = raw.strip()
        if not line:
            continue
        if line.startswith(";"):
            m = _COST_RE.match(line)
            if m:
                cost = int(m.group(1))
            continue
        steps.append(tuple(line.strip("()").lower().split()))
    return tuple(steps), cost


_NOISE = re.compile(
    r"^(INFO|Driver aborting|Remove intermediate|Usage error occurred|Traceback:)|exit code: \d+$"
)


def _error_line(stderr: str, stdout: str) -> str:
    """FD's most informative error line: the last non-noise line of stderr, else of stdout
    (the translator reports input errors there, as "message" then "Got: ...").  The driver
    sometimes relays a component's output as a bytes repr (``b'...\\n...'``): unfold it."""
    for text in (stderr, stdout):
        lines = [ln.strip().strip("'\"") for ln in text.replace("\\n", "\n").splitlines()]
        lines = [ln for ln in lines if ln and not _NOISE.search(ln)]
        if lines:
            if lines[-1].startswith("Got:") and len(lines) > 1:
                return f"{lines[-2]} {lines[-1]}"
            return lines[-1]
    return "(no output)"


def fd_plan(
    domain_text: str | None,
    problem_text: str | None,
    *,
    search: str = "astar(lmcut())",
    deadline: Deadline | None = None,
    time_limit: float | None = None,
    sas_text: str | None = None,
) -> PlanResult:
    """Run Fast Downward on PDDL text (or on a SAS+ task, ``sas_text``); ``planner`` of the
    result is ``"fd"``.  FD gets the time left before ``deadline`` (or ``time_limit`` seconds,
    a limit of this call alone, when that comes first) and answers ``TIMEOUT`` when it runs
    out."""
    return FdRun(
        domain_text,
        problem_text,
        search=search,
        deadline=deadline,
        time_limit=time_limit,
        sas_text=sas_text,
    ).result()


class FdRun:
    """One Fast Downward process, started on construction: :meth:`result` waits for its answer
    (as :func:`fd_plan` gives it), :meth:`cancel` ends it unanswered.  Either one removes the
    process group and the temporary folder, so a run started ahead of need (OPT's quick search
    on the other core) leaves nothing behind when it is not needed."""

    def __init__(
        self,
        domain_text: str | None,
        problem_text: str | None,
        *,
        search: str = "astar(lmcut())",
        deadline: Deadline | None = None,
        time_limit: float | None = None,
        sas_text: str | None = None,
    ):
        """FD on the PDDL ``domain_text`` and ``problem_text``, or, with ``sas_text`` (both
        texts ``None``), on that SAS+ task, which skips the translator
        (:mod:`mega_sat.planners.sas`)."""
        script = fd_script()
        if script is None:
            raise PlannerError("Fast Downward is not installed: pip install 'mega-sat[fd]'")
        self.t0 = time.perf_counter()
        self.deadline = within(deadline, time_limit)
        self._tmp: tempfile.TemporaryDirectory | None = tempfile.TemporaryDirectory(
            prefix="mega-sat-fd-"
        )
        tmp = self._tmp.name
        dom, prob, sas, self._plan_file = (
            os.path.join(tmp, n) for n in ("domain.pddl", "problem.pddl", "task.sas", "plan")
        )
        cmd = [sys.executable, str(script), "--plan-file", self._plan_file]
        binary = fd_search_binary() if sas_text is not None else None
        if binary is not None:
            # the search component alone, without the driver's Python start (about 65 ms a
            # run, which adds up over the many small JOINT runs of a loop)
            cmd = [str(binary), "--search", search, "--internal-plan-file", self._plan_file]
        elif sas_text is not None:
            cmd += [sas, "--search", search]  # one SAS+ file: the driver runs the search only
        else:
            cmd += [dom, prob]
            # No mutex invariants: with them, a delete of an atom the action does not require
            # becomes a conditional effect, which astar(lmcut()) refuses ("unsupported
            # feature").  Binary variables keep plain STRIPS semantics and optimal costs.
            cmd += ["--translate-options", "--invariant-generation-max-candidates", "0"]
            cmd += ["--search-options", "--search", search]
        try:
            if sas_text is not None:
                Path(sas).write_text(sas_text)
            else:
                Path(dom).write_text(str(domain_text))
                Path(prob).write_text(str(problem_text))
            # the time limit is wall-clock and enforced here: FD's own --overall-time-limit is
            # CPU time rounded down per component (a 1 s limit leaves the translator 0 s).  FD
            # runs in its own process group so the translator and search die with the driver.
            with open(sas if sas_text is not None else os.devnull) as stdin:
                self._proc: subprocess.Popen | None = subprocess.Popen(
                    cmd,
                    cwd=tmp,
                    stdin=stdin,  # the search binary reads its task here
                    stdout=subprocess.PIPE,
                    stderr=subprocess.PIPE,
                    text=True,
                    start_new_session=True,
                )
        except BaseException:
            self._tmp.cleanup()
            self._tmp = None
            raise

    def _answer(self, status: Status, plan=None, cost=None) -> PlanResult:
        reason = "" if status.decided else str(status)
        elapsed = time.perf_counter() - self.t0
        return PlanResult(status, plan, cost, status.decided, "fd", elapsed, reason)

    def result(self) -> PlanResult:
        """FD's answer (``TIMEOUT`` past the deadline); raises :class:`PlannerError` when FD
        fails.  Called once."""
        proc = self._proc
        if proc is None:
            raise PlannerError("this Fast Downward run was cancelled or has answered already")
        self._proc = None
        try:
            try:
                stdout, stderr = proc.communicate(timeout=self.deadline.remaining())
            except subprocess.TimeoutExpired:
                _kill_group(proc)
                return self._answer(Status.TIMEOUT)
            except BaseException:  # an interrupt or the run's time limit: no orphaned search
                _kill_group(proc)
                raise
            rc = proc.returncode
            if rc == _SOLVED:
                if not os.path.exists(self._plan_file):
                    raise PlannerError("Fast Downward reported success but wrote no plan file")
                steps, cost = parse_plan_text(Path(self._plan_file).read_text())
                if cost is None:
                    raise PlannerError("Fast Downward's plan file has no '; cost = N' line")
                if cost >= FD_INT_LIMIT:
                    raise PlannerError(
                        f"Fast Downward's plan costs {cost}, beyond the range in which its "
                        "32-bit cost sums are exact"
                    )
                return self._answer(Status.OPTIMAL, steps, cost)
            if rc in _UNSOLVABLE:
                return self._answer(Status.UNSOLVABLE)
            if rc in _TIMEOUT:
                return self._answer(Status.TIMEOUT)
            raise PlannerError(
                f"Fast Downward failed (exit code {rc}): {_error_line(stderr, stdout)}"
            )
        finally:
            self._cleanup()

    def cancel(self) -> None:
        """End the run without its answer (a no-op once it has answered)."""
        proc, self._proc = self._proc, None
        try:
            if proc is not None:
                _kill_group(proc)
        finally:
            self._cleanup()

    def _cleanup(self) -> None:
        if self._tmp is not None:
            self._tmp.cleanup()
            self._tmp = None


def _kill_group(proc: subprocess.Popen) -> None:
    """End FD's whole process group (driver, translator, search) and reap the driver."""
    with contextlib.suppress(ProcessLookupError):
        os.killpg(proc.pid, signal.SIGKILL)
    proc.communicate()
