"""VAL wrapper: verdicts on hand-written PDDL, and agreement with the simulator."""

from __future__ import annotations

import pytest
from helpers.fuzzing import oracle_settings
from helpers.randomtasks import models, plans
from hypothesis import HealthCheck, given
from hypothesis import strategies as st

from mega_sat.ground.simulate import simulate
from mega_sat.planners.val import val_available, val_validate

pytestmark = pytest.mark.skipif(not val_available(), reason="VAL not installed")

DOMAIN = """(define (domain t) (:requirements :strips :action-costs)
 (:predicates (at ?x) (conn ?x ?y))
 (:functions (total-cost) - number)
 (:action move :parameters (?x ?y) :precondition (and (at ?x) (conn ?x ?y))
  :effect (and (not (at ?x)) (at ?y) (increase (total-cost) 2))))
"""
PROBLEM = """(define (problem p) (:domain t) (:objects a b c)
 (:init (at a) (conn a b) (conn b c) (= (total-cost) 0))
 (:goal (at c)) (:metric minimize (total-cost)))
"""


def test_verdicts():
    r = val_validate(DOMAIN, PROBLEM, [("move", "a", "b"), ("move", "b", "c")])
    assert r.valid and r.cost == 4
    r = val_validate(DOMAIN, PROBLEM, [("move", "a", "b"), ("move", "a", "c")])
    assert not r.valid and r.cost is None
    assert r.message == "unsatisfied precondition at step 2: (move a c)"
    r = val_validate(DOMAIN, PROBLEM, [("move", "a", "b")])
    assert not r.valid and r.message == "goal not satisfied"
    r = val_validate(DOMAIN, PROBLEM, [("fly", "a")])
    assert not r.valid and "fly" in r.message


@oracle_settings(40, suppress_health_check=[HealthCheck.too_slow])
@given(data=st.data())
def test_val_agrees_with_simulate(data):
    from mega_sat.pddl.writer import domain_to_pddl, problem_to_pddl

    model = data.draw(models(allow_zero_cost=True))
    # VAL ignores surplus arguments, so malformed steps are the simulator's business only
    plan = data.draw(plans(model, max_len=5, malformed=False))
    sim = simulate(model, plan)
    val = val_validate(domain_to_pddl(model), problem_to_pddl(model), plan)
    assert val.valid == sim.valid, (sim.reason, val.message)
    assert val.cost == sim.cost


@pytest.mark.parametrize(
    ("plan", "why"),
    [
        ("(move p1)\n", "wrong number of arguments (expected 2, got 1)"),
        ("(move p1 p6 p7)\n", "wrong number of arguments (expected 2, got 3)"),
        ("(fly p1 p6)\n", "unknown action 'fly'"),
    ],
)
def test_verify_does_not_hand_val_steps_it_cannot_read(plan, why, tmp_path):
    """A step with too few arguments crashed VAL (SIGSEGV, so ``verify`` exited 4 without its
    report); such steps now fail VAL's checks as "not run", and ``verify`` exits 1."""
    from pathlib import Path

    from click.testing import CliRunner

    from mega_sat.cli.commands import main

    root = Path(__file__).resolve().parent.parent
    (tmp_path / "x.plan").write_text(plan)
    res = CliRunner().invoke(
        main,
        [
            "verify",
            "--task",
            str(root / "domains/usar-fetch/p1"),
            "--plan",
            str(tmp_path / "x.plan"),
            "--explanation",
            str(root / "docs/examples/usar-p1-low-alpha.explanation"),
        ],
    )
    assert res.exit_code == 1, res.output
    val_lines = [ln for ln in res.output.splitlines() if ln.startswith("FAIL VAL:")]
    assert len(val_lines) == 2 and all("not run: step 1" in ln and why in ln for ln in val_lines)


def test_variables_val_reserves_are_written_by_position(tmp_path):
    """VAL refuses variables named ?after, ?either, ?number (legal PDDL): the PDDL written for
    VAL and Fast Downward names parameters by position, so --verify checks such a model."""
    from mega_sat.api import MegaSolver, load_task_from_strings
    from mega_sat.pddl.writer import domain_to_pddl

    dom = """(define (domain d) (:requirements :strips)
      (:predicates (p ?x) (q ?x ?y))
      (:action a :parameters (?after ?either) :precondition (p ?after)
        :effect (and (q ?after ?either) (not (p ?after)))))"""
    prob = "(define (problem p1) (:domain d) (:objects o r) (:init (p o)) (:goal (q o r)))"
    task = load_task_from_strings(dom, prob, dom.replace("(not (p ?after))", ""), prob)
    assert "(?after ?either)" in domain_to_pddl(task.robot)
    assert "(?v0 ?v1)" in domain_to_pddl(task.robot, plain_variables=True)
    solver = MegaSolver(task)
    point = solver.frontier().points[0]
    report = solver.verify(point)
    assert report.ok and any(c.name.startswith("VAL") for c in report.checks), report.lines()


def test_names_val_reserves_are_renamed_for_it():
    """VAL cannot read a file naming an object 'within', a predicate 'number', an action
    'after', a function 'duration', a domain or a problem so (legal PDDL): they are renamed in
    what VAL gets."""
    from mega_sat.api import MegaSolver, load_task_from_strings
    from mega_sat.planners.val import val_names

    dom = """(define (domain within) (:requirements :strips :action-costs)
      (:predicates (number ?x) (q ?x))
      (:functions (duration ?x) - number (total-cost) - number)
      (:action after :parameters (?x) :precondition (number ?x)
        :effect (and (q ?x) (not (number ?x)) (increase (total-cost) (duration ?x)))))"""
    prob = """(define (problem number) (:domain within) (:objects within number-v)
      (:init (number within) (= (duration within) 3) (= (duration number-v) 1))
      (:goal (q within)))"""
    task = load_task_from_strings(dom, prob, dom.replace("(not (number ?x))", ""), prob)
    solver = MegaSolver(task)
    point = solver.frontier().points[0]
    assert point.plan == (("after", "within"),) and point.robot_cost == 3
    report = solver.verify(point)
    assert report.ok and any(c.name.startswith("VAL") for c in report.checks), report.lines()
    model, plan = val_names(task.robot, point.plan)
    assert plan == (("after-v", "within-v"),) and "number-v1" in model.predicates
    assert (model.domain_name, model.problem_name) == ("within-v", "number-v1")
    assert model.functions == {("duration-v", "within-v"): 3, ("duration-v", "number-v"): 1}
