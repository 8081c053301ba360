"""The may-reachable states and the unsolvable cores built on them, against explicit-state
ground truth on random families (tests/helpers/sat_families.py)."""

from __future__ import annotations

from pathlib import Path

import pytest
from helpers.fuzzing import oracle_settings
from helpers.sat_families import _succ, agreeing, dijkstra, families, selections
from hypothesis import given
from hypothesis import strategies as st

from mega_sat.analysis.abstraction import abstract_task
from mega_sat.analysis.pair_reachability import goal_pair_unreachable
from mega_sat.engines.support import unsolvable_core
from mega_sat.ground.family import GroundFamily
from mega_sat.search.may_reachability import MayReachability
from mega_sat.status import Status

SETTINGS = oracle_settings(200)


def _reachable(fam: GroundFamily, sel: frozenset[int]) -> set[frozenset[int]]:
    task = fam.specialize(sel)
    seen = {frozenset(task.init)}
    todo = list(seen)
    while todo:
        for _, t in _succ(task, todo.pop()):
            if t not in seen:
                seen.add(t)
                todo.append(t)
    return seen


def _seen_by(may: MayReachability, states: set[frozenset[int]]) -> set[frozenset[int]]:
    """``states`` as ``may`` keeps them: on the atoms relevant in some model, and constants."""
    keep = set(may.pos) | may.constant_true
    return {s & keep for s in states}


def _subsets(n: int):
    return st.frozensets(st.integers(0, n - 1), max_size=n) if n else st.just(frozenset())


@SETTINGS
@given(fam=families(max_atoms=5, max_actions=7), data=st.data())
def test_may_states_hold_every_agreeing_model_and_a_proof_is_sound(fam: GroundFamily, data):
    sel = data.draw(selections(fam.n_updates))
    may = MayReachability(fam, sel, node_limit=10_000)
    # the model's own reachable states, exhausted: ok exactly when it has no plan
    assert may.ok == (dijkstra(fam.specialize(sel)) is None)
    if not may.ok:
        return
    assert may.reached() == _seen_by(may, _reachable(fam, sel))
    first = data.draw(_subsets(fam.n_updates))
    second = data.draw(_subsets(fam.n_updates))
    for free in (first, second):
        before = may.reached()
        verdict = may.try_free(free)
        others = agreeing([(i, i in sel) for i in range(fam.n_updates) if i not in free],
                          fam.n_updates)  # fmt: skip
        if verdict != Status.UNSOLVABLE:
            assert verdict == Status.PLAN  # tiny tasks never reach a limit
            assert may.reached() == before  # a failed trial changes nothing
            # the coarser pair abstraction reaches the goal too (unsolvable_core skips it)
            fixed = set(range(fam.n_updates)) - may.free - free
            assert not goal_pair_unreachable(abstract_task(fam, sel, fixed))
            break
        # every agreeing model: no plan, and its reachable states inside R
        for other in others:
            assert dijkstra(fam.specialize(other)) is None
            assert _seen_by(may, _reachable(fam, other)) <= may.reached()
        assert may.free >= free
    if may.free:
        # R grown step by step is R for the final free set, computed at once
        fresh = MayReachability(fam, sel, node_limit=10_000)
        assert fresh.try_free(may.free) == Status.UNSOLVABLE
        assert fresh.reached() == may.reached()


@SETTINGS
@given(fam=families(max_atoms=5, max_actions=7), data=st.data())
def test_unsolvable_cores_exclude_only_unsolvable_models(fam: GroundFamily, data):
    sel = data.draw(selections(fam.n_updates))
    if dijkstra(fam.specialize(sel)) is not None:
        return
    core = unsolvable_core(
        fam,
        sel,
        work_limit=data.draw(st.sampled_from([None, 0, 3, 30])),
        trial_limit=data.draw(st.sampled_from([None, 0, 5])),
    )
    on = range(fam.n_updates) if core is None else core
    for other in agreeing([(i, i in sel) for i in on], fam.n_updates):
        assert dijkstra(fam.specialize(other)) is None


@SETTINGS
@given(fam=families(max_atoms=5, max_actions=7), data=st.data())
def test_ic3_on_the_abstraction_proves_only_unsolvable_models(fam: GroundFamily, data):
    """The proof ``unsolvable_core``'s ``ic3_queries`` adds: IC3 finding the abstraction
    with ``fixed`` updates unsolvable means every model agreeing on them has no plan."""
    from mega_sat.search.pdr import Pdr

    sel = data.draw(selections(fam.n_updates))
    fixed = data.draw(_subsets(fam.n_updates))
    with Pdr(abstract_task(fam, sel, fixed)) as pdr:
        verdict = pdr.run()
    others = agreeing([(i, i in sel) for i in fixed], fam.n_updates)
    if verdict == Status.UNSOLVABLE:
        assert all(dijkstra(fam.specialize(o)) is None for o in others)
    else:
        assert verdict == Status.PLAN


def test_ic3_shrinks_the_cores_the_states_cannot():
    """rover-martian Delta30 p2, the unsolvable model {1, 2, 6, 8, 14, 15}: its may-reachable
    states run past their limits on 14 trials and the core keeps 14 updates; IC3 on those
    trials' abstractions drops half of them.  The abstraction that fixes only the smaller
    core has no plan (so every model agreeing on it has none)."""
    from mega_sat.ground.grounding import ground
    from mega_sat.pddl.loading import load_task_dir
    from mega_sat.search.pdr import Pdr

    root = Path(__file__).resolve().parent.parent
    fam = ground(load_task_dir(root / "domains/rover-martian/delta/30/p2"))
    sel = frozenset({1, 2, 6, 8, 14, 15})
    kw = dict(work_limit=300_000, trial_limit=50_000)
    without = unsolvable_core(fam, sel, **kw, ic3_queries=0)
    with_ic3 = unsolvable_core(fam, sel, **kw, ic3_queries=5000)
    assert without is not None and with_ic3 is not None
    assert len(with_ic3) <= len(without) // 2
    with Pdr(abstract_task(fam, sel, with_ic3)) as pdr:
        assert pdr.run() == Status.UNSOLVABLE


def test_ic3_in_a_core_starts_from_the_last_invariant(monkeypatch):
    """The same model: each IC3 run of the core after a proof starts from that proof's
    invariant, and the proofs after the first take a small share of the first's SAT calls
    (without the seed each takes as many as the first)."""
    from mega_sat.ground.grounding import ground
    from mega_sat.pddl.loading import load_task_dir
    from mega_sat.search import pdr as pdr_module

    runs: list[tuple[int, tuple, Status, int]] = []  # (seeded cubes, invariant, verdict, calls)
    real_seed, real_run = pdr_module.Pdr.seed, pdr_module.Pdr.run

    def seed(self, cubes):
        self.seeded = tuple(cubes)
        return real_seed(self, cubes)

    def run(self, query_limit=None, deadline=None):
        verdict = real_run(self, query_limit, deadline)
        inv = self.invariant() if verdict == Status.UNSOLVABLE else ()
        runs.append((getattr(self, "seeded", ()), inv, verdict, self.queries))
        return verdict

    monkeypatch.setattr(pdr_module.Pdr, "seed", seed)
    monkeypatch.setattr(pdr_module.Pdr, "run", run)
    root = Path(__file__).resolve().parent.parent
    fam = ground(load_task_dir(root / "domains/rover-martian/delta/30/p2"))
    sel = frozenset({1, 2, 6, 8, 14, 15})
    unsolvable_core(fam, sel, work_limit=300_000, trial_limit=50_000, ic3_queries=5000)
    proofs = [k for k, r in enumerate(runs) if r[2] == Status.UNSOLVABLE]
    assert len(proofs) >= 4
    assert runs[proofs[0]][0] == ()  # nothing to start from yet
    last = ()
    for seeded, inv, verdict, _ in runs:
        assert seeded == last
        last = inv if verdict == Status.UNSOLVABLE else last
    first = runs[proofs[0]][3]
    assert all(runs[k][3] * 5 <= first for k in proofs[1:])


def test_ic3_stops_for_the_run_after_misses_in_a_row(monkeypatch):
    """``Ic3Streak``: runs at their limit count, a proof resets the count, a plan changes
    nothing; once closed, a core tries no IC3 and is the core without it."""
    from mega_sat.engines.support import Ic3Streak
    from mega_sat.ground.grounding import ground
    from mega_sat.pddl.loading import load_task_dir
    from mega_sat.search import pdr as pdr_module

    streak = Ic3Streak(2)
    for verdict in (Status.LIMIT, Status.PLAN, Status.UNSOLVABLE, Status.LIMIT):
        streak.record(verdict)
    assert streak.misses == 1 and streak.open()
    streak.record(Status.LIMIT)
    assert not streak.open()
    assert Ic3Streak(0).open()  # 0: never stops

    runs: list[int] = []
    real_run = pdr_module.Pdr.run
    monkeypatch.setattr(
        pdr_module.Pdr, "run", lambda self, *a, **k: runs.append(1) or real_run(self, *a, **k)
    )
    root = Path(__file__).resolve().parent.parent
    fam = ground(load_task_dir(root / "domains/rover-martian/delta/30/p2"))
    sel = frozenset({1, 2, 6, 8, 14, 15})
    kw = dict(work_limit=300_000, trial_limit=50_000)
    closed = unsolvable_core(fam, sel, **kw, ic3_queries=5000, ic3_streak=streak)
    assert runs == []
    assert closed == unsolvable_core(fam, sel, **kw, ic3_queries=0)


def test_the_loop_shares_one_streak_across_its_cores(monkeypatch):
    """The options reach every unsolvable core of a run, with one ``Ic3Streak`` for all."""
    from mega_sat.api import MegaSolver
    from mega_sat.engines import sat_loop
    from mega_sat.options import Options
    from mega_sat.pddl.loading import load_task_dir

    seen: list[dict] = []
    real = sat_loop.unsolvable_core

    def spy(*args, **kwargs):
        seen.append(kwargs)
        return real(*args, **kwargs)

    monkeypatch.setattr(sat_loop, "unsolvable_core", spy)
    root = Path(__file__).resolve().parent.parent
    task = load_task_dir(root / "domains/usar-fetch/delta/20/p1")
    # the hitting-set loop's cores (this task has 20 updates: the counterexample loop's)
    opts = Options(
        unsolvable_core_ic3_queries=700,
        unsolvable_core_ic3_misses=3,
        counterexample_loop_updates=0,
    )
    assert MegaSolver(task, options=opts).frontier().exact
    assert len(seen) >= 2
    assert {k["ic3_queries"] for k in seen} == {700}
    assert len({id(k["ic3_streak"]) for k in seen}) == 1
    assert seen[0]["ic3_streak"].limit == 3


@SETTINGS
@given(fam=families(max_atoms=5, max_actions=7), data=st.data())
def test_seeded_ic3_gives_the_verdict_of_ic3_alone(fam: GroundFamily, data):
    """IC3 on an abstraction started from the invariant of a coarser trial's abstraction (it
    fixes more updates) answers as IC3 from nothing does, on random families."""
    from mega_sat.search.pdr import Pdr

    sel = data.draw(selections(fam.n_updates))
    fixed = data.draw(_subsets(fam.n_updates))
    fewer = data.draw(st.sets(st.sampled_from(sorted(fixed))) if fixed else st.just(set()))
    trial = frozenset(fixed) - frozenset(fewer)
    with Pdr(abstract_task(fam, sel, fixed)) as pdr:
        if pdr.run() != Status.UNSOLVABLE:
            return
        cubes = pdr.invariant()
    with Pdr(abstract_task(fam, sel, trial)) as alone:
        expected = alone.run()
    with Pdr(abstract_task(fam, sel, trial)) as seeded:
        seeded.seed(cubes)
        assert seeded.run() == expected
    if expected == Status.UNSOLVABLE:
        others = agreeing([(i, i in sel) for i in trial], fam.n_updates)
        assert all(dijkstra(fam.specialize(o)) is None for o in others)


@SETTINGS
@given(fam=families(max_atoms=5, max_actions=7), data=st.data())
def test_a_state_limit_changes_the_verdict_only_to_limit(fam: GroundFamily, data):
    sel = data.draw(selections(fam.n_updates))
    free = data.draw(_subsets(fam.n_updates))
    unlimited = MayReachability(fam, sel, node_limit=10_000)
    if not unlimited.ok:
        return
    verdict = unlimited.try_free(free)
    limit = data.draw(st.integers(0, len(unlimited.states) + 1))
    limited = MayReachability(fam, sel, node_limit=limit)
    if not limited.ok:
        assert len(_seen_by(limited, _reachable(fam, sel))) > limit
        return
    got = limited.try_free(free)
    if verdict == Status.UNSOLVABLE:
        fits = len(unlimited.states) <= limit
        assert got == (Status.UNSOLVABLE if fits else Status.LIMIT)
        own = _seen_by(limited, _reachable(fam, sel))
        assert limited.reached() == (unlimited.reached() if fits else own)
    else:
        assert got in (Status.PLAN, Status.LIMIT)
        assert limited.reached() == _seen_by(limited, _reachable(fam, sel))


@SETTINGS
@given(fam=families(max_atoms=5, max_actions=7), data=st.data())
def test_work_and_trial_limits_change_the_verdict_only_to_limit(fam: GroundFamily, data):
    """The work counts the states trials add to R (not R's own); one trial may add at most
    ``max(growth * |R|, trial_limit)``.  A trial that needs more fails and changes nothing; one
    that adds no state succeeds even with no work left."""
    sel = data.draw(selections(fam.n_updates))
    free = data.draw(_subsets(fam.n_updates))
    unlimited = MayReachability(fam, sel, node_limit=10_000)
    if not unlimited.ok:
        return
    own, n_own = unlimited.reached(), len(unlimited.states)
    verdict = unlimited.try_free(free)
    added = len(unlimited.states) - n_own
    # limits around the states the trial needs, where an off-by-one would show
    around = st.sampled_from(sorted({0, max(added - 1, 0), added, added + 1}))
    work, trial = data.draw(around), data.draw(around)
    growth = data.draw(st.sampled_from([0, 1, 3]))
    limited = MayReachability(
        fam, sel, node_limit=10_000, work_limit=work, trial_limit=trial, trial_growth=growth
    )
    assert limited.ok and limited.reached() == own
    got = limited.try_free(free)
    if verdict == Status.UNSOLVABLE:
        fits = added <= work and added <= max(growth * n_own, trial)
        assert got == (Status.UNSOLVABLE if fits else Status.LIMIT)
        assert limited.reached() == (unlimited.reached() if fits else own)
    else:
        assert got in (Status.PLAN, Status.LIMIT)
        assert limited.reached() == own


def _four_switches() -> GroundFamily:
    """Four switches that only update 0 lets the agent turn on (R grows from 1 state to 16
    when it is free) and a ``finish`` action, guarded by update 1, that needs all four for the
    goal: with neither update the model has no plan, freeing update 1 adds no state."""
    from mega_sat.ground.family import GroundAction

    def act(name, pre, add, exists):
        return GroundAction(name, (), exists, tuple((p, None) for p in pre), (),
                            tuple((p, None) for p in add), (), (((), 1),))  # fmt: skip

    switches = [act(f"on{k}", [], [k], (0, True)) for k in range(4)]
    finish = act("finish", range(4), [4], (1, True))
    atoms = tuple((f"on{k}",) for k in range(4)) + (("done",),)
    return GroundFamily(atoms, 2, (*switches, finish), (), ((4, None),))


@pytest.mark.parametrize("growth", [0, 1, 14, 15])
@pytest.mark.parametrize("trial", [None, 0, 14, 15])
@pytest.mark.parametrize("work", [None, 0, 14, 15])
def test_limits_on_a_trial_that_adds_fifteen_states(work, trial, growth):
    fam = _four_switches()
    limits = {"work_limit": work, "trial_limit": trial, "trial_growth": growth}
    may = MayReachability(fam, frozenset(), node_limit=100, **limits)
    assert may.ok and len(may.states) == 1
    fits = (work is None or work >= 15) and (trial is None or max(growth, trial) >= 15)
    assert may.try_free([0]) == (Status.UNSOLVABLE if fits else Status.LIMIT)
    assert len(may.states) == (16 if fits else 1)
    # freeing update 1 alone adds no state: it succeeds whatever work is left
    other = MayReachability(fam, frozenset(), node_limit=100, **limits)
    assert other.try_free([1]) == Status.UNSOLVABLE and len(other.states) == 1


def _padded(fam: GroundFamily, pad: int = 70) -> GroundFamily:
    """``fam`` with ``pad`` more goal atoms that one unconditional action sets together: every
    reachable state comes in two copies (without and with them) and takes two words, and the
    goal is reachable exactly when it was (the action can always come last)."""
    from dataclasses import replace

    from mega_sat.ground.family import GroundAction

    n = len(fam.atoms)
    atoms = fam.atoms + tuple((f"pad{k}",) for k in range(pad))
    fill = GroundAction("fill", (), None, (), (), tuple((n + k, None) for k in range(pad)), (),
                        (((), 1),))  # fmt: skip
    goal = fam.goal + tuple((n + k, None) for k in range(pad))
    return replace(fam, atoms=atoms, actions=(*fam.actions, fill), goal=goal)


@SETTINGS
@given(fam=families(max_atoms=5, max_actions=7), data=st.data())
def test_states_wider_than_a_word_give_the_same_verdicts(fam: GroundFamily, data):
    sel = data.draw(selections(fam.n_updates))
    narrow = MayReachability(fam, sel, node_limit=10_000)
    wide = MayReachability(_padded(fam), sel, node_limit=10_000)
    assert wide.n_words == 2
    assert wide.ok == narrow.ok
    if not narrow.ok:
        return
    for free in (data.draw(_subsets(fam.n_updates)), data.draw(_subsets(fam.n_updates))):
        assert wide.try_free(free) == narrow.try_free(free)
        assert len(wide.states) == 2 * len(narrow.states)
