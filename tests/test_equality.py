"""Equality in preconditions: read as the static predicate ``=``, never a model difference,
pruned where both models negate it, written back as PDDL's own equality.

The reference for the pruning is the same task with equality spelled as an ordinary static
predicate ``same`` (initial atoms ``(same o o)``), which the grounding treats like any other
predicate: the frontiers must be equal, against the brute-force oracle.
"""

from __future__ import annotations

import itertools
import re
from dataclasses import replace

import pytest
from helpers.bruteforce import brute_force_frontier
from helpers.fuzzing import oracle_settings
from helpers.randomtasks import PARAMS, two_model_tasks
from helpers.sat_families import _succ, dijkstra
from hypothesis import HealthCheck, given
from hypothesis import strategies as st

from mega_sat.api import MegaSolver, frontier
from mega_sat.engines.sat_loop import sat_frontier
from mega_sat.errors import PDDLError, UnsolvableError
from mega_sat.ground.family import GroundTask
from mega_sat.ground.grounding import ground
from mega_sat.model.features import gamma
from mega_sat.model.lifted import EQUALITY, Model
from mega_sat.model.task import TwoModelTask
from mega_sat.pddl.loading import load_task_from_strings
from mega_sat.pddl.reader import parse_model
from mega_sat.pddl.writer import domain_to_pddl, problem_to_pddl
from mega_sat.planners.fast_downward import fd_available, fd_plan
from mega_sat.search.astar import astar

ROBOT_DOMAIN = """(define (domain bw-eq)
  (:requirements :strips :equality :action-costs)
  (:constants table)
  (:predicates (on ?x ?y) (clear ?x) (handempty) (holding ?x))
  (:functions (total-cost) - number)
  (:action pick-up :parameters (?x)
    :precondition (and (on ?x table) (clear ?x) (handempty))
    :effect (and (not (on ?x table)) (not (clear ?x)) (not (handempty)) (holding ?x)
                 (increase (total-cost) 1)))
  (:action put-down :parameters (?x)
    :precondition (holding ?x)
    :effect (and (not (holding ?x)) (clear ?x) (handempty) (on ?x table)
                 (increase (total-cost) 1)))
  (:action move :parameters (?x ?from ?to)
    :precondition (and (on ?x ?from) (clear ?x) (clear ?to) (handempty)
                       (not (= ?x ?to)) (not (= ?from ?to)) (not (= ?to table)))
    :effect (and (on ?x ?to) (clear ?from) (not (on ?x ?from)) (not (clear ?to))
                 (increase (total-cost) 1)))
  (:action stack :parameters (?x ?y)
    :precondition (and (holding ?x) (clear ?y) (not (= ?x ?y)))
    :effect (and (not (holding ?x)) (not (clear ?y)) (clear ?x) (handempty) (on ?x ?y)
                 (increase (total-cost) 2)))
  (:action unstack :parameters (?x ?y)
    :precondition (and (on ?x ?y) (clear ?x) (handempty) (not (= ?y table)))
    :effect (and (holding ?x) (clear ?y) (not (clear ?x)) (not (handempty)) (not (on ?x ?y))
                 (increase (total-cost) 2))))"""

# the human does not know that a block cannot move onto itself, and thinks stacking is cheap
HUMAN_DOMAIN = ROBOT_DOMAIN.replace("(not (= ?x ?to)) ", "").replace(
    "(on ?x ?y)\n                 (increase (total-cost) 2)",
    "(on ?x ?y)\n                 (increase (total-cost) 1)",
)

PROBLEM = """(define (problem p) (:domain bw-eq)
  (:objects a b c d)
  (:init (on a b) (on b c) (on c table) (on d table) (clear a) (clear d) (handempty)
         (= (total-cost) 0))
  (:goal (and (on d a) (on c d)))
  (:metric minimize (total-cost)))"""


def _task() -> TwoModelTask:
    return load_task_from_strings(ROBOT_DOMAIN, PROBLEM, HUMAN_DOMAIN, PROBLEM)


def _named(model: Model, objects: frozenset[str]) -> Model:
    """``model`` with equality spelled as the ordinary static predicate ``same``."""

    def ren(atoms):
        return frozenset(("same", *a[1:]) if a[0] == EQUALITY else a for a in atoms)

    schemas = {
        n: replace(s, pre=ren(s.pre), negpre=ren(s.negpre)) for n, s in model.schemas.items()
    }
    init = {a for a in model.init if a[0] != EQUALITY} | {("same", o, o) for o in objects}
    predicates = {p: k for p, k in model.predicates.items() if p != EQUALITY}
    return replace(
        model, schemas=schemas, init=frozenset(init), predicates={**predicates, "same": 2}
    )


def _named_task(task: TwoModelTask) -> TwoModelTask:
    objects = task.robot.objects | task.human.objects
    return TwoModelTask.from_models(_named(task.robot, objects), _named(task.human, objects))


def _small(task: GroundTask, limit: int = 20_000) -> bool:
    """Whether ``task`` has at most ``limit`` reachable states (breadth-first)."""
    seen, frontier = {task.init}, [task.init]
    while frontier:
        nxt = []
        for state in frontier:
            for _, succ in _succ(task, state):
                if succ not in seen:
                    if len(seen) >= limit:
                        return False
                    seen.add(succ)
                    nxt.append(succ)
        frontier = nxt
    return True


def _pairs(points):
    return [(p.size, p.robot_cost) for p in points]


# ------------------------------------------------------------------------------- reading


def test_equality_is_read_as_the_static_predicate():
    m = parse_model(ROBOT_DOMAIN, PROBLEM)
    assert m.predicates[EQUALITY] == 2
    assert m.schemas["move"].negpre == {
        ("=", "?x", "?to"),
        ("=", "?from", "?to"),
        ("=", "?to", "table"),
    }
    assert {a for a in m.init if a[0] == EQUALITY} == {
        ("=", o, o) for o in ("a", "b", "c", "d", "table")
    }
    positive = ROBOT_DOMAIN.replace("(not (= ?y table))", "(= ?y ?y)")
    assert ("=", "?y", "?y") in parse_model(positive, PROBLEM).schemas["unstack"].pre
    # a domain without equality has no '=' predicate and no '=' atoms
    plain = parse_model(ROBOT_DOMAIN.replace(" (not (= ?x ?y))", ""), PROBLEM)
    assert EQUALITY in plain.predicates  # move and unstack still use it
    base = parse_model(
        "(define (domain d) (:predicates (p)) (:action a :parameters () :precondition (p)"
        " :effect (not (p))))",
        "(define (problem q) (:domain d) (:init (p)) (:goal (and)))",
    )
    assert EQUALITY not in base.predicates and not base.init - {("p",)}


@pytest.mark.parametrize(
    ("edit", "message"),
    [
        (("(on ?x ?to) (clear ?from)", "(on ?x ?to) (= ?x ?to) (clear ?from)"), "in an effect"),
        (("(on ?x ?to) (clear ?from)", "(on ?x ?to) (not (= ?x ?to))"), "in an effect"),
        (("(not (= ?x ?y))", "(not (= ?x ?z))"), "undefined variable '?z'"),
        (("(not (= ?x ?y))", "(not (= ?x ?y ?x))"), "'=' takes 2 arguments, got 3"),
        (("(not (= ?x ?y))", "(not (= ?x nowhere))"), "undefined constant 'nowhere'"),
    ],
)
def test_equality_errors_in_the_domain(edit, message):
    dom = ROBOT_DOMAIN.replace(*edit)
    assert dom != ROBOT_DOMAIN
    with pytest.raises(PDDLError, match=re.escape(message)) as e:
        parse_model(dom, PROBLEM, domain_path="d.pddl")
    assert str(e.value).startswith("d.pddl: line ")


def test_equality_in_the_goal_is_refused():
    prob = PROBLEM.replace("(on c d)", "(on c d) (= a a)")
    with pytest.raises(PDDLError, match=r"p.pddl: line 5: equality .* in the goal is not sup"):
        parse_model(ROBOT_DOMAIN, prob, problem_path="p.pddl")


# ------------------------------------------------------------------------------ two models


def test_equality_is_never_a_difference():
    """The human's domain does not use '=' at all in one schema: the difference is that
    precondition, and no initial-state '=' atom, even when one model lacks equality."""
    task = _task()
    assert [u.name for u in task.delta] == [
        "add-move-has-negprecondition-= ?to ?x",  # written one way: = is symmetric
        "add-stack-has-cost-2",
    ]
    no_eq = HUMAN_DOMAIN.replace("(not (= ?from ?to)) (not (= ?to table))", "").replace(
        "(not (= ?x ?y))", ""
    )
    no_eq = no_eq.replace("(not (= ?y table))", "")
    assert "(=" not in no_eq
    t2 = load_task_from_strings(ROBOT_DOMAIN, PROBLEM, no_eq, PROBLEM)
    assert all(u.feature.kind == "negpre" or "cost" in u.name for u in t2.delta)
    assert len(t2.delta) == 6


def test_equality_is_symmetric_and_x_equals_x_says_nothing():
    """``(= ?to ?from)`` says what ``(= ?from ?to)`` says, and ``(= ?x ?x)`` nothing: neither is
    a difference, and the shared negated equality still prunes."""
    swapped = ROBOT_DOMAIN.replace("(not (= ?from ?to))", "(not (= ?to ?from))").replace(
        "(not (= ?x ?y))", "(not (= ?y ?x)) (= ?y ?y)"
    )
    task = load_task_from_strings(ROBOT_DOMAIN, PROBLEM, swapped, PROBLEM)
    assert task.delta == ()
    steps = {(a.name, *a.args) for a in ground(task).actions}
    assert not any(s[0] == "move" and s[2] == s[3] for s in steps)
    assert not any(s[0] == "stack" and s[1] == s[2] for s in steps)


def test_groundings_both_models_forbid_are_left_out():
    fam = ground(_task())
    steps = {(a.name, *a.args) for a in fam.actions}
    assert not any(s[0] == "stack" and s[1] == s[2] for s in steps)
    assert not any(s[0] == "unstack" and s[2] == "table" for s in steps)
    # only the robot forbids moving a block onto itself: those groundings stay, guarded
    assert ("move", "a", "b", "a") in steps
    assert not any(s[0] == "move" and s[2] == s[3] for s in steps)


def test_frontier_equals_the_named_predicate_and_brute_force():
    task = _task()
    solver = MegaSolver(task)
    fr = solver.frontier()
    named = _named_task(task)
    c_r, pts, _ = brute_force_frontier(named, ground(named))
    assert fr.exact and fr.robot_optimal_cost == c_r
    assert _pairs(fr.points) == _pairs(pts)
    assert len(ground(named).actions) > len(solver.family.actions)  # the pruning did something


@st.composite
def _tasks_with_equality(draw):
    task = draw(two_model_tasks(max_delta=4))
    robot, human = task.robot, task.human
    for name in sorted(robot.schemas):
        s = robot.schemas[name]
        if len(s.params) < 2 or draw(st.integers(0, 2)) == 0:
            continue
        atom = ("=", *PARAMS[:2]) if draw(st.booleans()) else ("=", PARAMS[1], PARAMS[0])
        negated = draw(st.booleans())
        field = "negpre" if negated else "pre"
        owners = draw(st.sampled_from(["robot", "human", "both", "both"]))
        if owners != "human":
            s2 = replace(s, **{field: getattr(s, field) | {atom}})
            robot = replace(robot, schemas={**robot.schemas, name: s2})
        h = human.schemas.get(name)
        if h is not None and len(h.params) == 2 and owners != "robot":
            h2 = replace(h, **{field: getattr(h, field) | {atom}})
            human = replace(human, schemas={**human.schemas, name: h2})
    objects = robot.objects | human.objects
    preds = {EQUALITY: 2}
    robot = replace(robot, predicates={**robot.predicates, **preds})
    human = replace(human, predicates={**human.predicates, **preds})
    # the reader gives both models the identity atoms; from_models completes them
    robot = replace(robot, init=robot.init | {(EQUALITY, o, o) for o in sorted(objects)[:1]})
    return TwoModelTask.from_models(robot, human)


@oracle_settings(60, suppress_health_check=[HealthCheck.too_slow, HealthCheck.filter_too_much])
@given(_tasks_with_equality())
def test_random_equalities_against_the_named_predicate(task):
    _check_against_named(task)


# two tasks whose groundings keep different dead actions.  In the first, "=" rules out
# (mark o0 o0) while grounding, so (p2 o0) is never reached and (use o0 ?y) goes too, which
# the named predicate keeps; in the second, the human's (a0 ?x) needs (p0 ?x ?x) false, which
# no action can make true
CHAIN_DOMAIN = """(define (domain chain-eq)
  (:requirements :strips :equality :negative-preconditions)
  (:predicates (done) (p1 ?x) (p2 ?x))
  (:action mark :parameters (?x ?y)
    :precondition (and (p1 ?x) (not (= ?x ?y))) :effect (p2 ?y))
  (:action use :parameters (?x ?y) :precondition (p2 ?x) :effect (done)))"""

CHAIN_PROBLEM = """(define (problem p) (:domain chain-eq) (:objects o0 o1)
  (:init (p1 o0)) (:goal (done)))"""

SELF_DOMAIN = """(define (domain self-eq)
  (:requirements :strips :equality :negative-preconditions)
  (:predicates (p0 ?x ?y) (p1))
  (:action a0 :parameters (?x) :precondition (and) :effect (p1))
  (:action a1 :parameters (?x ?y) :precondition (not (= ?x ?y)) :effect (p0 ?x ?y)))"""

SELF_PROBLEM = """(define (problem p) (:domain self-eq) (:objects o0 o1)
  (:init) (:goal (p0 o0 o0)))"""


@pytest.mark.parametrize(
    "robot, human, problem",
    [
        (CHAIN_DOMAIN, CHAIN_DOMAIN, CHAIN_PROBLEM),
        (
            SELF_DOMAIN,
            SELF_DOMAIN.replace("(and) :effect (p1)", "(not (p0 ?x ?x)) :effect (p1)"),
            SELF_PROBLEM,
        ),
    ],
)
def test_groundings_that_keep_different_dead_actions_agree(robot, human, problem):
    task = load_task_from_strings(robot, problem, human, problem)
    steps = {a.step for a in ground(task).actions}
    assert steps != {a.step for a in ground(_named_task(task)).actions}
    _check_against_named(task)


def _check_against_named(task: TwoModelTask) -> None:
    """Grounding and frontier of ``task`` against the same task with the named predicate."""
    objects = task.robot.objects | task.human.objects
    identity = {(EQUALITY, o, o) for o in objects}
    assert identity <= task.robot.init and identity <= task.human.init
    assert not any(u.feature.kind == "init" and u.feature.atom[0] == EQUALITY for u in task.delta)
    named = _named_task(task)
    assert sorted(u.name.replace("-same ", "-= ") for u in named.delta) == sorted(
        u.name for u in task.delta
    )
    fam, fam_named = ground(task), ground(named)
    # every member of the family has the same optimal cost.  Not always the same live actions:
    # "=" is decided while grounding, before reachability, and the two groundings then prune
    # dead and duplicate actions differently, in either direction
    by_name = {u.name: i for i, u in enumerate(named.delta)}
    for k in range(len(task.delta) + 1):
        for sel in itertools.combinations(range(len(task.delta)), k):
            sel_named = frozenset(by_name[task.delta[i].name.replace("-= ", "-same ")] for i in sel)
            member, member_named = fam.specialize(frozenset(sel)), fam_named.specialize(sel_named)
            if _small(member) and _small(member_named):
                assert dijkstra(member) == dijkstra(member_named)
    try:
        c_r, pts, _ = brute_force_frontier(named, fam_named, state_limit=20_000)
    except ValueError:
        with pytest.raises(UnsolvableError):
            sat_frontier(task, fam)
        return
    c_eq, pts_eq, _ = brute_force_frontier(task, fam, state_limit=20_000)
    assert (c_eq, _pairs(pts_eq)) == (c_r, _pairs(pts))
    fr = sat_frontier(task, fam)
    assert fr.robot_optimal_cost == c_r and _pairs(fr.points) == _pairs(pts)


# ---------------------------------------------------------------------- writing, FD


def test_written_model_uses_pddl_equality_and_reads_back_the_same():
    task = _task()
    model = task.updated_model(range(len(task.delta)))
    dom, prob = domain_to_pddl(model), problem_to_pddl(model)
    assert ":equality" in dom and "(not (= ?to ?x))" in dom
    assert "(= " not in dom.split("(:predicates")[1].split(")\n")[0]
    assert "(= a a)" not in prob
    back = parse_model(dom, prob)
    assert gamma(back) == gamma(model)


@pytest.mark.skipif(not fd_available(), reason="Fast Downward not installed")
def test_optimal_costs_agree_with_fast_downward_on_the_original_files():
    task = _task()
    solver = MegaSolver(task)
    for dom, model in ((ROBOT_DOMAIN, task.robot), (HUMAN_DOMAIN, task.human)):
        fd = fd_plan(dom, PROBLEM)
        ours = solver.family.specialize(
            solver.family.robot_selection if model is task.robot else frozenset()
        )
        assert astar(ours).cost == fd.cost


def test_several_human_models_of_which_one_uses_equality():
    """Each pair gives its robot model (= o o) over all objects of every pair, so the robot
    models agree whichever human models use equality and whatever objects they add."""
    from mega_sat.pddl.multi_task import MultiHumanTask

    robot = parse_model(HUMAN_DOMAIN, PROBLEM)  # a robot without '=' in move
    plain = ROBOT_DOMAIN.replace("(not (= ?x ?y))", "").replace(" (not (= ?y table))", "")
    plain = plain.replace("(not (= ?x ?to)) (not (= ?from ?to)) (not (= ?to table))", "")
    assert "(=" not in plain
    extra = PROBLEM.replace("(:objects a b c d)", "(:objects a b c d e)")
    humans = [parse_model(ROBOT_DOMAIN, PROBLEM), parse_model(plain, extra)]
    multi = MultiHumanTask.from_models(robot, humans)
    assert all(t.robot == multi.robot for t in multi.tasks)
    assert ("=", "e", "e") in multi.robot.init
    assert not any(u.feature.kind == "init" and u.feature.atom[0] == "=" for u in multi.delta)
    assert frontier(multi).exact
