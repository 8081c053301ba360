"""User-facing errors: one line, naming the file, the place and the problem.

``str(error)`` is the message alone (``<file>: <place>: <problem>``), so a library caller can
show it in its own words; the CLI prints it as ``error: <message>`` and exits with
``error.exit_code``, never with a traceback.  Anything else escaping is a bug in mega-sat.
"""

from __future__ import annotations

import signal
import threading

# The exit codes of every command, one table (docs/cli.md, "Exit codes and errors").
EXIT_OK = 0
EXIT_FAILED = 1
EXIT_USAGE = 2
EXIT_UNSOLVABLE = 3
EXIT_TOOL = 4
EXIT_OUTPUT = 74
EXIT_TIMEOUT = 124
EXIT_SIGINT = 128 + signal.SIGINT
EXIT_SIGTERM = 128 + signal.SIGTERM

EXIT_CODES: dict[int, str] = {
    EXIT_OK: "an answer, complete or partial (a time limit with a partial answer is 0 plus "
    "`complete: false`)",
    EXIT_FAILED: "a plan or a verification that failed",
    EXIT_USAGE: "bad input (or a task larger than the memory the process may use)",
    EXIT_UNSOLVABLE: "the robot problem (or the model asked about) is proven unsolvable",
    EXIT_TOOL: "an external tool failed",
    EXIT_OUTPUT: "the output could not be written",
    EXIT_TIMEOUT: "the time limit was reached before an answer could be reported: no robot "
    "optimum, MCE, plan or verification finished yet, or for `frontier` and `solve` no frontier "
    "point found yet",
    EXIT_SIGINT: "interrupted by SIGINT (Ctrl-C)",
    EXIT_SIGTERM: "interrupted by SIGTERM",
}
"""Meaning of each exit code; a test checks that docs/cli.md lists exactly these."""


class Interrupted(BaseException):  # noqa: N818 - the name says what happened
    """SIGINT or SIGTERM arrived; the CLI raises it from its signal handler.

    A ``BaseException`` (like ``KeyboardInterrupt``) so that library code does not swallow it
    on its way to the CLI, which reports what was proven and exits with ``exit_code``.
    """

    def __init__(self, signum: int):
        self.signum = signum
        self.exit_code = 128 + signum
        self.signal_name = signal.Signals(signum).name
        super().__init__(f"interrupted by {self.signal_name}")


def is_pysat_interrupt(e: BaseException) -> bool:
    """Whether ``e`` is python-sat's error for a SIGINT it caught during a solve."""
    return type(e).__module__ == "pysolvers" and "keyboard interrupt" in str(e).lower()


def restore_sigint() -> None:
    """Undo what python-sat leaves behind when it catches SIGINT during a solve: its C handler
    jumps out of the solve with ``longjmp``, so SIGINT stays blocked and that handler stays
    installed (a later Ctrl-C would then be lost, or jump into a stale frame).  Registers the
    Python-level handler again and unblocks SIGINT; main thread only (pysat catches SIGINT
    only there)."""
    if threading.current_thread() is not threading.main_thread():
        return
    handler = signal.getsignal(signal.SIGINT)
    if handler is not None:
        signal.signal(signal.SIGINT, handler)
    signal.pthread_sigmask(signal.SIG_UNBLOCK, {signal.SIGINT})


def redeliver_sigint(e: BaseException) -> None:
    """python-sat turns a SIGINT during a solve into its own error ("Caught keyboard
    interrupt") instead of running the process's SIGINT handler.  Repair the signal state
    (:func:`restore_sigint`) and deliver the signal again, so the handler in place raises as
    for any other Ctrl-C (``KeyboardInterrupt`` by default, :class:`Interrupted` in the CLI);
    other errors are left alone."""
    if is_pysat_interrupt(e):
        restore_sigint()
        signal.raise_signal(signal.SIGINT)


class MegaSatError(Exception):
    """Base class of every error caused by user input or an unsolvable request."""

    exit_code = EXIT_USAGE

    def __init__(self, message: str, *, path: str | None = None, where: str | None = None):
        self.message = message
        self.path = path
        self.where = where
        super().__init__(self.__str__())

    def __str__(self) -> str:
        loc = ""
        if self.path:
            loc = f"{self.path}"
            if self.where:
                loc += f": {self.where}"
            loc += ": "
        elif self.where:
            loc = f"{self.where}: "
        return f"{loc}{self.message}"


class PDDLError(MegaSatError):
    """Malformed PDDL, or PDDL that uses a construct mega-sat does not support."""


class FamilyNotCompiled(PDDLError):  # noqa: N818 - a PDDLError, named for its cause
    """Each model alone is fine, but the family of all ``human + E`` cannot be written with
    one-literal guards (a negative goal's complement would need two updates at once).
    Commands about one model ground that model alone instead; the others report it."""


class ModelMismatchError(MegaSatError):
    """Robot and human models that cannot form one model family (e.g. different arities).

    ``anchor`` says where the cause is written, for a reader of the files to give its line:
    the file's role (``human_domain``, ...), what it is (``action``, ``predicate``,
    ``function`` or ``value``) and its name or term."""

    def __init__(
        self,
        message: str,
        *,
        path: str | None = None,
        where: str | None = None,
        anchor: tuple[str, str, tuple[str, ...]] | None = None,
    ):
        super().__init__(message, path=path, where=where)
        self.anchor = anchor


class UnsolvableError(MegaSatError):
    """The robot problem (or another problem that must be solvable) has no plan."""

    exit_code = EXIT_UNSOLVABLE


class PlannerError(MegaSatError):
    """An external tool (Fast Downward, CBC, VAL) failed (distinct from a proven
    'unsolvable'; running out of the run's time limit is :class:`TimeLimitReached`)."""

    exit_code = EXIT_TOOL


class UsageError(MegaSatError):
    """Bad option values (alpha < 0, unknown updates in an explanation file, ...)."""


class StdoutError(MegaSatError):
    """Standard output cannot be written (closed, a full disk, a closed pipe)."""

    exit_code = EXIT_OUTPUT
