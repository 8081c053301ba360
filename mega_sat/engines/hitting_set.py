"""Minimum-cost hitting sets over learned clauses: the search over subsets of Delta.

The SAT engine asks, again and again, for a cheapest explanation ``E`` (a set of update
indices; its cost is the sum of its updates' costs, ``|E|`` when every update costs 1) that
satisfies every clause learned so far.  A learned clause is a list of guard
literals ``(i, v)`` ("update i is selected" if ``v``), at least one of which must hold.  Two
interchangeable back ends, both exact: RC2 MaxSAT (python-sat) and an ILP solved by CBC (PuLP).
Both keep every clause; RC2 also keeps its solver alive between calls.
"""

from __future__ import annotations

import warnings
from collections.abc import Iterable, Sequence

from mega_sat.deadline import NO_DEADLINE, Deadline, TimeLimitReached
from mega_sat.errors import PlannerError
from mega_sat.ground.family import GuardLit

Clause = tuple[GuardLit, ...]


class HittingSetSolver:
    """Interface: ``add(clause)`` and ``minimum()`` (``None`` when no selection is left).

    ``costs``: a positive integer cost per update (``None``: every update costs 1); the
    minimum is over the sum of the selected updates' costs.
    """

    name = "abstract"

    def __init__(self, n_updates: int, costs: Sequence[int] | None = None):
        self.n = n_updates
        self.costs = tuple(costs) if costs is not None else (1,) * n_updates
        if len(self.costs) != n_updates or any(c <= 0 for c in self.costs):
            raise ValueError("one positive cost per update")
        self.clauses: list[Clause] = []
        self.calls = 0

    def add(self, clause: Iterable[GuardLit]) -> None:
        self.clauses.append(tuple(sorted(set(clause))))

    def minimum(self) -> frozenset[int] | None:
        raise NotImplementedError

    @staticmethod
    def satisfies(selection: frozenset[int], clause: Sequence[GuardLit]) -> bool:
        return any((i in selection) == v for i, v in clause)


class RC2HittingSet(HittingSetSolver):
    """Weighted partial MaxSAT with RC2: hard learned clauses, soft unit clauses ``not e_i``."""

    name = "rc2"

    def __init__(self, n_updates: int, costs: Sequence[int] | None = None):
        super().__init__(n_updates, costs)
        from pysat.examples.rc2 import RC2
        from pysat.formula import WCNF

        w = WCNF()
        for i in range(n_updates):
            w.append([-(i + 1)], weight=self.costs[i])
        self._rc2 = RC2(w)
        self._unsat = False

    def add(self, clause: Iterable[GuardLit]) -> None:
        super().add(clause)
        lits = [(i + 1) if v else -(i + 1) for i, v in self.clauses[-1]]
        if not lits:
            self._unsat = True
            return
        self._rc2.add_clause(lits)

    def minimum(self) -> frozenset[int] | None:
        self.calls += 1
        if self._unsat:
            return None
        model = self._rc2.compute()
        if model is None:
            self._unsat = True
            return None
        return frozenset(v - 1 for v in model if 0 < v <= self.n)

    def close(self) -> None:
        self._rc2.delete()


class ILPHittingSet(HittingSetSolver):
    """0/1 ILP solved by CBC through PuLP: ``min sum cost_i x_i`` s.t. every clause is hit.

    CBC gets the time left before ``deadline``; a solve it cuts short raises
    :class:`TimeLimitReached` (a hitting set that is not proven minimum would break the loop's
    argument, and "no solution found in time" is not "no selection left").
    """

    name = "ilp"

    def __init__(
        self, n_updates: int, deadline: Deadline | None = None, costs: Sequence[int] | None = None
    ):
        super().__init__(n_updates, costs)
        self.deadline = deadline if deadline is not None else NO_DEADLINE

    def minimum(self) -> frozenset[int] | None:
        import pulp

        from mega_sat.analysis.cbc import solve_cbc

        self.calls += 1
        if any(len(c) == 0 for c in self.clauses):
            return None
        self.deadline.check()
        with warnings.catch_warnings():
            # PuLP 3.x announces API changes for 4.0 on every call; the calls below work in both
            warnings.simplefilter("ignore", DeprecationWarning)
            prob = pulp.LpProblem("hitting_set", pulp.LpMinimize)
            x = [pulp.LpVariable(f"e{i}", cat="Binary") for i in range(self.n)]
            prob += pulp.lpSum(c * xi for c, xi in zip(self.costs, x, strict=True)) if x else 0
            for c in self.clauses:
                prob += pulp.lpSum(x[i] if v else 1 - x[i] for i, v in c) >= 1
        status = solve_cbc(prob, time_limit=self.deadline.remaining(), gapRel=0)
        if self.deadline.expired() and prob.sol_status != pulp.LpSolutionOptimal:
            # past the deadline only a proven optimum is used (solve_cbc already keeps a
            # cut-short "infeasible" from counting)
            raise TimeLimitReached(self.deadline.seconds)
        if status == pulp.LpStatusInfeasible:
            return None
        if status == pulp.LpStatusOptimal and prob.sol_status == pulp.LpSolutionOptimal:
            return frozenset(i for i in range(self.n) if (x[i].value() or 0) > 0.5)
        if self.deadline.expired():
            raise TimeLimitReached(self.deadline.seconds)
        raise PlannerError(f"CBC did not solve the hitting-set ILP ({pulp.LpStatus[status]})")

    def close(self) -> None:
        pass


BACKENDS = {"rc2": RC2HittingSet, "ilp": ILPHittingSet}


def make_hitting_set(
    kind: str,
    n_updates: int,
    *,
    deadline: Deadline | None = None,
    costs: Sequence[int] | None = None,
) -> HittingSetSolver:
    """A hitting-set solver minimising the sum of ``costs`` (1 per update when ``None``); CBC
    (``ilp``) runs within ``deadline`` (RC2's SAT calls cannot be cut short; the loop checks
    the deadline around them)."""
    if kind == "ilp":
        return ILPHittingSet(n_updates, deadline, costs)
    try:
        return BACKENDS[kind](n_updates, costs)
    except KeyError:
        raise ValueError(f"unknown hitting-set solver {kind!r} (choose from rc2, ilp)") from None
