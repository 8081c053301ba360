"""Horizon-free "no joint plan" proofs (h^2 on the robot x human product) against paired-state
search on random families, and the landmarks they give on a task where they matter."""

from __future__ import annotations

from pathlib import Path

from helpers.bruteforce import brute_force_frontier
from helpers.fuzzing import oracle_settings
from helpers.randomtasks import two_model_tasks
from helpers.sat_families import agreeing, families, selections
from hypothesis import given
from hypothesis import strategies as st

from mega_sat.analysis.joint_pairs import JointPairs
from mega_sat.engines.sat_loop import sat_frontier
from mega_sat.ground.family import GroundFamily
from mega_sat.ground.grounding import ground

SETTINGS = oracle_settings(200)
ROOT = Path(__file__).parent.parent


def joint_plan_exists(family: GroundFamily, selection: frozenset[int]) -> bool:
    """Some action sequence reaches the robot's goal in the robot model and the human's goal
    in ``human + selection`` (breadth-first over paired states, no cost bound)."""
    rt = family.specialize(family.robot_selection)
    ht = family.specialize(selection)
    h_by = {a.index: a for a in ht.actions}
    pairs = [(r, h_by[r.index]) for r in rt.actions if r.index in h_by]
    start = (frozenset(rt.init), frozenset(ht.init))
    seen, todo = {start}, [start]
    while todo:
        rs, hs = todo.pop()
        if rt.goal <= rs and ht.goal <= hs:
            return True
        for r, h in pairs:
            if r.pre <= rs and not r.negpre & rs and h.pre <= hs and not h.negpre & hs:
                nxt = ((rs - r.delete) | r.add, (hs - h.delete) | h.add)
                if nxt not in seen:
                    seen.add(nxt)
                    todo.append(nxt)
    return False


def _fixed_sets(n: int):
    return st.frozensets(st.integers(0, n - 1), max_size=n) if n else st.just(frozenset())


@SETTINGS
@given(fam=families(), data=st.data())
def test_no_joint_plan_holds_for_every_agreeing_model(fam: GroundFamily, data):
    sel = data.draw(selections(fam.n_updates))
    fixed = data.draw(_fixed_sets(fam.n_updates))
    pairs = JointPairs(fam)
    if pairs.no_joint_plan(sel, fixed):
        for other in agreeing([(i, i in sel) for i in fixed], fam.n_updates):
            assert not joint_plan_exists(fam, other)
    # every update fixed: the product is exact enough that a joint plan is never refuted
    if joint_plan_exists(fam, sel):
        assert not pairs.no_joint_plan(sel, frozenset(range(fam.n_updates)))


@SETTINGS
@given(fam=families())
def test_landmarks_are_in_every_selection_with_a_joint_plan(fam: GroundFamily):
    found = JointPairs(fam).landmarks()
    for i in found:
        for other in agreeing([(i, False)], fam.n_updates):
            assert not joint_plan_exists(fam, other)


@SETTINGS
@given(fam=families())
def test_landmarks_are_the_updates_whose_one_trial_proves(fam: GroundFamily):
    """The seeded trials (and the early stop when the human model's own product reaches the
    goal pairs) find exactly the updates whose unseeded product alone proves no joint plan."""
    pairs = JointPairs(fam)
    one_by_one = {
        i for i in range(fam.n_updates) if pairs.no_joint_plan(frozenset(), frozenset({i}))
    }
    assert pairs.landmarks() == one_by_one


@oracle_settings(40, suppress_health_check=())
@given(two_model_tasks(max_delta=5))
def test_landmarks_are_in_every_frontier_explanation(task):
    fam = ground(task)
    try:
        _, points, _ = brute_force_frontier(task, fam, state_limit=20_000)
    except ValueError:
        return
    found = JointPairs(fam).landmarks()
    for p in points:
        assert found <= p.selection


def test_blocksworld_landmarks_decide_a_frontier_otherwise_out_of_reach():
    """blocksworld Δ20 p1: the human's goal has (clear a), the robot's (on b a); only
    explanations with update 5 (which removes that goal) can have a joint plan.  Without the
    landmarks the loop spends minutes in OPT calls on models without update 5."""
    from mega_sat.pddl.loading import load_task_dir

    task = load_task_dir(ROOT / "domains/blocksworld/delta/20/p1")
    fam = ground(task)
    assert JointPairs(fam).landmarks() == {0, 5, 7, 8, 10}
    fr = sat_frontier(task, fam, timeout=120)
    assert fr.exact
    assert [(p.size, p.robot_cost) for p in fr.points] == [(6, 7), (7, 6)]
    assert fr.stats["explanation_landmarks"] == 5
    for p in fr.points:
        assert {0, 5, 7, 8, 10} <= p.selection


@SETTINGS
@given(fam=families())
def test_no_landmarks_where_a_robot_plan_runs_in_the_human_model(fam: GroundFamily):
    """The loop skips the landmark proofs when the robot's plan runs in the human model (a
    joint plan of E = {}): they would find none."""
    from mega_sat.ground.simulate import ground_plan_cost
    from mega_sat.search.astar import astar

    r = astar(fam.specialize(fam.robot_selection))
    if r.plan is not None and ground_plan_cost(fam.specialize(()), r.plan) is not None:
        assert JointPairs(fam).landmarks() == frozenset()
