"""Abstractions, h^2 pair reachability and explicit JOINT with cores, each against
explicit-state ground truth on random families (tests/sat_families.py); the tiered OPT is
checked in tests/test_tiered_opt.py."""

from __future__ import annotations

from helpers.fuzzing import oracle_settings
from helpers.sat_families import agreeing, dijkstra, families, joint_brute, plan_cost, selections
from hypothesis import given
from hypothesis import strategies as st

from mega_sat.analysis.abstraction import abstract_task
from mega_sat.analysis.pair_reachability import goal_pair_unreachable, pair_masks
from mega_sat.ground.family import GroundFamily
from mega_sat.search.astar import astar
from mega_sat.search.joint import JointSearcher, search_joint

SETTINGS = oracle_settings(150)


def _fixed_sets(n: int):
    return st.frozensets(st.integers(0, n - 1), max_size=n) if n else st.just(frozenset())


@SETTINGS
@given(fam=families(), data=st.data())
def test_full_abstraction_is_the_model_and_partial_ones_over_approximate(fam: GroundFamily, data):
    sel = data.draw(selections(fam.n_updates))
    exact = abstract_task(fam, sel, range(fam.n_updates))
    assert not any(a.negpre for a in exact.actions)
    # with every update fixed: same optimum as the concrete model
    assert dijkstra(exact) == dijkstra(fam.specialize(sel))
    fixed = data.draw(_fixed_sets(fam.n_updates))
    abst = abstract_task(fam, sel, fixed)
    best_abs = dijkstra(abst)
    for other in agreeing([(i, i in sel) for i in fixed], fam.n_updates):
        task = fam.specialize(other)
        c = dijkstra(task)
        if c is None:
            continue
        # every plan of an agreeing model runs in the abstraction, at no higher cost
        r = astar(task, heuristic="blind")
        ac = plan_cost(abst, r.plan)
        assert ac is not None and ac <= c
        assert best_abs is not None and best_abs <= c


@SETTINGS
@given(fam=families(), data=st.data())
def test_pair_reachability_never_refutes_a_solvable_model(fam: GroundFamily, data):
    sel = data.draw(selections(fam.n_updates))
    fixed = data.draw(_fixed_sets(fam.n_updates))
    if goal_pair_unreachable(abstract_task(fam, sel, fixed)):
        for other in agreeing([(i, i in sel) for i in fixed], fam.n_updates):
            assert dijkstra(fam.specialize(other)) is None


@SETTINGS
@given(fam=families(), data=st.data())
def test_pair_masks_seeded_by_a_finer_abstraction_are_the_same(fam: GroundFamily, data):
    # freeing updates only relaxes the abstraction, so the finer one's pairs are reachable
    sel = data.draw(selections(fam.n_updates))
    fixed = data.draw(_fixed_sets(fam.n_updates))
    finer = fixed | data.draw(_fixed_sets(fam.n_updates))
    task = abstract_task(fam, sel, fixed)
    seed = pair_masks(abstract_task(fam, sel, finer))
    assert pair_masks(task, seed) == pair_masks(task)


@SETTINGS
@given(fam=families(), data=st.data())
def test_kept_pair_masks_are_those_of_the_task_asked_about(fam: GroundFamily, data):
    # tasks that differ in one initial fact or one delete must not share a fixpoint, and a
    # seed does not change it
    from dataclasses import replace

    from mega_sat.analysis.pair_reachability import _fixpoint

    task = abstract_task(fam, data.draw(selections(fam.n_updates)), [])
    variants = [task, replace(task, init=task.init ^ {0})]
    if task.actions:
        a = task.actions[0]
        variants.append(
            replace(task, actions=(replace(a, delete=a.delete ^ {0}),) + task.actions[1:])
        )
    for t in variants + variants:
        got = pair_masks(t)
        assert got == list(_fixpoint(len(t.atoms), t.init, _acts(t), None))
        got.clear()  # the caller's list, not the kept one
        seed = [0] * len(t.atoms)
        assert pair_masks(t, seed) == pair_masks(t) != []


def test_kept_pair_masks_stay_within_their_limits(monkeypatch):
    # the keeping never holds more fixpoints or bits than allowed, and never changes an answer
    from mega_sat.analysis import pair_reachability as pr

    kept = pr._Kept()
    monkeypatch.setattr(pr, "_kept", kept)
    monkeypatch.setattr(pr, "KEEP_FIXPOINTS", 4)  # the bits are the tighter limit
    monkeypatch.setattr(pr, "KEEP_BITS", 3 * 5 * 5)
    from mega_sat.ground.family import GroundTask, StripsAction

    def task(n: int, first: int) -> GroundTask:
        # a chain of n atoms from atom `first`: each action moves the token one step on
        acts = tuple(
            StripsAction(
                i,
                "move",
                (str(i),),
                frozenset({i}),
                frozenset(),
                frozenset({i + 1}),
                frozenset({i}),
                1,
            )
            for i in range(first, n - 1)
        )
        atoms = tuple(("at", (f"p{i}",)) for i in range(n))
        return GroundTask(atoms, acts, frozenset({first}), frozenset())

    small = [task(5, f) for f in range(4)]
    for t in small[:3]:
        assert pr.pair_masks(t) == list(pr._fixpoint(5, t.init, _acts(t), None))
    assert len(kept.masks) == 3 and kept.bits == 75
    big = task(9, 0)  # 9 * 9 bits are more than allowed: answered, not kept, nothing dropped
    assert pr.pair_masks(big) == list(pr._fixpoint(9, big.init, _acts(big), None))
    assert len(kept.masks) == 3 and kept.bits == 75
    pr.pair_masks(small[0])  # asked again: now the most recent
    pr.pair_masks(small[3])  # one more: the least recently asked for (small[1]) goes
    assert [k[1] for k in kept.masks] == [small[i].init for i in (2, 0, 3)]
    got = pr.pair_masks(small[2], [0] * 5)  # a seed does not change the fixpoint
    assert got == list(pr._fixpoint(5, small[2].init, _acts(small[2]), None))
    got.clear()  # the caller's list, not the kept one
    assert pr.pair_masks(small[2]) != []


def _acts(t):
    return tuple((a.pre, a.add, a.delete) for a in t.actions)


def test_pair_reachability_sees_what_relaxation_cannot():
    # one token moved between two places: the goal "at both" is relaxed-reachable only
    from mega_sat.ground.family import GroundAction

    move = GroundAction("move", ("a", "b"), None, ((0, None),), (), ((1, None),), ((0, None),),
                        (((), 1),))  # fmt: skip
    back = GroundAction("move", ("b", "a"), None, ((1, None),), (), ((0, None),), ((1, None),),
                        (((), 1),))  # fmt: skip
    fam = GroundFamily((("at", "a"), ("at", "b")), 0, (move, back), ((0, None),),
                       ((0, None), (1, None)))  # fmt: skip
    task = abstract_task(fam, frozenset(), [])
    assert astar(task, heuristic="hmax").status == "unsolvable"
    assert goal_pair_unreachable(task)


@SETTINGS
@given(fam=families(max_atoms=3, max_actions=5, max_updates=4), data=st.data())
def test_search_joint_matches_paired_search_and_cores_are_sound(fam: GroundFamily, data):
    robot = fam.specialize(fam.robot_selection)
    searcher = JointSearcher(robot)
    for _ in range(2):
        sel = data.draw(selections(fam.n_updates))
        hb = data.draw(st.integers(0, 7))
        rb = data.draw(st.one_of(st.none(), st.integers(0, 7)))
        keep = data.draw(_fixed_sets(fam.n_updates))
        r = search_joint(searcher, fam, sel, rb, hb, keep=keep)
        best = joint_brute(fam, sel, rb, hb)
        if best is None:
            assert r.status == "infeasible" and r.core is not None
            assert all(v == (i in sel) for i, v in r.core)
            assert {i for i, _ in r.core} >= keep
            for other in agreeing(r.core, fam.n_updates):
                assert joint_brute(fam, other, rb, hb) is None
        else:
            assert r.status == "plan" and r.robot_cost == best
            assert plan_cost(robot, r.plan) == r.robot_cost
            assert plan_cost(fam.specialize(sel), r.plan) == r.human_cost <= hb
