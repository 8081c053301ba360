"""A human model written without the robot's costs: a human domain with no cost function (or no
``:action-costs`` at all) against a robot whose moves cost a distance.

The human's schemas cost 1; the robot's ``move`` costs ``(dist ?a ?b)``.  The distances are
values of a function only the robot's domain declares, so the human takes them from the robot
problem (the human holds none to differ from), and the cost update alone brings them into
``human + E``.  The robot's problem also serves as the human's when none is given; what the
human domain cannot read there (``(total-cost)``, the distances, the metric) is left out.
"""

from __future__ import annotations

import pytest
from helpers.bruteforce import brute_force_frontier

from mega_sat.api import frontier
from mega_sat.errors import MegaSatError, PDDLError
from mega_sat.ground.grounding import ground
from mega_sat.model.features import COST
from mega_sat.pddl.loading import load_task_dir, load_task_from_strings
from mega_sat.pddl.writer import domain_to_pddl, problem_to_pddl

ROBOT_DOMAIN = """(define (domain deliver)
  (:requirements :strips :typing :action-costs)
  (:types loc pkg)
  (:predicates (at ?l - loc) (road ?a ?b - loc) (has ?p - pkg) (pkg-at ?p - pkg ?l - loc))
  (:functions (total-cost) - number (dist ?a ?b - loc) - number)
  (:action move :parameters (?a ?b - loc)
    :precondition (and (at ?a) (road ?a ?b))
    :effect (and (not (at ?a)) (at ?b) (increase (total-cost) (dist ?a ?b))))
  (:action pick :parameters (?p - pkg ?l - loc)
    :precondition (and (at ?l) (pkg-at ?p ?l))
    :effect (and (has ?p) (not (pkg-at ?p ?l)) (increase (total-cost) 1)))
  (:action drop :parameters (?p - pkg ?l - loc)
    :precondition (and (at ?l) (has ?p))
    :effect (and (not (has ?p)) (pkg-at ?p ?l) (increase (total-cost) 1))))"""

# no costs at all, and picking up needs no package there
HUMAN_DOMAIN = """(define (domain deliver)
  (:requirements :strips :typing)
  (:types loc pkg)
  (:predicates (at ?l - loc) (road ?a ?b - loc) (has ?p - pkg) (pkg-at ?p - pkg ?l - loc))
  (:action move :parameters (?a ?b - loc)
    :precondition (and (at ?a) (road ?a ?b))
    :effect (and (not (at ?a)) (at ?b)))
  (:action pick :parameters (?p - pkg ?l - loc)
    :precondition (at ?l)
    :effect (and (has ?p) (not (pkg-at ?p ?l))))
  (:action drop :parameters (?p - pkg ?l - loc)
    :precondition (and (at ?l) (has ?p))
    :effect (and (not (has ?p)) (pkg-at ?p ?l))))"""

ROADS = "(road a b) (road b a) (road b c) (road c b) (road a c) (road c a)"
DISTANCES = (
    "(= (dist a b) 3) (= (dist b a) 3) (= (dist b c) 3) (= (dist c b) 3) "
    "(= (dist a c) 10) (= (dist c a) 10)"
)

ROBOT_PROBLEM = f"""(define (problem p) (:domain deliver)
  (:objects a b c - loc p - pkg)
  (:init (at a) (pkg-at p b) {ROADS}
         (= (total-cost) 0) {DISTANCES})
  (:goal (and (pkg-at p c) (at a)))
  (:metric minimize (total-cost)))"""

HUMAN_PROBLEM = f"""(define (problem p) (:domain deliver)
  (:objects a b c - loc p - pkg)
  (:init (at a) (pkg-at p b) {ROADS})
  (:goal (and (pkg-at p c) (at a))))"""


def _pairs(points) -> list[tuple[int, int]]:
    return [(len(p.explanation), p.robot_cost) for p in points]


@pytest.mark.parametrize("human_problem", [HUMAN_PROBLEM, None], ids=["own", "robot's"])
def test_the_human_takes_the_robot_distances_and_the_cost_update_brings_them(human_problem):
    task = load_task_from_strings(ROBOT_DOMAIN, ROBOT_PROBLEM, HUMAN_DOMAIN, human_problem)
    names = task.names(task.all_updates)
    assert names == [
        "add-pick-has-precondition-pkg-at ?p ?l",
        "add-move-has-cost-(dist ?a ?b)",
    ]
    assert task.human.functions == task.robot.functions  # no value is a difference
    cost = next(i for i, u in enumerate(task.delta) if u.feature.kind == COST)
    updated = task.updated_model(frozenset({cost}))
    assert updated.schema_cost(updated.schemas["move"], ("a", "c")) == 10
    # with unit costs the human returns by the direct road (and picks p up anywhere); once
    # moves cost their distances, the robot's way there and back via b (3+1+3+1+3+3 = 14) is
    # as cheap as any plan of the human's, wherever p is picked up
    c_r, pts, _ = brute_force_frontier(task, ground(task))
    fr = frontier(task)
    assert fr.exact and fr.robot_optimal_cost == c_r == 14
    assert _pairs(fr.points) == _pairs(pts) == [(1, 14)]
    assert fr.points[0].explanation == ("add-move-has-cost-(dist ?a ?b)",)


def test_the_updated_human_model_is_written_with_the_distances():
    task = load_task_from_strings(ROBOT_DOMAIN, ROBOT_PROBLEM, HUMAN_DOMAIN)
    updated = task.updated_model(task.all_updates)
    domain, problem = domain_to_pddl(updated), problem_to_pddl(updated)
    assert "(increase (total-cost) (dist ?a ?b))" in domain and "(dist ?x0 ?x1)" in domain
    assert "(= (dist a c) 10)" in problem
    again = load_task_from_strings(ROBOT_DOMAIN, ROBOT_PROBLEM, domain, problem)
    assert again.delta == ()


def test_constant_robot_costs_with_the_robot_problem_for_both():
    """The commonest first model: the human domain is the robot's without ``:action-costs``,
    and one problem with ``(= (total-cost) 0)`` and a metric serves both."""
    robot = ROBOT_DOMAIN.replace("(dist ?a ?b))", "2)").replace(" (dist ?a ?b - loc) - number", "")
    problem = ROBOT_PROBLEM.replace(DISTANCES, "")
    task = load_task_from_strings(robot, problem, HUMAN_DOMAIN)
    assert task.names(task.all_updates) == [
        "add-pick-has-precondition-pkg-at ?p ?l",
        "add-move-has-cost-2",
    ]
    assert _pairs(frontier(task).points) == [(1, 8)]


def test_a_human_problem_of_its_own_is_still_checked():
    """Only the robot's problem, borrowed, may hold what the human domain does not declare."""
    own = ROBOT_PROBLEM.replace("(define (problem p)", "(define (problem h)")
    with pytest.raises(MegaSatError, match=r"human problem: line 4: \(total-cost\) is not decl"):
        load_task_from_strings(ROBOT_DOMAIN, ROBOT_PROBLEM, HUMAN_DOMAIN, own)


def test_a_function_the_human_declares_keeps_its_own_values():
    """A human domain that declares ``dist`` holds its own values: one it lacks is an error,
    one it gives otherwise is an update."""
    human = ROBOT_DOMAIN
    lacking = ROBOT_PROBLEM.replace("(= (dist c a) 10)", "")
    with pytest.raises(MegaSatError, match=r"robot problem: line 4: cost function value"):
        load_task_from_strings(ROBOT_DOMAIN, ROBOT_PROBLEM, human, lacking)
    other = ROBOT_PROBLEM.replace("(= (dist c a) 10)", "(= (dist c a) 1)")
    task = load_task_from_strings(ROBOT_DOMAIN, ROBOT_PROBLEM, human, other)
    assert task.names(task.all_updates) == ["add-has-initial-value-dist c a=10"]


def test_an_object_only_the_human_problem_has_is_named_where_it_is_declared(tmp_path):
    """A human problem with an extra location ``w``: the human's ``(move a w)`` may cost the
    robot's ``(dist a w)`` under the cost update, and the robot problem, where the distances
    come from, has no ``w``.  The error names the object's line, not the robot problem."""
    human_problem = HUMAN_PROBLEM.replace("(:objects a b c - loc", "(:objects a b c\n w - loc")
    human_problem = human_problem.replace(ROADS, ROADS + " (road a w) (road w a)")
    files = {
        "robot-domain.pddl": ROBOT_DOMAIN,
        "robot-problem.pddl": ROBOT_PROBLEM,
        "human-domain.pddl": HUMAN_DOMAIN,
        "human-problem.pddl": human_problem,
    }
    for name, text in files.items():
        (tmp_path / name).write_text(text)
    task = load_task_dir(tmp_path)
    with pytest.raises(PDDLError) as info:
        ground(task)
    assert str(info.value) == (
        f"{tmp_path / 'human-problem.pddl'}: line 3: object 'w' is declared only in this "
        "problem, and the cost of (move a w) in the robot's model is (dist a w), which has no "
        f"value: declare 'w' in {tmp_path / 'robot-problem.pddl'} too and give "
        "(= (dist a w) N) in :init"
    )
    # read from strings, the same message without a line
    task = load_task_from_strings(ROBOT_DOMAIN, ROBOT_PROBLEM, HUMAN_DOMAIN, human_problem)
    with pytest.raises(PDDLError, match=r"human problem: object 'w' is declared only in this"):
        ground(task)


def test_a_function_only_the_human_declares_prices_the_human_moves():
    """The other way round: the human believes moves cost their distances, the robot's cost
    1.  The distances are the human's own beliefs, which no update reaches; the cost update
    alone brings the robot's unit cost."""
    robot = HUMAN_DOMAIN  # no costs: every action costs 1
    task = load_task_from_strings(robot, HUMAN_PROBLEM, ROBOT_DOMAIN, ROBOT_PROBLEM)
    assert task.names(task.all_updates) == [
        "remove-pick-has-precondition-pkg-at ?p ?l",
        "add-move-has-cost-1",
    ]
    assert not task.robot.functions and task.human.functions[("dist", "a", "c")] == 10
    c_r, pts, _ = brute_force_frontier(task, ground(task))
    fr = frontier(task)
    assert fr.exact and fr.robot_optimal_cost == c_r == 4
    assert _pairs(fr.points) == _pairs(pts) == [(0, 6), (1, 5), (2, 4)]
    # the updated human model is written with its distances and read back as the same model
    updated = task.updated_model(frozenset({1}))
    assert updated.schema_cost(updated.schemas["move"], ("a", "c")) == 1
    domain, problem = domain_to_pddl(updated), problem_to_pddl(updated)
    again = load_task_from_strings(robot, HUMAN_PROBLEM, domain, problem)
    assert again.names(again.all_updates) == ["remove-pick-has-precondition-pkg-at ?p ?l"]
