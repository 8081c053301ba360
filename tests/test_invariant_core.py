"""Unsolvable cores from IC3 invariants (mega_sat.sat.invariant_core), and IC3 alongside SAT
OPT's search for a first plan, against Dijkstra on random families and on a shipped model."""

from __future__ import annotations

from pathlib import Path

import pytest
from helpers.fuzzing import oracle_settings
from helpers.sat_families import agreeing, all_selections, dijkstra, families, selections
from hypothesis import given
from hypothesis import strategies as st

from mega_sat.ground.family import GroundAction, GroundFamily
from mega_sat.options import Options
from mega_sat.sat.invariant_core import InvariantCores, invariant_core
from mega_sat.sat.oracles import SatOracles
from mega_sat.search.pdr import Pdr
from mega_sat.status import Status

SETTINGS = oracle_settings(200)
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


def check_against_dijkstra(orc: SatOracles, fam: GroundFamily, sel: frozenset[int]) -> None:
    """OPT's answer for ``sel`` is Dijkstra's (a cost marked not exact may be above it), and
    an IC3 invariant is kept only for a model without a plan."""
    r, best = orc.opt(sel), dijkstra(fam.specialize(sel))
    if best is None:
        assert r.status == Status.UNSOLVABLE and r.exact
    else:
        assert r.status == Status.OPTIMAL and (r.cost == best or not r.exact)
    if orc.take_invariant(sel) is not None:
        assert best is None and "IC3" in r.reason


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
            check_against_dijkstra(orc, fam, data.draw(selections(fam.n_updates)))


@pytest.mark.parametrize("ic3_share", [25, 10**6])
@oracle_settings(300)
@given(fam=families(max_atoms=6, max_actions=8))
def test_side_proofs_in_turns_are_exact(ic3_share: int, fam: GroundFamily):
    """Once no plan fits one step, reachability and IC3 take turns from one state on (the
    probe alongside SAT never starts, operator counting is off so that more models get this
    far), with IC3's share as in the default and a thousand calls per state: on every
    selection the answer matches Dijkstra, and an invariant is kept only for a model without a
    plan."""
    opts = Options(
        opt_reachability_steps=1,
        opt_side_proof_states=1,
        opt_side_proof_ic3_per_1000=ic3_share,
        opt_reachability_conflicts=10**9,
        counting_trials=0,
    )
    with SatOracles(fam, options=opts) as orc:
        for sel in all_selections(fam.n_updates):
            check_against_dijkstra(orc, fam, sel)


def switches_and_latches(n: int) -> GroundFamily:
    """``n`` switches, free to turn on and off, and two latches: a latch is set while one
    switch is on and the other latch unset, and is never unset.  So the goal (both latches) is
    unreachable among ``3 * 2**n`` reachable states, every switch is relevant, the relaxation
    reaches the goal in two steps, and one clause (not both latches) is an invariant."""
    one = (((), 1),)
    acts = []
    for i in range(n):
        acts.append(GroundAction(f"on{i}", (), None, (), ((i, None),), ((i, None),), (), one))
        acts.append(GroundAction(f"off{i}", (), None, ((i, None),), (), (), ((i, None),), one))
        for latch, other in ((n, n + 1), (n + 1, n)):
            pre, negpre, add = ((i, None),), ((other, None),), ((latch, None),)
            acts.append(GroundAction(f"set{latch}-{i}", (), None, pre, negpre, add, (), one))
    atoms = tuple((f"p{i}",) for i in range(n + 2))
    return GroundFamily(atoms, 0, tuple(acts), (), ((n, None), (n + 1, None)))


@pytest.mark.parametrize("ic3", [True, False])
def test_side_proofs_take_turns(ic3: bool):
    """Switches and latches with 16 switches (196,608 states): in turns from 1,000 states,
    IC3's one clause proves "no plan" before the reachability check gets far; with IC3 off
    the check exhausts the states instead."""
    opts = Options(
        opt_reachability_steps=1, opt_side_proof_states=1000, opt_invariant_probe_rate=int(ic3)
    )
    with SatOracles(switches_and_latches(16), options=opts) as orc:
        r = orc.opt(frozenset())
        assert r.status == Status.UNSOLVABLE and r.exact
        how = "an inductive invariant (IC3)" if ic3 else "no reachable state satisfies"
        assert r.reason.startswith("no plan within 2 steps, and " + how)
        assert orc.stats.opt_by_invariant == (1 if ic3 else None)
        assert orc.stats.opt_by_reachability == (None if ic3 else 1)


def opt_with_record(opts: Options, kind: str, history: list[int] | None):
    """OPT of switches and latches (16 switches) with the side proof ``kind``'s record set
    to ``history`` first (None: a fresh one): the answer, and the record before and after."""
    with SatOracles(switches_and_latches(16), options=opts) as orc:
        record = orc.opt_oracle._side_yield
        if history is not None:
            record[kind] = list(history)
        before = list(record[kind])
        r = orc.opt(frozenset())
        assert r.status == Status.UNSOLVABLE and r.exact
        return r, before, record


@pytest.mark.parametrize(
    "history, floor, how",
    [
        (None, 0.0625, "an inductive invariant (IC3)"),
        ([0, 999], 0.001, "no reachable state satisfies"),
        ([0, 999], 1.0, "an inductive invariant (IC3)"),
    ],
)
def test_ic3_share_in_turns_follows_its_yield(history, floor, how):
    """Switches and latches with 16 switches, where IC3 wins the turns at its full share.
    After 999 OPT calls in which IC3 proved nothing, its share is 1/500 (floor 1/1000), and
    reachability exhausts the states first; ``opt_side_proof_min_share=1`` keeps the full share.
    Either way the answer is exact, and the call counts in IC3's record."""
    opts = Options(
        opt_reachability_steps=1, opt_side_proof_states=1000, opt_side_proof_min_share=floor
    )
    r, before, record = opt_with_record(opts, "ic3 turns", history)
    assert r.reason.startswith("no plan within 2 steps, and " + how)
    won = int(how.startswith("an inductive"))
    assert record["ic3 turns"] == [before[0] + won, before[1] + 1]
    assert record["probe"] == [0, 0]  # the probe never started


def test_side_share_formula():
    """Whole while a side proof ends about half of its calls or more, then falling with its
    yield down to ``opt_side_proof_min_share``, and never above 1."""
    with SatOracles(switches_and_latches(2), options=Options(opt_side_proof_min_share=0.1)) as orc:
        opt = orc.opt_oracle
        for record, share in (([0, 0], 1.0), ([5, 11], 1.0), ([1, 7], 0.5), ([0, 99], 0.1)):
            opt._side_yield["probe"] = record
            assert opt._side_share("probe") == share
    with SatOracles(switches_and_latches(2), options=Options(opt_side_proof_min_share=2.0)) as orc:
        orc.opt_oracle._side_yield["probe"] = [0, 99]
        assert orc.opt_oracle._side_share("probe") == 1.0  # a floor above 1 is the full rate


@pytest.mark.parametrize("history", [None, [0, 100]])
def test_probe_alongside_sat_follows_its_yield(history):
    """The probe alongside SAT (no turns: they start past 1000 steps) proves switches and
    latches unsolvable at its full rate, and still at a sixteenth of it; the call counts in
    the probe's record."""
    opts = Options(
        first_chunk=1,
        solve_chunk=1,
        opt_reachability_conflicts=0,
        opt_reachability_steps=1000,
        opt_reachability_probe_rate=10**5,
        opt_invariant_probe_rate=1000,
    )
    r, before, record = opt_with_record(opts, "probe", history)
    assert r.reason.endswith("(checked while SAT looked for a plan)")
    assert record["probe"] == [before[0] + 1, before[1] + 1]


class _Proven:
    """Stands in for IC3 after ``UNSOLVABLE``: only its invariant's cubes are read."""

    def __init__(self, *cubes):
        self.cubes = tuple(frozenset({c}) for c in cubes)

    def invariant(self):
        return self.cubes


def test_the_lemma_pool_keeps_the_latest_invariants():
    """The invariant that proved a model unsolvable goes to the loop and into the pool of
    IC3 seeds, most recent last, at most ``ic3_seed_lemmas`` cubes; 0 keeps none.  A proof in
    turns (switches and latches) fills the pool."""
    a, b, c, d = (0, True), (1, True), (2, False), (3, True)
    with SatOracles(switches_and_latches(2), options=Options(ic3_seed_lemmas=3)) as orc:
        opt = orc.opt_oracle
        opt._keep_invariant(frozenset({0}), _Proven(a, b))
        opt._keep_invariant(frozenset({1}), _Proven(c, a, d))
        assert list(opt._lemmas) == [frozenset({x}) for x in (c, a, d)]
        assert orc.take_invariant({0}) == _Proven(a, b).cubes
    with SatOracles(switches_and_latches(2), options=Options(ic3_seed_lemmas=0)) as orc:
        orc.opt_oracle._keep_invariant(frozenset(), _Proven(a))
        assert not orc.opt_oracle._lemmas
    opts = Options(opt_reachability_steps=1, opt_side_proof_states=1000)
    with SatOracles(switches_and_latches(16), options=opts) as orc:
        assert orc.opt(frozenset()).status == Status.UNSOLVABLE
        assert orc.opt_oracle._lemmas and orc.stats.opt_by_invariant == 1


def binary_counter(n: int) -> GroundFamily:
    """``n`` bits counting up from zero to all set: the only plan has ``2**n - 1`` steps, far
    more than the relaxation's lower bound."""
    one = (((), 1),)
    acts = []
    for i in range(n):
        low = tuple((j, None) for j in range(i))
        acts.append(GroundAction(f"inc{i}", (), None, low, ((i, None),), ((i, None),), low, one))
    goal = tuple((i, None) for i in range(n))
    return GroundFamily(tuple((f"b{i}",) for i in range(n)), 0, tuple(acts), (), goal)


@pytest.mark.parametrize("ic3_share", [0, 25, 10**6])
def test_side_proofs_leave_a_long_plan_to_sat(ic3_share: int):
    """A 5-bit counter: no plan fits the first horizons, and in the turns IC3 (with a
    thousand calls per state, first) or the reachability check finds that the goal is
    reachable, so SAT goes on to the 31-step plan."""
    opts = Options(
        opt_reachability_steps=1,
        opt_side_proof_states=1,
        opt_side_proof_ic3_per_1000=max(ic3_share, 1),
        opt_invariant_probe_rate=int(ic3_share > 0),
    )
    with SatOracles(binary_counter(5), options=opts) as orc:
        r = orc.opt(frozenset())
        assert r.status == Status.OPTIMAL and r.exact and r.cost == 31
        assert orc.take_invariant(frozenset()) is None


def test_ic3_in_turns_with_reachability_and_its_core_on_barman():
    """barman-bar Delta30 p3 with ten updates: no plan, no horizon up to the cap shows it and
    the 6.4 million reachable states are too many to exhaust; once no plan fits 32 steps, IC3
    in turns with the reachability check does (before the check reaches its 2 million states),
    and its invariant holds with all but a few of the 30 updates free (which few depends on the
    invariant found), where the may-reachability core frees none; with IC3 on its cut-short
    trials (the default), that core is small too."""
    from mega_sat.engines.support import unsolvable_core
    from mega_sat.ground.grounding import ground
    from mega_sat.pddl.loading import load_task_dir

    fam = ground(load_task_dir(ROOT / "domains/barman-bar/delta/30/p3"))
    sel = frozenset({0, 2, 3, 8, 9, 10, 14, 15, 17, 19})
    with SatOracles(fam) as orc:
        r = orc.opt(sel)
        assert r.status == Status.UNSOLVABLE and r.exact
        assert (
            r.reason
            == "no plan within 40 steps, and an inductive invariant (IC3) excludes the goal"
        )
        assert orc.stats.opt_by_invariant == 1 and orc.stats.opt_by_reachability is None
        cubes = orc.take_invariant(sel)
        assert orc.take_invariant(sel) is None  # handed over once
    assert cubes
    core = invariant_core(fam, sel, cubes)
    assert core is not None and len(core) <= 10
    assert unsolvable_core(fam, sel, ic3_queries=0) is None
    with_ic3 = unsolvable_core(fam, sel)
    assert with_ic3 is not None and len(with_ic3) <= 10
