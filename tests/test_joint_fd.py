"""JOINT by Fast Downward on the product task (mega_sat/planners/joint_fd.py, sas.py): answers
equal the paired-state brute force, cores hold for every selection they cover, and the
loop's frontiers stay the brute-force ones when FD answers its JOINT calls."""

from __future__ import annotations

import pytest
from helpers.bruteforce import brute_force_frontier
from helpers.fuzzing import oracle_settings
from helpers.multi_bruteforce import multi_brute_force_frontier
from helpers.multi_randomtasks import multi_human_tasks, multi_tradeoff_tasks
from helpers.randomtasks import two_model_tasks
from helpers.sat_families import agreeing, dijkstra, families, joint_brute, plan_cost, selections
from helpers.tradeoff_tasks import tradeoff_tasks
from hypothesis import HealthCheck, assume, given
from hypothesis import strategies as st

from mega_sat.deadline import NO_DEADLINE
from mega_sat.engines.multi_human import multi_frontier
from mega_sat.engines.sat_loop import sat_frontier
from mega_sat.ground.family import GroundAction, GroundFamily
from mega_sat.ground.grounding import ground
from mega_sat.options import Options
from mega_sat.planners.fast_downward import fd_available, fd_plan
from mega_sat.planners.joint_fd import JointByFd
from mega_sat.planners.sas import product_sas

pytestmark = pytest.mark.skipif(not fd_available(), reason="Fast Downward not installed")


@oracle_settings(60)
@given(
    fam=families(max_atoms=4, max_actions=6, max_updates=3, min_cost=0),
    lmcut=st.booleans(),
    data=st.data(),
)
def test_fd_joint_equals_the_paired_brute_force(fam: GroundFamily, lmcut: bool, data):
    robot = fam.specialize(fam.robot_selection)
    r_lb = dijkstra(robot)
    sel = data.draw(selections(fam.n_updates))
    human = fam.specialize(sel)
    c = dijkstra(human)
    # the empty plan answers a task whose goals hold at once without FD
    assume(r_lb is not None and c is not None and not robot.goal <= robot.init)
    rb = data.draw(st.one_of(st.none(), st.integers(r_lb, r_lb + 6)))
    best_any = joint_brute(fam, sel, None, c)
    # the loop passes the robot cost of a joint plan of human cost c when it knows one
    known = None
    if best_any is not None and data.draw(st.booleans()):
        known = best_any + data.draw(st.integers(0, 3))
    keep = data.draw(st.frozensets(st.integers(0, max(fam.n_updates - 1, 0)), max_size=2))
    keep = frozenset(i for i in keep if i < fam.n_updates)
    fd = JointByFd(robot, r_lb, family=fam, options=Options(joint_fd_lmcut=lmcut))
    r = fd.joint(sel, rb, c, known=known, keep=keep, deadline=NO_DEADLINE)
    assert r is not None
    best = joint_brute(fam, sel, rb, c)
    if best is None:
        assert r.status == "infeasible" and r.core is not None and r.exact
        assert all(v == (i in sel) for i, v in r.core)
        assert {i for i, _ in r.core} >= keep
        for other in agreeing(r.core, fam.n_updates):
            assert joint_brute(fam, other, rb, c) is None
    else:
        assert r.status == "plan" and r.robot_cost == best and r.exact
        assert plan_cost(robot, r.plan) == best
        assert plan_cost(fam.specialize(sel), r.plan) == r.human_cost == c


def _action(name, pre=(), negpre=(), add=(), delete=(), cost=1, exists=None):
    return GroundAction(
        name=name,
        args=(),
        exists=exists,
        pre=tuple((p, None) for p in pre),
        negpre=tuple((p, None) for p in negpre),
        add=tuple((p, None) for p in add),
        delete=tuple((p, None) for p in delete),
        cost=(((), cost),),
    )


def test_product_sas_keeps_strips_semantics():
    """Add wins over delete, negative conditions hold, an effect that sets what the action
    requires is no effect, static and unreachable parts are dropped, and a goal nothing can
    reach leaves a task without plan."""
    fam = GroundFamily(
        atoms=(("p",), ("q",), ("r",), ("s",), ("static",)),
        n_updates=0,
        actions=(
            _action("flip", pre=(4,), add=(0,), delete=(0, 2)),  # add wins: p stays
            _action("need-not-r", pre=(0,), negpre=(2,), add=(1,)),
            _action("never", pre=(3,), add=(1,), cost=0),  # s is never reachable
            _action("noop", pre=(1,), add=(1,), cost=0),
        ),
        init=((2, None), (4, None)),
        goal=((0, None), (1, None)),
    )
    task = fam.specialize(frozenset())
    sas, names = product_sas(((task, 1),))
    assert "act2" not in names and "act3" not in names
    r = fd_plan(None, None, sas_text=sas)
    assert r.status == "optimal" and r.cost == 2
    assert tuple(names[s[0]] for s in r.plan) == (("flip",), ("need-not-r",))
    blocked = GroundFamily(fam.atoms, 0, fam.actions, fam.init, ((3, None),))
    sas, _ = product_sas(((blocked.specialize(frozenset()), 1),))
    assert fd_plan(None, None, sas_text=sas).status == "unsolvable"


def test_costs_past_fd_range_are_left_to_the_search():
    """Weights that could overflow FD's 32-bit sums: no answer, the caller's search runs."""
    big = 10**8
    fam = GroundFamily(
        atoms=(("g",),),
        n_updates=0,
        actions=(_action("go", add=(0,), cost=big),),
        init=(),
        goal=((0, None),),
    )
    robot = fam.specialize(frozenset())
    fd = JointByFd(robot, big, family=fam)
    assert fd.joint(frozenset(), 3 * big, big, deadline=NO_DEADLINE) is None
    assert fd.runs == 0


def _costs(robot: int, human: int, update: int = 0):
    """Cost cases: ``robot`` with the update selected (as in the robot model), else ``human``."""
    return (((update, True),), robot), (((update, False),), human)


def test_the_weight_makes_the_order_lexicographic():
    """The human-optimal plan costs the robot 10, a plan one human unit dearer costs it 1: a
    weight below ``K - r + 1`` would let the dearer plan win the product's optimum."""
    add = ((0, None),)
    fam = GroundFamily(
        atoms=(("g",),),
        n_updates=1,
        actions=(
            GroundAction("a", (), None, (), (), add, (), _costs(10, 1)),
            GroundAction("b", (), None, (), (), add, (), _costs(1, 2)),
        ),
        init=(),
        goal=((0, None),),
    )
    robot = fam.specialize(fam.robot_selection)
    for bound in (10, 12, None):
        r = JointByFd(robot, 1, family=fam).joint(frozenset(), bound, 1, deadline=NO_DEADLINE)
        assert r.status == "plan" and (r.robot_cost, r.human_cost) == (10, 1)
        assert r.plan == (("a",),)
    r = JointByFd(robot, 1, family=fam).joint(frozenset(), 9, 1, deadline=NO_DEADLINE)
    assert r.status == "infeasible"


def test_a_core_keeps_an_update_whose_model_has_a_plan_at_the_bound():
    """Human model: only ``b`` (robot cost 7 > K = 5) reaches the goal within c = 1.  With
    update 0, ``a`` exists and costs the robot exactly K: the core must keep update 0 (a
    trial whose abstraction's optimum equals ``M c + K`` rules nothing out)."""
    add = ((0, None),)
    fam = GroundFamily(
        atoms=(("g",),),
        n_updates=2,
        actions=(
            GroundAction("a", (), (0, True), (), (), add, (), _costs(5, 1, update=1)),
            GroundAction("b", (), None, (), (), add, (), _costs(7, 1, update=1)),
        ),
        init=(),
        goal=((0, None),),
    )
    robot = fam.specialize(fam.robot_selection)
    fd = JointByFd(robot, 5, family=fam)
    r = fd.joint(frozenset(), 5, 1, deadline=NO_DEADLINE)
    assert r.status == "infeasible" and r.core == frozenset({(0, False)})
    assert joint_brute(fam, frozenset({0}), 5, 1) == 5


def test_a_sas_task_runs_with_and_without_the_driver(monkeypatch):
    """The search binary reads the SAS+ task on its standard input; where the package ships
    no binary beside its driver, the driver runs the search on the file: the same answers."""
    import mega_sat.planners.fast_downward as fdmod

    fam = GroundFamily(
        atoms=(("p",), ("q",)),
        n_updates=0,
        actions=(_action("a", add=(0,), cost=2), _action("b", pre=(0,), add=(1,), cost=3)),
        init=(),
        goal=((1, None),),
    )
    sas, names = product_sas(((fam.specialize(frozenset()), 1),))
    blocked, _ = product_sas(((GroundFamily(fam.atoms, 0, fam.actions[1:], (), fam.goal)
                               .specialize(frozenset()), 1),))  # fmt: skip
    answers = []
    for binary in (True, False):
        if not binary:
            monkeypatch.setattr(fdmod, "fd_search_binary", lambda: None)
        r = fd_plan(None, None, sas_text=sas)
        answers.append((r.status, r.cost, tuple(names[s[0]] for s in r.plan)))
        assert fd_plan(None, None, sas_text=blocked).status == "unsolvable"
    assert answers == [("optimal", 5, (("a",), ("b",)))] * 2


FD_AT_ONCE = Options(joint_fd_after_work=0)
"""FD takes every JOINT call the paired-state search would answer (by default small searches
answer themselves, so on these small tasks FD would hardly run)."""


@oracle_settings(120, suppress_health_check=[HealthCheck.too_slow, HealthCheck.filter_too_much])
@given(st.one_of(two_model_tasks(max_delta=5, allow_zero_cost=True), tradeoff_tasks()))
def test_frontiers_with_fd_at_once_equal_brute_force(task):
    """The loop with FD answering its explicit JOINT calls (zero-cost tasks send every call
    there; with positive costs, --joint search does) gives the brute-force frontier."""
    fam = ground(task)
    try:
        c_r, pts, _ = brute_force_frontier(task, fam, state_limit=20_000)
    except ValueError:
        return
    joint = "portfolio" if fam.min_cost <= 0 else "search"
    fr = sat_frontier(task, fam, joint=joint, options=FD_AT_ONCE)
    assert fr.robot_optimal_cost == c_r
    assert [(p.size, p.robot_cost) for p in fr.points] == [(p.size, p.robot_cost) for p in pts]
    assert fr.complete and fr.exact


@oracle_settings(60, suppress_health_check=[HealthCheck.too_slow, HealthCheck.filter_too_much])
@given(st.one_of(multi_human_tasks(allow_zero_cost=True, max_delta=4), multi_tradeoff_tasks()))
def test_several_humans_with_fd_at_once_equal_brute_force(task):
    """The several-humans engine with FD answering its product searches (the sum of the
    human costs at the sum of their optima) gives the brute-force frontier."""
    fams = [ground(t) for t in task.tasks]
    try:
        c_r, pts, _ = multi_brute_force_frontier(task, fams, state_limit=20_000)
    except ValueError:
        return
    fr = multi_frontier(task, fams, options=FD_AT_ONCE)
    assert fr.robot_optimal_cost == c_r
    assert [(p.explanation_cost, p.robot_cost) for p in fr.points] == [
        (p.explanation_cost, p.robot_cost) for p in pts
    ]
    assert fr.exact and fr.complete
