"""The answers to the two questions of the hitting-set loop, whoever answers them.

``OPT(E)`` (the optimal cost of ``human + E``) and ``JOINT(E, K, c)`` (the cheapest robot plan
within both bounds, or a core) are answered by the SAT oracles (:mod:`mega_sat.sat`) and by
explicit search (:mod:`mega_sat.search.joint`); both give these types, so the loop reads one
vocabulary (:class:`mega_sat.status.Status`).
"""

from __future__ import annotations

from dataclasses import dataclass

from mega_sat.ground.family import GuardLit
from mega_sat.model.lifted import PlanStep
from mega_sat.status import Status


@dataclass(frozen=True)
class OptResult:
    """Outcome of ``OPT(E)``.

    ``status``: ``OPTIMAL`` (``cost``/``plan`` set), ``UNSOLVABLE`` (no plan at all) or
    ``LIMIT`` (a budget ran out: nothing proven).  ``exact`` is false when the answer is not a
    proof (then ``reason`` says why; an ``OPTIMAL`` that is not exact is only the best plan
    found).
    """

    status: Status
    cost: int | None
    plan: tuple[PlanStep, ...] | None
    exact: bool
    reason: str
    calls: int
    time_s: float


@dataclass(frozen=True)
class JointResult:
    """Outcome of ``JOINT(E, K, c)``.

    ``status``: ``PLAN`` (``plan``, ``robot_cost`` (minimal), ``human_cost`` set),
    ``INFEASIBLE`` (``core`` set: selector literals of the assumptions that alone rule out every
    joint plan within the bounds; ``frozenset()`` means no selection at all has one; ``None``
    from a search that gives no core), or ``LIMIT`` / ``TIMEOUT`` (nothing proven; ``plan`` is
    the best witness found so far, if any).  ``selection`` is the model ``human + E`` the human
    side was evaluated in (for a call on a partial assignment, the one the solver picked).
    ``exact`` as in :class:`OptResult`; an inexact core is only valid up to the horizon used
    (``horizon``; 0 for explicit search, which has none).  ``expanded``: the nodes an explicit
    search expanded (0 for SAT).
    """

    status: Status
    plan: tuple[PlanStep, ...] | None
    robot_cost: int | None
    human_cost: int | None
    core: frozenset[GuardLit] | None
    selection: frozenset[int] | None
    exact: bool
    reason: str
    horizon: int
    calls: int
    time_s: float
    expanded: int = 0
