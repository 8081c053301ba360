"""IC3 (mega_sat.search.pdr) against Dijkstra on random families, on a shipped model no
horizon proves unsolvable, and as OPT's last resort past the horizon cap."""

from __future__ import annotations

from pathlib import Path

from helpers.sat_families import dijkstra, families, selections
from hypothesis import HealthCheck, given, settings
from hypothesis import strategies as st

from mega_sat.ground.family import GroundFamily
from mega_sat.options import Options
from mega_sat.sat.oracles import SatOracles
from mega_sat.search.pdr import Pdr
from mega_sat.status import Status

SETTINGS = settings(
    max_examples=200, deadline=None, derandomize=True, suppress_health_check=list(HealthCheck)
)
ROOT = Path(__file__).resolve().parent.parent


@SETTINGS
@given(fam=families(), data=st.data())
def test_pdr_decides_exactly_the_models_with_no_plan(fam: GroundFamily, data):
    for _ in range(3):
        task = fam.specialize(data.draw(selections(fam.n_updates)))
        with Pdr(task) as pdr:
            verdict = pdr.run()
        assert verdict == (Status.UNSOLVABLE if dijkstra(task) is None else Status.PLAN)


@SETTINGS
@given(fam=families(), data=st.data())
def test_opt_past_the_cap_is_exact_or_says_it_is_not(fam: GroundFamily, data):
    """With a one-step horizon cap and a one-node fallback search, IC3 proves every model
    with no plan unsolvable; a model with a longer plan gets SAT's best effort or is left
    undecided, marked not exact either way."""
    opts = Options(horizon_cap=1, fallback_node_limit=1, opt_reachability_steps=1000)
    with SatOracles(fam, options=opts) as orc:
        for _ in range(3):
            sel = data.draw(selections(fam.n_updates))
            r, best = orc.opt(sel), dijkstra(fam.specialize(sel))
            if best is None:
                assert r.status == Status.UNSOLVABLE and r.exact
            elif r.status == Status.OPTIMAL:  # SAT at the cap: a plan, proven or marked not
                assert r.cost == best if r.exact else r.cost >= best
            else:
                assert r.status == Status.LIMIT and not r.exact and "IC3 gave plan" in r.reason


def _usar_delta30_p2() -> GroundFamily:
    from mega_sat.ground.grounding import ground
    from mega_sat.pddl.loading import load_task_dir

    return ground(load_task_dir(ROOT / "domains" / "usar-fetch" / "delta" / "30" / "p2"))


def test_opt_proves_unsolvable_by_an_invariant_past_the_cap():
    """usar-fetch Delta30 p2 with updates {19, 20} (a photo stays taken only while a robot
    stays, and the goal sends every robot away): with a 4-step cap, no reachability check and
    a 10-node fallback search, only the invariant decides; within one SAT call it cannot."""
    fam = _usar_delta30_p2()
    sel = frozenset({19, 20})
    slow = dict(horizon_cap=4, fallback_node_limit=10, opt_reachability_steps=1000)
    slow["opt_reachability_conflicts"] = 10**9
    with SatOracles(fam, options=Options(**slow)) as orc:
        r = orc.opt(sel)
        assert r.status == Status.UNSOLVABLE and r.exact and "IC3" in r.reason
        assert orc.stats.opt_by_invariant == 1
    with SatOracles(fam, options=Options(**slow, pdr_queries=1)) as orc:
        r = orc.opt(sel)
        assert r.status == Status.LIMIT and not r.exact and "IC3 gave limit" in r.reason
    with Pdr(fam.specialize(frozenset({4}))) as pdr:  # a model with a plan
        assert pdr.run() == Status.PLAN
