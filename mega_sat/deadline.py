"""One time limit for a whole run: a :class:`Deadline` made once from ``--timeout`` /
``timeout=`` and handed down to every step (grounding, encodings, the loop, each search, SAT
call and subprocess), so that each step asks the same clock how much time is left.

``check()`` is cheap (one clock read and one comparison), so loops can call it every few
thousand iterations; it raises :class:`TimeLimitReached`, which the caller that can report a
partial result (the CLI, :class:`mega_sat.api.MegaSolver`) catches.
"""

from __future__ import annotations

import math
import time
from dataclasses import dataclass

from mega_sat.errors import EXIT_TIMEOUT, UsageError

MAX_TIMEOUT = 1e9
"""Seconds (about 31 years) above which a time limit means no limit: ``inf``, ``1e308`` and
``1e10`` would overflow the timers that enforce a limit, and no run lasts that long."""


class TimeLimitReached(BaseException):  # noqa: N818 - the name says what happened
    """The run's time limit has passed.

    A ``BaseException`` (like ``KeyboardInterrupt``) so that no ``except Exception`` on the
    way up swallows it.  ``forced`` is true when the CLI's backstop timer raised it at an
    arbitrary point (between any two bytecodes), so nothing half-done may be reused.
    """

    exit_code = EXIT_TIMEOUT

    def __init__(
        self,
        seconds: float | None = None,
        *,
        forced: bool = False,
        detail: str | None = None,
        partial: bool = False,
    ):
        self.seconds = seconds
        self.forced = forced
        self.detail = detail
        """What was proven before the limit, for the error line (e.g. a lower bound)."""
        self.partial = partial
        """``detail`` holds part of the answer (verify's finished checks), not only a bound."""
        text = "time limit reached" if seconds is None else f"time limit {seconds}s reached"
        self.headline = text
        """The message without ``detail``, for a note that says itself what was done."""
        super().__init__(text if detail is None else f"{text} ({detail})")


def parse_timeout(value: object, *, name: str = "timeout") -> float | None:
    """Seconds of a time limit from an option value (number or text), or ``None`` for none.

    ``None``, ``inf`` and anything above :data:`MAX_TIMEOUT` mean no limit; ``nan``, zero,
    negative numbers and text that is not a number are refused with a :class:`UsageError`.
    """
    if value is None:
        return None
    if isinstance(value, bool):  # float(True) is 1.0: a slip, not a limit of one second
        raise UsageError(f"{name} must be a number of seconds > 0, got {value!r}")
    try:
        seconds = float(value.strip() if isinstance(value, str) else value)  # type: ignore[arg-type]
    except (TypeError, ValueError):
        raise UsageError(f"{name} must be a number of seconds > 0, got {value!r}") from None
    if math.isnan(seconds) or seconds <= 0:
        raise UsageError(f"{name} must be a number of seconds > 0, got {value!r}")
    return None if seconds > MAX_TIMEOUT else seconds


@dataclass(frozen=True)
class Deadline:
    """A point in time (``at``, a :func:`time.perf_counter` value; ``None``: no limit) and the
    limit it came from (``seconds``, for messages)."""

    at: float | None = None
    seconds: float | None = None

    @classmethod
    def after(cls, timeout: object = None, *, elapsed: float = 0.0) -> Deadline:
        """The deadline ``timeout`` seconds (see :func:`parse_timeout`) after a start that was
        ``elapsed`` seconds ago."""
        seconds = parse_timeout(timeout)
        if seconds is None:
            return NO_DEADLINE
        return cls(time.perf_counter() - elapsed + seconds, seconds)

    @property
    def limited(self) -> bool:
        return self.at is not None

    def remaining(self) -> float | None:
        """Seconds left (0 once passed); ``None`` without a limit."""
        return None if self.at is None else max(0.0, self.at - time.perf_counter())

    def expired(self) -> bool:
        return self.at is not None and time.perf_counter() >= self.at

    def check(self) -> None:
        """Raise :class:`TimeLimitReached` once the deadline has passed."""
        if self.at is not None and time.perf_counter() >= self.at:
            raise TimeLimitReached(self.seconds)

    def cap(self, seconds: float | None) -> float | None:
        """``seconds`` (a step's own limit, ``None``: none) cut to the time left."""
        left = self.remaining()
        if left is None:
            return seconds
        return left if seconds is None else min(seconds, left)

    def describe(self) -> str:
        return "no time limit" if self.seconds is None else f"time limit {self.seconds}s"


NO_DEADLINE = Deadline()
"""The deadline of a run without a time limit."""


def slack(seconds: float) -> float:
    """How far past a time limit of ``seconds`` a run may stop: max(1 s, 5 %)."""
    return max(1.0, 0.05 * seconds)
