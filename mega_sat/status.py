"""One status vocabulary for every question the engines ask (OPT, JOINT, a planner call)."""

from __future__ import annotations

from enum import Enum


class Status(str, Enum):
    """The answer to one question.  A ``str`` so that JSON, stats and comparisons with the
    plain words keep working; ``str()`` and f-strings give the word itself."""

    OPTIMAL = "optimal"
    """OPT: a plan of proven optimal cost."""
    UNSOLVABLE = "unsolvable"
    """OPT: proven that no plan exists."""
    PLAN = "plan"
    """JOINT: a plan within both bounds whose robot cost is minimal among them."""
    INFEASIBLE = "infeasible"
    """JOINT: proven that no plan meets both bounds."""
    TIMEOUT = "timeout"
    """The deadline passed before an answer: nothing proven."""
    LIMIT = "limit"
    """A node, conflict or horizon budget ran out before an answer: nothing proven."""

    def __str__(self) -> str:
        return self.value

    def __format__(self, spec: str) -> str:
        return format(self.value, spec)

    @property
    def decided(self) -> bool:
        """Whether the answer is proven (not a timeout or a budget running out)."""
        return self not in (Status.TIMEOUT, Status.LIMIT)
