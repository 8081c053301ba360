"""IC3 (mega_sat.search.pdr) against Dijkstra on random families, on a shipped model no
horizon proves unsolvable, and as OPT's last resort past the horizon cap."""

from __future__ import annotations

import itertools
from pathlib import Path

from helpers.fuzzing import oracle_settings
from helpers.sat_families import all_selections, dijkstra, families, selections
from hypothesis import given
from hypothesis import strategies as st

from mega_sat.ground.family import GroundFamily
from mega_sat.options import Options
from mega_sat.sat.oracles import SatOracles
from mega_sat.search.pdr import Pdr
from mega_sat.status import Status

SETTINGS = oracle_settings(200)
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
def test_an_obligation_is_the_regression_of_its_cube_through_the_step(fam: GroundFamily, data):
    """A predecessor found for a cube is not the model's one state but the regression of the
    cube through the model's action: that action's conditions and the cube's literals it
    leaves alone. It holds the initial state (the state the level-1 query started from),
    every state in it reaches the cube, and it is exactly one action's regression."""
    task = fam.specialize(data.draw(selections(fam.n_updates)))
    with Pdr(task) as pdr:
        rel = pdr.task
        if not rel.atoms:
            return
        cube = data.draw(cubes(len(rel.atoms)))
        found, got = pdr._predecessor(cube, 1)
    if not found:
        return
    init = set(rel.init)

    def holds(c, state) -> bool:
        return all((p in state) == v for p, v in c)

    def step(a, state):
        return (state - a.delete) | a.add

    assert holds(got, init)
    assert any(
        got
        == {(p, v) for p, v in cube if p not in a.add | a.delete}
        | {(p, True) for p in a.pre}
        | {(p, False) for p in a.negpre}
        and holds(cube, step(a, init))
        for a in rel.actions
    )
    free = sorted(set(range(len(rel.atoms))) - {p for p, _ in got})
    fixed = {p for p, v in got if v}
    for bits in itertools.product((False, True), repeat=len(free)):
        state = fixed | {p for p, b in zip(free, bits, strict=True) if b}
        assert any(
            a.pre <= state and not (a.negpre & state) and holds(cube, step(a, state))
            for a in rel.actions
        )


def test_an_obligation_that_holds_the_initial_state_is_a_plan():
    """Atoms a, g; initially a; one action needs a, adds g and deletes a.  An obligation on g
    at level 2 regresses to "a holds", which the initial state is in: the goal is reachable.
    Blocking that cube at level 1 instead (the initial state has no successor with a) would
    exclude the initial state from F_1."""
    from mega_sat.deadline import NO_DEADLINE
    from mega_sat.ground.family import GroundTask, StripsAction

    go = StripsAction(0, "go", (), frozenset({0}), frozenset(), frozenset({1}), frozenset({0}), 1)
    task = GroundTask(("a", "g"), (go,), frozenset({0}), frozenset({1}))
    with Pdr(task) as pdr:
        pdr._new_level()
        pdr._new_level()
        assert pdr._block(frozenset({(1, True)}), 2, None, NO_DEADLINE) == Status.PLAN


@st.composite
def cubes(draw, n_atoms: int):
    """A random cube over ``n_atoms`` atoms: mostly wrong lemmas, some right ones."""
    atoms = draw(st.sets(st.integers(0, n_atoms - 1), min_size=1, max_size=n_atoms))
    return frozenset((p, draw(st.booleans())) for p in atoms)


@SETTINGS
@given(fam=families(), data=st.data())
def test_seeded_lemmas_never_change_the_verdict(fam: GroundFamily, data):
    """IC3 seeded with random cubes (most are not lemmas of the model) and with the
    invariants of the family's other unsolvable models decides exactly the models with no
    plan; a seeded cube is never one some state within one step is in."""
    n = len(fam.atoms)
    pool = list(data.draw(st.lists(cubes(n), max_size=8)))
    for sel in itertools.islice(all_selections(fam.n_updates), 8):
        task = fam.specialize(sel)
        with Pdr(task) as pdr:
            added = pdr.seed(pool)
            seeded = [c for level in pdr._frames for c in level]
            verdict = pdr.run()
            if verdict == Status.UNSOLVABLE:
                pool.extend(pdr.invariant())
        assert added == len(seeded) <= len(pool)
        assert verdict == (Status.UNSOLVABLE if dijkstra(task) is None else Status.PLAN)
        states_within_one = {frozenset(task.init)} | {
            frozenset((set(task.init) - a.delete) | a.add)
            for a in task.actions
            if a.pre <= set(task.init) and not (a.negpre & set(task.init))
        }
        for cube in seeded:
            assert not any(all((p in s) == v for p, v in cube) for s in states_within_one)


def test_lemmas_of_a_neighbour_model_save_most_queries():
    """barman-bar Delta30 p3: two models without a plan that differ in two updates (1 and 2
    swapped).  IC3 on the second needs 8,317 queries from nothing, and 1,271 when seeded
    with the first one's invariant, nearly all of whose clauses carry over."""
    from mega_sat.ground.grounding import ground
    from mega_sat.pddl.loading import load_task_dir

    fam = ground(load_task_dir(ROOT / "domains/barman-bar/delta/30/p3"))
    first = fam.specialize(frozenset({0, 2, 3, 8, 9, 10, 14, 15, 17, 19}))
    second = fam.specialize(frozenset({0, 1, 3, 8, 9, 10, 14, 15, 17, 19}))
    with Pdr(first) as pdr:
        assert pdr.run() == Status.UNSOLVABLE
        lemmas = pdr.invariant()
    with Pdr(second) as pdr:
        assert pdr.run() == Status.UNSOLVABLE
        alone = pdr.queries
    with Pdr(second) as pdr:
        added = pdr.seed(lemmas)
        assert pdr.run() == Status.UNSOLVABLE
        seeded = pdr.queries
    assert added >= 0.9 * len(lemmas)
    assert seeded < alone / 2


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
