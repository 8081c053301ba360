"""User-facing errors: one line, naming the file, the place and the problem.

The CLI prints ``str(error)`` and exits with ``error.exit_code``; it never shows a traceback for
these.  Anything else escaping is a bug in mega-sat.
"""

from __future__ import annotations


class MegaSatError(Exception):
    """Base class of every error caused by user input or an unsolvable request."""

    exit_code = 2

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
        return f"error: {loc}{self.message}"


class PDDLError(MegaSatError):
    """Malformed PDDL, or PDDL that uses a construct mega-sat does not support."""


class ModelMismatchError(MegaSatError):
    """Robot and human models that cannot form one model family (e.g. different arities)."""


class UnsolvableError(MegaSatError):
    """The robot problem (or another problem that must be solvable) has no plan."""

    exit_code = 3


class PlannerError(MegaSatError):
    """An external planner failed or timed out (distinct from a proven 'unsolvable')."""

    exit_code = 4


class UsageError(MegaSatError):
    """Bad option values (alpha < 0, unknown updates in an explanation file, ...)."""
