"""Both MEGA engines and MCE against the brute-force oracle, on random small tasks.

The oracle (helpers.bruteforce) enumerates every subset of Delta and uses explicit-state
Dijkstra over paired (robot, human) states; it shares no code with the SAT encoding, the
hitting-set loop or the A* model-space search.
"""

from __future__ import annotations

from fractions import Fraction

import pytest
from helpers.bruteforce import brute_force_frontier, brute_force_mce, check_witnesses
from helpers.fuzzing import oracle_settings
from helpers.minitasks import usar_like
from helpers.randomtasks import two_model_tasks
from helpers.tradeoff_tasks import tradeoff_tasks
from hypothesis import HealthCheck, given
from hypothesis import strategies as st

from mega_sat.engines.astar import astar_frontier, astar_solve
from mega_sat.engines.mce import minimal_explanation
from mega_sat.engines.sat_loop import sat_frontier
from mega_sat.engines.verify import verify_pair
from mega_sat.errors import UnsolvableError
from mega_sat.ground.grounding import ground
from mega_sat.options import Options
from mega_sat.results import choose
from mega_sat.sat.oracles import SatOracles

SETTINGS = oracle_settings(
    150, suppress_health_check=[HealthCheck.too_slow, HealthCheck.filter_too_much]
)


# plain random tasks (odd corners: costs from functions, schemas one model lacks, no plans)
# and route maps with real trade-offs (multi-point frontiers)
TASKS = st.one_of(two_model_tasks(max_delta=6), tradeoff_tasks())


def _solvable(task):
    fam = ground(task)
    try:
        c_r, pts, results = brute_force_frontier(task, fam, state_limit=20_000)
    except ValueError:
        return None
    return fam, c_r, pts, results


def _pairs(points):
    return [(p.size, p.robot_cost) for p in points]


@SETTINGS
@given(
    TASKS,
    st.sampled_from(["rc2", "ilp"]),
    st.sampled_from(["sat", "search", "portfolio"]),
    st.sampled_from([None, "builtin", "sat"]),
    st.booleans(),
    st.booleans(),
    st.sampled_from([0, 3000]),
    st.booleans(),
)
def test_sat_frontier_equals_brute_force(
    task, hs, joint, planner, joint_first, pair_proofs, below_nodes, monotone
):
    got = _solvable(task)
    if got is None:
        with pytest.raises(UnsolvableError):
            sat_frontier(task, ground(task))
        return
    fam, c_r, pts, results = got
    # "portfolio" with a zero budget: every JOINT falls through to the explicit search after
    # the SAT oracle gave up (exercises the hand-over)
    budget = 0 if joint == "portfolio" else 20_000
    fr = sat_frontier(
        task,
        fam,
        planner=planner,
        hitting_set=hs,
        joint=joint,
        joint_conflict_budget=budget,
        options=Options(
            joint_before_opt=joint_first,
            joint_pair_proofs=pair_proofs,
            plan_below_robot_nodes=below_nodes,  # the search below the robot optimum
            monotone_cores=monotone,  # cores and supports without monotone literals
        ),
    )
    assert fr.robot_optimal_cost == c_r
    assert _pairs(fr.points) == _pairs(pts)
    assert fr.complete
    if fam.min_cost > 0:
        assert fr.exact
    # each witness is a real MEGA solution: the oracle's best for that E is no worse
    check_witnesses(task, fam, fr.points, results)
    assert all(results[p.selection].human_cost == p.human_cost for p in fr.points)


def test_joint_before_opt_decides_candidates_without_opt_and_keeps_the_frontier():
    """usar-fetch Δ10 p1: JOINT at a remembered plan's cost rules out candidates that then
    need no OPT call; the frontier is the one the loop finds with OPT first."""
    from pathlib import Path

    from mega_sat.pddl.loading import load_task_dir

    task = load_task_dir(Path(__file__).parent.parent / "domains/usar-fetch/delta/10/p1")
    fam = ground(task)
    runs = {
        first: sat_frontier(task, fam, options=Options(joint_before_opt=first))
        for first in (True, False)
    }
    assert _pairs(runs[True].points) == _pairs(runs[False].points) == [(3, 7), (4, 5), (6, 4)]
    assert runs[True].exact and runs[False].exact
    assert runs[True].stats["joint_before_opt_cores"] > 0
    assert runs[False].stats["joint_before_opt_cores"] == 0
    assert runs[True].stats["opt_calls"] < runs[False].stats["opt_calls"]


def test_the_search_below_the_robot_optimum_runs_only_up_to_its_number_of_updates():
    """barman-bar Δ7 p2 (7 updates): the search pruned at the robot optimum answers some
    candidates by default, none once the limit is below 7 or its budget is 0, and the
    frontier is the same either way."""
    from pathlib import Path

    from mega_sat.pddl.loading import load_task_dir

    task = load_task_dir(Path(__file__).parent.parent / "domains/barman-bar/delta/7/p2")
    fam = ground(task)
    runs = [
        sat_frontier(task, fam, options=o)
        for o in (
            Options(),
            Options(plan_below_robot_max_updates=6),
            Options(plan_below_robot_nodes=0),
        )
    ]
    assert runs[0].stats["plan_below_robot_by_search"] > 0
    assert [r.stats["plan_below_robot_by_search"] for r in runs[1:]] == [0, 0]
    assert _pairs(runs[0].points) == _pairs(runs[1].points) == _pairs(runs[2].points)
    assert all(r.exact for r in runs)


@SETTINGS
@given(TASKS)
def test_mce_equals_brute_force(task):
    got = _solvable(task)
    if got is None:
        return
    fam = got[0]
    orc = SatOracles(fam)
    robot = orc.robot_optimal()
    ex = minimal_explanation(task, fam, robot.plan, oracles=orc)
    assert len(ex.explanation) == brute_force_mce(task, fam, robot.plan, state_limit=20_000)
    assert ex.robot_cost == robot.cost
    assert ex.human_cost == orc.opt(ex.selection).cost


@SETTINGS
@given(TASKS, st.sampled_from([0, 0.3, 1, 2.5, 10]))
def test_astar_never_better_than_sat(task, alpha):
    got = _solvable(task)
    if got is None:
        return
    fam, c_r, pts, _ = got
    fr = sat_frontier(task, fam)
    sat = choose(fr, alpha)
    ast = astar_solve(task, fam, alpha, planner="builtin")
    a = Fraction(repr(float(alpha)))
    obj_sat = sat.chosen.size + a * (sat.chosen.robot_cost - c_r)
    obj_ast = ast.chosen.size + a * (ast.chosen.robot_cost - c_r)
    assert obj_sat <= obj_ast
    assert verify_pair(
        task, fam, ast.chosen.selection, ast.chosen.plan, producer="builtin", use_val=False
    ).ok
    # where ties among optimal plans cannot matter (every human-optimal plan of every model
    # the search visits has the same robot cost), the baseline finds the same optimum
    afr = astar_frontier(task, fam, planner="builtin")
    for p in afr.points:
        assert any(q.size <= p.size and q.robot_cost <= p.robot_cost for q in fr.points)


@SETTINGS
@given(TASKS)
def test_paper_properties(task):
    got = _solvable(task)
    if got is None:
        return
    fam, c_r, pts, results = got
    fr = sat_frontier(task, fam)
    n = len(task.delta)
    # property 3: alpha = 0 gives the most explicable plan (smallest |E| of any solution)
    smallest = min(len(s) for s, r in results.items() if r.robot_cost is not None)
    assert choose(fr, 0).chosen.size == smallest
    # property 2: alpha >= |Delta| gives a robot-optimal plan with the minimum explanation
    high = choose(fr, max(n, 1) + 0.5).chosen
    assert high.robot_cost == c_r
    assert high.size == min(len(s) for s, r in results.items() if r.robot_cost == c_r)
    # property 4: the frontier's robot-optimal end is the smallest E for *some* robot-optimal
    # plan, never larger than the MCE of one fixed robot-optimal plan
    orc = SatOracles(fam)
    mce = minimal_explanation(task, fam, orc.robot_optimal().plan, oracles=orc)
    assert fr.points[-1].robot_cost == c_r
    assert fr.points[-1].size <= len(mce.explanation)


def test_usar_like_frontier_both_engines():
    task = usar_like()
    fam = ground(task)
    fr = sat_frontier(task, fam)
    assert _pairs(fr.points) == [(1, 7), (3, 3)]
    assert fr.exact and fr.robot_optimal_cost == 3
    assert fr.points[0].explanation == ("remove-has-initial-state-clear_path s a",)
    low, high = choose(fr, 0.1).chosen, choose(fr, 10).chosen
    assert ("clear_passage", "s", "a") in low.plan and low.robot_cost == 7
    assert high.robot_cost == 3 and high.size == 3
    afr = astar_frontier(task, fam, planner="builtin")
    assert _pairs(afr.points) == [(1, 7), (3, 3)]
    assert afr.stats["nodes_expanded"] >= 4


def test_anytime_returns_lower_bound():
    task = usar_like()
    fam = ground(task)
    fr = sat_frontier(task, fam, timeout=1e-9)
    assert not fr.complete and not fr.exact
    assert fr.next_size_lower_bound is not None
    assert any("time limit" in n for n in fr.notes)


@pytest.mark.parametrize("planner", ["builtin", "sat", "portfolio"])
def test_time_limit_bounds_the_explicit_opt_planner(planner):
    """The sat engine's OPT planner gets what is left of the time limit.  barman-bar Δ=15 p3
    has human models whose optimum takes the built-in planner more than a minute; before the
    planner got the limit, a 3 s run took 71 s."""
    import time
    from pathlib import Path

    from mega_sat.api import MegaSolver
    from mega_sat.pddl.loading import load_task, resolve_task_dir

    d = Path(__file__).resolve().parent.parent / "domains" / "barman-bar" / "delta" / "15" / "p3"
    task = load_task(**resolve_task_dir(str(d)))
    from mega_sat.deadline import TimeLimitReached

    t0 = time.perf_counter()
    try:
        fr = MegaSolver(task, planner=planner, timeout=3.0).frontier()
    except TimeLimitReached:  # a loaded machine: even the robot optimum took the 3 s
        fr = None
    assert time.perf_counter() - t0 < 3.0 + 4.0
    if fr is not None:
        assert not fr.complete and not fr.exact
        assert any("time limit 3.0s reached" in n for n in fr.notes)


@oracle_settings(80, suppress_health_check=[HealthCheck.too_slow, HealthCheck.filter_too_much])
@given(st.one_of(two_model_tasks(max_delta=5, allow_zero_cost=True), tradeoff_tasks()))
def test_default_engine_settings_follow_the_costs_and_stay_exact(task):
    """MegaSolver's defaults: the OPT portfolio (search and SAT in turns) and SAT JOINT, except
    with zero-cost actions (where the horizon argument proves nothing): the built-in planner
    and the JOINT portfolio.  Either way the frontier is the brute-force one."""
    from mega_sat.api import MegaSolver

    fam = ground(task)
    zero = fam.min_cost <= 0
    s = MegaSolver(task)
    assert s.planner == ("builtin" if zero else "portfolio")
    assert s.joint == ("portfolio" if zero else "sat")
    assert MegaSolver(task, engine="astar").planner == "builtin"
    assert MegaSolver(task, planner="fd", joint="search").joint == "search"
    got = _solvable(task)
    if got is None:
        with pytest.raises(UnsolvableError):
            s.frontier()
        return
    _, c_r, pts, _ = got
    fr = s.frontier()
    assert fr.robot_optimal_cost == c_r
    assert _pairs(fr.points) == _pairs(pts)
    assert fr.complete and fr.exact  # with zero costs too: the JOINT portfolio's search proves
    assert fr.stats["opt_planner"] == s.planner and fr.stats["joint"] == s.joint


COUNTER = """(define (domain counter)
 (:requirements :strips :negative-preconditions :action-costs)
 (:constants b0 b1 b2 b3 b4)
 (:predicates (on ?b) (done) (jammed))
 (:functions (total-cost))
 (:action inc0 :parameters () :precondition (not (on b0)) :effect (on b0))
 (:action inc1 :parameters () :precondition (and (on b0) (not (on b1)))
  :effect (and (on b1) (not (on b0))))
 (:action inc2 :parameters () :precondition (and (on b0) (on b1) (not (on b2)) JAM)
  :effect (and (on b2) (not (on b0)) (not (on b1))))
 (:action inc3 :parameters () :precondition (and (on b0) (on b1) (on b2) (not (on b3)))
  :effect (and (on b3) (not (on b0)) (not (on b1)) (not (on b2))))
 (:action inc4 :parameters () :precondition (and (on b0) (on b1) (on b2) (on b3) (not (on b4)))
  :effect (and (on b4) (not (on b0)) (not (on b1)) (not (on b2)) (not (on b3))))
 (:action finish :parameters () :precondition (and (on b0) (on b1) (on b2) (on b3) (on b4))
  :effect (and (done) (increase (total-cost) FINISH)))
 (:action shortcut :parameters () :effect (and (done) (increase (total-cost) 10))))
"""
"""A five-bit counter of free increments: the robot's optimum is 31 zero-cost steps and
``finish`` (cost 1), longer than any horizon JOINT's SAT encoding derives from costs."""


def test_zero_cost_joint_answers_are_proven_by_search():
    """The JOINT portfolio's SAT side answered "no joint plan" at horizon 15, which proves
    nothing with zero-cost actions; the loop learned it as an empty clause and stopped with
    [(0, 10)], "complete", missing (1, 1) (found by a sweep; `explain` gave |E| = 1).  Now
    its search answers such calls."""
    from mega_sat import api

    robot = COUNTER.replace(" JAM", "").replace("FINISH", "1")
    human = COUNTER.replace("JAM", "(not (jammed))").replace("FINISH", "3")
    problem = (
        "(define (problem c) (:domain counter) (:init INIT (= (total-cost) 0)) (:goal (done)))"
    )
    task = api.load_task_from_strings(
        robot, problem.replace("INIT", ""), human, problem.replace("INIT", "(jammed)")
    )
    fr = api.MegaSolver(task).frontier()
    assert fr.robot_optimal_cost == 1
    assert [(p.size, p.robot_cost) for p in fr.points] == [(0, 10), (1, 1)]
    assert fr.exact and fr.complete and fr.stats["joint_searches"] >= 1


ROOMS = """(define (domain rooms) (:requirements :strips :action-costs)
  (:predicates (at ?r) (door ?a ?b) (lit ?r))
  (:functions (total-cost))
  (:action go :parameters (?a ?b) :precondition (and (at ?a) (door ?a ?b) EXTRA)
    :effect (and (not (at ?a)) (at ?b) (increase (total-cost) 1))))"""
ROOMS_PROBLEM = """(define (problem rooms-1) (:domain rooms) (:objects r1 r2 r3 r4 r5)
  (:init (at r1) (door r1 r2) (door r2 r4) (door r1 r3) (door r3 r5) (door r5 r4)
         (lit r3) (lit r4) (lit r5))
  (:goal (at r4)))"""


def test_verify_refuses_a_point_of_another_task():
    """A point's selection indexes its own task's model difference: checked against another
    task it once passed as "ok" with some other explanation (found by an API sweep)."""
    from mega_sat import api
    from mega_sat.errors import UsageError

    robot = ROOMS.replace("EXTRA", "")
    task_a = api.load_task_from_strings(robot, ROOMS_PROBLEM, ROOMS.replace("EXTRA", "(lit ?b)"))
    task_b = api.load_task_from_strings(robot, ROOMS_PROBLEM, ROOMS.replace("EXTRA", "(lit ?a)"))
    point = api.frontier(task_a).points[-1]
    assert point.explanation and api.verify(task_a, point).ok
    with pytest.raises(UsageError, match="is it from another task"):
        api.verify(task_b, point)
    with pytest.raises(UsageError, match="not both"):
        api.MegaSolver(task_a).verify(point, plan=[("go", "r1", "r2")])


def test_mce_plan_failure_cores_are_small_and_sound():
    """A candidate where the plan fails is excluded by its first failure only (depots p2 used
    to enumerate ~10^5 candidates, one ~23-literal support clause each)."""
    import random
    from pathlib import Path

    from mega_sat.engines.support import failure_core
    from mega_sat.ground.simulate import simulate_ground
    from mega_sat.pddl.loading import load_task_dir

    task = load_task_dir(Path(__file__).parents[1] / "domains/missing-schemas/depots/p2")
    fam = ground(task)
    plan = SatOracles(fam).robot_optimal().plan
    rnd = random.Random(0)
    for _ in range(100):
        sel = frozenset(i for i in range(fam.n_updates) if rnd.random() < 0.5)
        core = failure_core(fam, sel, plan)
        assert (core is None) == simulate_ground(fam.specialize(sel), plan).valid
        if core is None:
            continue
        assert len(core) <= 3
        for _ in range(10):
            other = {i for i in range(fam.n_updates) if rnd.random() < 0.5}
            other = (other | {i for i, v in core if v}) - {i for i, v in core if not v}
            assert not simulate_ground(fam.specialize(other), plan).valid
    ex = minimal_explanation(task, fam, plan)
    assert len(ex.explanation) == 8 and ex.stats["candidates"] < 100
