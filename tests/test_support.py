"""Soundness of the exclusion cores of unsolvable models (``mega_sat.engines.support``)."""

from __future__ import annotations

import time

from helpers.sat_families import agreeing, dijkstra, families, selections
from hypothesis import HealthCheck, assume, given, settings
from hypothesis import strategies as st

from mega_sat.deadline import Deadline
from mega_sat.engines.support import unsolvable_core

SETTINGS = settings(
    max_examples=150, deadline=None, derandomize=True, suppress_health_check=list(HealthCheck)
)


@SETTINGS
@given(
    fam=families(max_atoms=4, max_actions=5, max_updates=4),
    data=st.data(),
    stop=st.sampled_from([None, "past"]),
)
def test_unsolvable_core_rules_out_only_unsolvable_models(fam, data, stop):
    """Every selection agreeing with ``selection`` on the returned updates has no plan (brute
    force); with the deadline already passed nothing is tried, so every update stays."""
    sel = data.draw(selections(fam.n_updates))
    assume(dijkstra(fam.specialize(sel)) is None)
    deadline = None if stop is None else Deadline(time.perf_counter())
    core = unsolvable_core(fam, sel, search_seconds=1.0, deadline=deadline)
    if stop is not None:
        assert core is None
        return
    if core is None:
        return  # nothing smaller than "all updates": the caller excludes the model alone
    lits = [(i, i in sel) for i in core]
    for other in agreeing(lits, fam.n_updates):
        assert dijkstra(fam.specialize(other)) is None, (sorted(core), sorted(other))
