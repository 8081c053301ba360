"""Fast Downward wrapper: plan parsing, exit codes, and optimal costs equal the built-in's."""

from __future__ import annotations

import pytest
from helpers.fuzzing import oracle_settings
from helpers.pddl_tasks import pigeonhole
from helpers.randomtasks import models
from hypothesis import HealthCheck, given

from mega_sat.errors import PlannerError
from mega_sat.ground.grounding import ground_model
from mega_sat.ground.simulate import simulate
from mega_sat.planners.fast_downward import fd_available, fd_plan, parse_plan_text
from mega_sat.search.astar import astar

needs_fd = pytest.mark.skipif(not fd_available(), reason="Fast Downward not installed")

DOMAIN = """(define (domain t) (:requirements :strips :action-costs)
 (:predicates (at ?x) (conn ?x ?y))
 (:functions (total-cost) - number)
 (:action move :parameters (?x ?y) :precondition (and (at ?x) (conn ?x ?y))
  :effect (and (not (at ?x)) (at ?y) (increase (total-cost) 2))))
"""
PROBLEM = """(define (problem p) (:domain t) (:objects a b c)
 (:init (at a) (conn a b) (conn b c) {extra} (= (total-cost) 0))
 (:goal (at c)) (:metric minimize (total-cost)))
"""


def test_parse_plan_text():
    steps, cost = parse_plan_text("(MOVE a b)\n(move b c)\n; cost = 4 (general cost)\n")
    assert steps == (("move", "a", "b"), ("move", "b", "c")) and cost == 4
    assert parse_plan_text("; cost = 0 (unit cost)\n") == ((), 0)
    assert parse_plan_text("(noop)\n")[1] is None


@needs_fd
def test_solved_and_unsolvable():
    r = fd_plan(DOMAIN, PROBLEM.format(extra=""))
    assert r.status == "optimal" and r.cost == 4 and r.planner == "fd"
    assert r.plan == (("move", "a", "b"), ("move", "b", "c"))
    r = fd_plan(DOMAIN, PROBLEM.format(extra="").replace("(conn a b)", ""))
    assert r.status == "unsolvable" and r.plan is None
    # reachable in the relaxation, unsolvable for real: the search has to prove it
    both = PROBLEM.format(extra="").replace("(:goal (at c))", "(:goal (and (at b) (at c)))")
    r = fd_plan(DOMAIN, both)
    assert r.status == "unsolvable"


@needs_fd
def test_errors_raise_planner_error():
    with pytest.raises(PlannerError, match="Fast Downward failed") as e:
        fd_plan(
            DOMAIN.replace("(at ?x) (conn ?x ?y))", "(at ?x) ((conn ?x ?y)))", 1),
            PROBLEM.format(extra=""),
        )
    assert "Predicate name is expected to be a word" in str(e.value)
    with pytest.raises(PlannerError, match="no_such_search"):
        fd_plan(DOMAIN, PROBLEM.format(extra=""), search="no_such_search()")


@needs_fd
@oracle_settings(12, suppress_health_check=[HealthCheck.too_slow])
@given(models(allow_zero_cost=True))
def test_fd_optimal_cost_equals_builtin(model):
    from mega_sat.pddl.writer import domain_to_pddl, problem_to_pddl

    builtin = astar(ground_model(model))
    fd = fd_plan(domain_to_pddl(model), problem_to_pddl(model))
    assert fd.status == builtin.status
    assert fd.cost == builtin.cost
    if fd.plan is not None:
        sim = simulate(model, fd.plan)
        assert sim.valid and sim.cost == fd.cost


@needs_fd
def test_time_limit_gives_timeout():
    r = fd_plan(*pigeonhole(14), time_limit=1)
    assert r.status == "timeout" and r.plan is None
    assert fd_plan(*pigeonhole(3)).status == "unsolvable"
