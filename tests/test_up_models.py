"""unified-planning models in and out (mega_sat.pddl.up_models): models built in Python give the
same frontier as the same models read from PDDL, plans go back as valid ``SequentialPlan``
objects, and other kinds of problem are refused by the library's own feature names."""

from __future__ import annotations

from pathlib import Path

import pytest

from mega_sat import api
from mega_sat.errors import MegaSatError

up = pytest.importorskip("unified_planning")

from unified_planning.engines import PlanGenerationResultStatus  # noqa: E402
from unified_planning.engines.plan_validator import (  # noqa: E402
    SequentialPlanValidator,
)
from unified_planning.model.metrics import MinimizeActionCosts  # noqa: E402
from unified_planning.plans import ActionInstance, SequentialPlan  # noqa: E402
from unified_planning.shortcuts import (  # noqa: E402
    BoolType,
    Equals,
    Exists,
    Fluent,
    InstantaneousAction,
    IntType,
    Not,
    Object,
    Problem,
    RealType,
    UserType,
    Variable,
)

ROOT = Path(__file__).resolve().parents[1]

up.shortcuts.get_environment().credits_stream = None


def _usar(human: bool, distinct: bool = False) -> Problem:
    """domains/usar-fetch p1 built in Python: the robot's map, or the commander's (human);
    ``distinct``: ``move`` also requires ``(not (= ?a ?b))``."""
    wp = UserType("waypoint")
    robot_at = Fluent("robot_at", BoolType(), l=wp)
    clear_path = Fluent("clear_path", BoolType(), a=wp, b=wp)
    clearable = Fluent("clearable", BoolType(), a=wp, b=wp)
    picture_taken = Fluent("picture_taken", BoolType(), l=wp)
    move = InstantaneousAction("move", a=wp, b=wp)
    a, b = move.parameters
    move.add_precondition(robot_at(a))
    move.add_precondition(clear_path(a, b))
    if distinct:
        move.add_precondition(Not(Equals(a, b)))
    move.add_effect(robot_at(a), False)
    move.add_effect(robot_at(b), True)
    clear = InstantaneousAction("clear_passage", a=wp, b=wp)
    a, b = clear.parameters
    clear.add_precondition(robot_at(a))
    clear.add_precondition(clearable(a, b))
    clear.add_effect(clearable(a, b), False)
    clear.add_effect(clear_path(a, b), True)
    pic = InstantaneousAction("take_picture", l=wp)
    pic.add_precondition(robot_at(pic.parameters[0]))
    pic.add_effect(picture_taken(pic.parameters[0]), True)

    p = Problem("usar-p1")
    for f in (robot_at, clear_path, clearable, picture_taken):
        p.add_fluent(f, default_initial_value=False)
    for act in (move, clear, pic):
        p.add_action(act)
    o = {f"p{i}": Object(f"p{i}", wp) for i in range(1, 9)}
    p.add_objects(o.values())
    p.set_initial_value(robot_at(o["p1"]), True)
    paths = [("p1", "p2"), ("p2", "p1"), ("p3", "p4"), ("p4", "p3"), ("p4", "p5"), ("p5", "p4")]
    paths += [("p1", "p6"), ("p6", "p1"), ("p8", "p5"), ("p5", "p8")]
    paths += [("p1", "p8")] if human else [("p6", "p7"), ("p7", "p5")]
    for x, y in paths:
        p.set_initial_value(clear_path(o[x], o[y]), True)
    p.set_initial_value(clearable(o["p2"], o["p3"]), True)
    p.add_goal(picture_taken(o["p5"]))
    p.add_quality_metric(MinimizeActionCosts({move: 1, clear: 3, pic: 1}))
    return p


ROOMS_DOMAIN = """(define (domain rooms)
  (:requirements :strips :typing :negative-preconditions :action-costs)
  (:types place - object room hall - place)
  (:predicates (at ?r - place) (door ?a - place ?b - place) (locked ?r - place) (key ?r - place))
  (:functions (dist ?a - place ?b - place) (total-cost))
  (:action Go :parameters (?a - place ?b - place)
    :precondition (and (at ?a) (door ?a ?b){extra})
    :effect (and (not (at ?a)) (at ?b) (increase (total-cost) (dist ?a ?b))))
  (:action unlock :parameters (?r - place)
    :precondition (and (key ?r))
    :effect (and (not (locked ?r)) (increase (total-cost) 4))))"""

ROOMS_PROBLEM = """(define (problem rooms-1) (:domain rooms)
  (:objects h1 - hall r2 r3 r4 - room)
  (:init (at h1) (door h1 r2) (door r2 r4) (door h1 r3) (door r3 r4) (locked r2) (key r2)
         (= (dist h1 r2) 1) (= (dist r2 r4) 1) (= (dist h1 r3) 3) (= (dist r3 r4) 3)
         (= (dist h1 r3) 3) (= (dist h1 h1) 1) (= (dist h1 r4) 1) (= (dist r2 h1) 1)
         (= (dist r2 r2) 1) (= (dist r2 r3) 1) (= (dist r3 h1) 1) (= (dist r3 r2) 1)
         (= (dist r3 r3) 1) (= (dist r4 h1) 1) (= (dist r4 r2) 1) (= (dist r4 r3) 1)
         (= (dist r4 r4) 1) (= (total-cost) 0))
  (:goal (and (at r4))))"""


def _rooms(human: bool) -> Problem:
    """The rooms task above in Python: a type hierarchy, costs from a static fluent, and a
    human who believes a locked room cannot be entered (a negative precondition)."""
    place = UserType("place")
    room, hall = UserType("room", place), UserType("hall", place)
    at = Fluent("at", BoolType(), r=place)
    door = Fluent("door", BoolType(), a=place, b=place)
    locked = Fluent("locked", BoolType(), r=place)
    key = Fluent("key", BoolType(), r=place)
    dist = Fluent("dist", IntType(), a=place, b=place)
    go = InstantaneousAction("Go", a=place, b=place)  # upper case on purpose
    a, b = go.parameters
    go.add_precondition(at(a))
    go.add_precondition(door(a, b))
    if human:
        go.add_precondition(Not(locked(b)))
    go.add_effect(at(a), False)
    go.add_effect(at(b), True)
    unlock = InstantaneousAction("unlock", r=place)
    unlock.add_precondition(key(unlock.parameters[0]))
    unlock.add_effect(locked(unlock.parameters[0]), False)
    p = Problem("rooms-1")
    for f in (at, door, locked, key):
        p.add_fluent(f, default_initial_value=False)
    p.add_fluent(dist, default_initial_value=1)
    p.add_action(go)
    p.add_action(unlock)
    o = {"h1": Object("h1", hall), **{n: Object(n, room) for n in ("r2", "r3", "r4")}}
    p.add_objects(o.values())
    p.set_initial_value(at(o["h1"]), True)
    for x, y in (("h1", "r2"), ("r2", "r4"), ("h1", "r3"), ("r3", "r4")):
        p.set_initial_value(door(o[x], o[y]), True)
    p.set_initial_value(locked(o["r2"]), True)
    p.set_initial_value(key(o["r2"]), True)
    for x, y, d in (("h1", "r3", 3), ("r3", "r4", 3)):
        p.set_initial_value(dist(o[x], o[y]), d)
    p.add_goal(at(o["r4"]))
    p.add_quality_metric(MinimizeActionCosts({go: dist(a, b), unlock: 4}))
    return p


def _points(fr):
    return [(p.explanation, p.plan, p.robot_cost, p.human_cost) for p in fr.points]


def _check_plans(problem: Problem, fr) -> None:
    validator = SequentialPlanValidator()
    for point in fr.points:
        plan = point.to_up_plan(problem)
        assert isinstance(plan, SequentialPlan)
        assert len(plan.actions) == len(point.plan)
        assert all(isinstance(ai, ActionInstance) for ai in plan.actions)
        assert all(ai.action in problem.actions for ai in plan.actions)
        result = validator.validate(problem, plan)
        assert result.status.name == "VALID", result
        (cost,) = result.metric_evaluations.values()
        assert cost == point.robot_cost


def test_usar_built_in_python_gives_the_pddl_frontier():
    task = api.load_task_from_up(_usar(human=False), _usar(human=True))
    pddl = api.load_task_dir(ROOT / "domains" / "usar-fetch" / "p1")
    assert [u.name for u in task.delta] == [u.name for u in pddl.delta]
    fr, expected = api.frontier(task), api.frontier(pddl)
    assert fr.exact and expected.exact
    assert fr.robot_optimal_cost == expected.robot_optimal_cost == 4
    assert _points(fr) == _points(expected)
    assert [(p.size, p.robot_cost) for p in fr.points] == [(1, 8), (3, 4)]
    _check_plans(_usar(human=False), fr)


def test_types_negative_conditions_and_fluent_costs_match_the_pddl_text():
    robot, human = _rooms(human=False), _rooms(human=True)
    task = api.load_task_from_up(robot, human)
    pddl = api.load_task_from_strings(
        ROOMS_DOMAIN.format(extra=""),
        ROOMS_PROBLEM,
        ROOMS_DOMAIN.format(extra=" (not (locked ?b))"),
    )
    assert [u.name for u in task.delta] == [u.name for u in pddl.delta]
    assert [u.name for u in task.delta] == ["remove-go-has-negprecondition-locked ?b"]
    fr, expected = api.frontier(task), api.frontier(pddl)
    assert _points(fr) == _points(expected)
    # explicable: unlock r2 first (cost 6); robot optimal: through locked r2 (cost 2), explained
    assert [(p.size, p.robot_cost) for p in fr.points] == [(0, 6), (1, 2)]
    _check_plans(robot, fr)
    sol = api.solve(task, 10.0)
    plan = sol.to_up_plan(robot)
    assert [ai.action.name for ai in plan.actions] == ["Go", "Go"]  # the model's own names
    mce_plan = api.MegaSolver(task).explain().to_up_plan(robot)
    assert [str(ai) for ai in mce_plan.actions] == [str(ai) for ai in plan.actions]


def test_human_problem_defaults_to_the_robot_problem():
    task = api.load_task_from_up(_usar(human=False))
    assert task.delta == ()
    assert api.frontier(task).points[0].size == 0


def test_up_plan_of_an_unknown_step_is_one_clear_error():
    from mega_sat.pddl.up_models import to_up_plan

    with pytest.raises(MegaSatError, match=r"plan step '\(fly p1 p2\)' names no action"):
        to_up_plan([("fly", "p1", "p2")], _usar(False))
    with pytest.raises(MegaSatError, match=r"plan step '\(move p1\)' is no action"):
        to_up_plan([("move", "p1")], _usar(False))


def test_equality_in_a_precondition_is_read():
    task = api.load_task_from_up(_usar(False, distinct=True), _usar(False))
    assert [u.name for u in task.delta] == ["add-move-has-negprecondition-= ?a ?b"]
    assert api.frontier(task).exact


def _conditional() -> Problem:
    p = _usar(False)
    move = p.action("move")
    a, b = move.parameters
    move.add_effect(p.fluent("picture_taken")(b), True, condition=p.fluent("robot_at")(a))
    return p


def _existential() -> Problem:
    p = _usar(False)
    x = Variable("x", p.user_type("waypoint"))
    p.action("take_picture").add_precondition(Exists(p.fluent("clear_path")(x, x), x))
    return p


def _real_cost() -> Problem:
    p = _usar(False)
    p.clear_quality_metrics()
    acts = {a: 1.5 for a in p.actions}
    p.add_quality_metric(MinimizeActionCosts(acts))
    return p


def _numeric_condition() -> Problem:
    p = _usar(False)
    fuel = Fluent("fuel", RealType())
    p.add_fluent(fuel, default_initial_value=3)
    p.action("move").add_precondition(fuel() > 1)
    return p


@pytest.mark.parametrize(
    ("make", "feature"),
    [
        (_conditional, "CONDITIONAL_EFFECTS"),
        (_existential, "EXISTENTIAL_CONDITIONS"),
        (_real_cost, "REAL_NUMBERS_IN_ACTIONS_COST"),
        (_numeric_condition, "SIMPLE_NUMERIC_PLANNING"),
    ],
)
def test_other_kinds_are_refused_by_the_library_feature_name(make, feature):
    with pytest.raises(MegaSatError) as e:
        api.load_task_from_up(_usar(False), make())
    msg = str(e.value)
    assert "human_problem 'usar-p1' uses problem-kind features" in msg and feature in msg
    assert "\n" not in msg


@pytest.mark.parametrize("bad", [None, "usar", 3])
def test_a_non_problem_is_one_clear_error(bad):
    if bad is None:  # the human problem may be left out, the robot's may not
        with pytest.raises(MegaSatError, match="robot_problem must be a unified_planning"):
            api.load_task_from_up(None)
        return
    with pytest.raises(MegaSatError, match="human_problem must be a unified_planning"):
        api.load_task_from_up(_usar(False), bad)


def test_plans_found_by_mega_sat_are_optimal_for_a_up_planner_too():
    """The robot-optimal end of the frontier has the optimal cost a unified-planning planner
    finds on the robot problem, where one is installed (Fast Downward through the fd extra)."""
    from unified_planning.shortcuts import OneshotPlanner

    try:
        planner = OneshotPlanner(name="fast-downward-opt")
    except Exception:
        pytest.skip("no unified-planning optimal planner installed")
    robot = _rooms(human=False)
    with planner:
        res = planner.solve(robot)
    assert res.status == PlanGenerationResultStatus.SOLVED_OPTIMALLY
    fr = api.frontier(api.load_task_from_up(robot, _rooms(human=True)))
    (cost,) = SequentialPlanValidator().validate(robot, res.plan).metric_evaluations.values()
    assert fr.robot_optimal_cost == cost
