"""Watching the SAT oracles call by call, without touching their insides.

``SatOracles(family, observer=obs)`` calls ``obs.begin(call)`` before every ``OPT`` and
``JOINT`` call and ``obs.end(call)`` after it (also when it raises), with one
:class:`OracleCall` that ``end`` finds filled in: the answer or the exception, wall seconds,
SAT conflicts, the largest horizon asked, and the seconds of each kind of work.  ``begin`` may
return a :class:`mega_sat.deadline.Deadline` for that call alone (the oracles stop at the
earlier of it and their own deadline).  The ``bench-calls`` harness
(:mod:`mega_sat.bench.oracle_calls`) is built on this.
"""

from __future__ import annotations

from dataclasses import dataclass
from typing import Protocol

from mega_sat.deadline import Deadline
from mega_sat.ground.family import GuardLit
from mega_sat.search.answers import JointResult, OptResult


@dataclass
class OracleCall:
    """One ``OPT`` or ``JOINT`` call: what was asked (set before ``begin``), what came back and
    what it cost (set before ``end``)."""

    kind: str
    """``"opt"`` or ``"joint"``."""
    selection: frozenset[int] | None = None
    """The model ``human + selection`` asked about; ``None`` for JOINT on a partial assignment."""
    lits: tuple[GuardLit, ...] | None = None
    """JOINT on a partial assignment: its selector literals."""
    robot_bound: int | None = None
    human_bound: int | None = None
    cached: bool = False
    """OPT answered from the oracles' cache, without new work."""
    result: OptResult | JointResult | None = None
    error: BaseException | None = None
    """What the call raised (:class:`mega_sat.sat.solving.OracleInterrupted` at a deadline)."""
    seconds: float = 0.0
    conflicts: int | None = None
    """Conflicts of both SAT solvers during the call; ``None`` if a solver does not count them."""
    max_horizon_asked: int | None = None
    """The largest horizon whose goal the call assumed; ``None``: no SAT query."""
    solve_s: float = 0.0
    """Seconds inside SAT solver calls."""
    grow_s: float = 0.0
    """Seconds growing the encodings (new steps with their invariants, goal and cost clauses)."""
    search_s: float = 0.0
    """Seconds of explicit searches (OPT's lowered-cost search, the fallbacks past the cap)."""
    counting_s: float = 0.0
    """Seconds of operator-counting integer programs."""


class OracleObserver(Protocol):
    """Receives every oracle call; see the module docstring."""

    def begin(self, call: OracleCall) -> Deadline | None: ...

    def end(self, call: OracleCall) -> None: ...
