"""Operator-counting lower bounds for the oracles, per partial assignment of the selectors.

The integer program of :mod:`mega_sat.analysis.operator_counting` on the two-fact abstraction
of a partial assignment bounds the cost of every plan of every model agreeing with it: OPT uses
it as a lower bound, JOINT's dominance cores to settle deletion trials without a horizon.
"""

from __future__ import annotations

import time
from collections.abc import Iterable

from mega_sat.analysis.abstraction import abstract_task
from mega_sat.analysis.operator_counting import operator_counting_bound
from mega_sat.ground.family import GroundFamily, GuardLit
from mega_sat.options import Options
from mega_sat.sat.solving import Solving
from mega_sat.sat.stats import OracleStats, add_seconds, bump


class CountingBounds:
    """Cached bounds, switched off for the task once they stop paying (see :meth:`on`)."""

    def __init__(
        self,
        family: GroundFamily,
        options: Options,
        enabled: bool,
        solving: Solving,
        stats: OracleStats,
    ):
        self.family = family
        self.options = options
        self.enabled = enabled
        self.solving = solving
        self.stats = stats
        self._cache: dict[frozenset[GuardLit], float | None] = {}
        self._tries = 0
        self._gains = 0

    def on(self) -> bool:
        """Whether bounds are still computed: not after ``counting_trials`` bounds none of
        which was above the bound the caller already had (where the integer program stays far
        below the plans' costs, each try only costs time)."""
        return self.enabled and (self._tries < self.options.counting_trials or self._gains > 0)

    def bound(self, lits: Iterable[GuardLit], above: float) -> float | None:
        """Lower bound on the cost of every plan of every ``human + E'`` agreeing with ``lits``
        (``inf``: none has a plan); ``None`` when unknown or switched off.  ``above``: the bound
        the caller has without it (to judge whether the bounds pay)."""
        key = frozenset(lits)
        if key in self._cache:
            return self._cache[key]
        if not self.on():
            return None
        t0 = time.perf_counter()
        sel = frozenset(i for i, v in key if v)
        task = abstract_task(self.family, sel, [i for i, _ in key])
        limit, left = self.options.counting_time_limit, self.solving.time_left()
        cut = left is not None and left < limit
        if cut:
            limit = max(left, 0.01)
        got = operator_counting_bound(task, time_limit=limit)
        # its work, for the OPT portfolio's referee: an integer program over the actions
        self.solving.side_work += self.options.race_states_per_lp_action * len(task.actions)
        if not (cut and got is None):  # a bound cut short by the deadline may be found later
            self._cache[key] = got
        self._tries += 1
        self._gains += got is not None and got > above
        self.stats.counting_calls = bump(self.stats.counting_calls)
        self.stats.counting_time_s = add_seconds(
            self.stats.counting_time_s, time.perf_counter() - t0
        )
        return got
