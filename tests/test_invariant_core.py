"""Unsolvable cores from IC3 invariants (mega_sat.sat.invariant_core), and IC3 alongside SAT
OPT's search for a first plan, against Dijkstra on random families and on a shipped model."""

from __future__ import annotations

from pathlib import Path

from helpers.sat_families import agreeing, dijkstra, families, selections
from hypothesis import HealthCheck, given, settings
from hypothesis import strategies as st

from mega_sat.ground.family import GroundFamily
from mega_sat.options import Options
from mega_sat.sat.invariant_core import InvariantCores, invariant_core
from mega_sat.sat.oracles import SatOracles
from mega_sat.search.pdr import Pdr
from mega_sat.status import Status

SETTINGS = settings(
    max_examples=200, deadline=None, derandomize=True, suppress_health_check=list(HealthCheck)
)
ROOT = Path(__file__).resolve().parent.parent


@SETTINGS
@given(fam=families(), data=st.data())
def test_invariant_cores_exclude_only_models_without_a_plan(fam: GroundFamily, data):
    # one solver for several invariants (as in the loop), and a fresh one per invariant
    with InvariantCores(fam) as shared:
        for _ in range(3):
            sel = data.draw(selections(fam.n_updates))
            with Pdr(fam.specialize(sel)) as pdr:
                if pdr.run() != Status.UNSOLVABLE:
                    continue
                cubes = pdr.invariant()
            for core in (shared.core(sel, cubes), invariant_core(fam, sel, cubes)):
                # the invariant is one of human + sel itself: with every update fixed it passes
                assert core is not None
                for other in agreeing([(i, i in sel) for i in core], fam.n_updates):
                    assert dijkstra(fam.specialize(other)) is None


@SETTINGS
@given(fam=families(), data=st.data())
def test_ic3_alongside_sat_is_exact(fam: GroundFamily, data):
    """Chunks of one conflict and no reachability check: IC3 runs between every two chunks
    of the first-plan search, so wherever SAT needs a conflict it is the one to answer."""
    opts = Options(
        first_chunk=1,
        solve_chunk=1,
        opt_reachability_conflicts=0,
        opt_reachability_probe_rate=0,
        opt_reachability_steps=1000,
        opt_invariant_probe_rate=1000,
    )
    with SatOracles(fam, options=opts) as orc:
        for _ in range(3):
            sel = data.draw(selections(fam.n_updates))
            r, best = orc.opt(sel), dijkstra(fam.specialize(sel))
            if best is None:
                assert r.status == Status.UNSOLVABLE and r.exact
            else:
                assert r.status == Status.OPTIMAL and (r.cost == best or not r.exact)
            if orc.take_invariant(sel) is not None:
                assert best is None and "IC3" in r.reason


def test_ic3_alongside_sat_and_its_core_on_barman():
    """barman-bar Delta30 p3 with ten updates: no plan, no horizon up to the cap shows it and
    the reachable states are too many to exhaust; IC3 alongside SAT does, and its invariant
    holds with all but a few of the 30 updates free (which few depends on the invariant found),
    where the may-reachability core frees none."""
    from mega_sat.engines.support import unsolvable_core
    from mega_sat.ground.grounding import ground
    from mega_sat.pddl.loading import load_task_dir

    fam = ground(load_task_dir(ROOT / "domains/barman-bar/delta/30/p3"))
    sel = frozenset({0, 2, 3, 8, 9, 10, 14, 15, 17, 19})
    with SatOracles(fam) as orc:
        r = orc.opt(sel)
        assert r.status == Status.UNSOLVABLE and r.exact
        assert "IC3" in r.reason and "while SAT looked for a plan" in r.reason
        cubes = orc.take_invariant(sel)
        assert orc.take_invariant(sel) is None  # handed over once
    assert cubes
    core = invariant_core(fam, sel, cubes)
    assert core is not None and len(core) <= 10
    assert unsolvable_core(fam, sel) is None
