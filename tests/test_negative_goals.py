"""Negative goals, ``(not (p ...))`` in ``:goal``: read, differences of their own, written back,
and compiled in the ground family into positive goals on complement atoms.

The reference is independent of that compilation: a Dijkstra over the *lifted* models' states
(every applicable step by brute force over the objects, the goal tested literally, negative
goals included) gives each selection's optimal human cost and the cheapest robot cost among
plans optimal for the human, from which the frontier follows.
"""

from __future__ import annotations

import heapq
import itertools
import json
from dataclasses import replace

import pytest
from click.testing import CliRunner
from helpers.fuzzing import oracle_settings
from helpers.randomtasks import applicable_steps, ground_atoms, two_model_tasks
from hypothesis import assume, given
from hypothesis import strategies as st

from mega_sat.api import frontier
from mega_sat.cli.commands import main
from mega_sat.engines.sat_loop import sat_frontier
from mega_sat.errors import PDDLError, UnsolvableError
from mega_sat.ground.grounding import complement_atom, ground
from mega_sat.ground.simulate import simulate
from mega_sat.model.features import NEGGOAL
from mega_sat.model.lifted import Atom, Model, PlanStep
from mega_sat.model.task import TwoModelTask
from mega_sat.pddl.loading import load_task_from_strings
from mega_sat.pddl.reader import parse_model
from mega_sat.pddl.writer import domain_to_pddl, problem_to_pddl
from mega_sat.planners.fast_downward import fd_available, fd_plan
from mega_sat.results import pareto_filter

# ---------------------------------------------------------------- the lifted reference

State = frozenset[Atom]


def _step(model: Model, state: State, step: PlanStep) -> tuple[State, int]:
    s = model.schemas[step[0]]
    b = dict(zip(s.params, step[1:], strict=True))

    def g(a: Atom) -> Atom:
        return (a[0], *(b.get(x, x) for x in a[1:]))

    after = (state - {g(a) for a in s.delete}) | {g(a) for a in s.add}
    return frozenset(after), model.schema_cost(s, step[1:])


def _goal(model: Model, state: State) -> bool:
    return model.goal <= state and not (model.neggoal & state)


def _optimum(model: Model) -> int | None:
    best, heap = {model.init: 0}, [(0, 0, model.init)]
    tie = itertools.count(1)
    while heap:
        g, _, s = heapq.heappop(heap)
        if g > best[s]:
            continue
        if _goal(model, s):
            return g
        for step in applicable_steps(model, s):
            t, c = _step(model, s, step)
            if g + c < best.get(t, g + c + 1):
                best[t] = g + c
                heapq.heappush(heap, (g + c, next(tie), t))
    return None


def _cheapest_for_robot(robot: Model, human: Model, bound: int) -> int | None:
    """The cheapest robot cost of a plan valid in both models whose human cost is ``bound``."""
    start = (robot.init, human.init, 0)
    best, heap = {start: 0}, [(0, 0, start)]
    tie = itertools.count(1)
    while heap:
        g, _, node = heapq.heappop(heap)
        if g > best[node]:
            continue
        rs, hs, hc = node
        if hc == bound and _goal(robot, rs) and _goal(human, hs):
            return g
        shared = set(applicable_steps(robot, rs)) & set(applicable_steps(human, hs))
        for step in sorted(shared):
            r2, rc = _step(robot, rs, step)
            h2, c = _step(human, hs, step)
            if hc + c > bound:
                continue
            nxt = (r2, h2, hc + c)
            if g + rc < best.get(nxt, g + rc + 1):
                best[nxt] = g + rc
                heapq.heappush(heap, (g + rc, next(tie), nxt))
    return None


def lifted_frontier(task: TwoModelTask) -> tuple[int | None, list[tuple[int, int]]]:
    """``(C*_R, [(|E|, robot cost), ...])`` by the lifted reference."""
    c_r = _optimum(task.robot)
    if c_r is None:
        return None, []
    found = []
    for k in range(len(task.delta) + 1):
        for sel in itertools.combinations(range(len(task.delta)), k):
            human = task.updated_model(sel)
            c_h = _optimum(human)
            if c_h is None:
                continue
            cost = _cheapest_for_robot(task.robot, human, c_h)
            if cost is not None:
                found.append((k, cost))
    best: list[tuple[int, int]] = []
    for k, cost in sorted(found):
        if not best or cost < best[-1][1]:
            best.append((k, cost))
    return c_r, best


def _pairs(points) -> list[tuple[int, int]]:
    return [(len(p.explanation), p.robot_cost) for p in points]


# ---------------------------------------------------------------- a hand-made task

DOMAIN = """(define (domain lights)
  (:requirements :strips :negative-preconditions :action-costs)
  (:predicates (on ?l) (at ?l) (lamp ?l) (road ?a ?b))
  (:functions (total-cost) - number)
  (:action switch-off :parameters (?l)
    :precondition (and (lamp ?l) (on ?l) (at ?l))
    :effect (and (not (on ?l)) (increase (total-cost) 1)))
  (:action switch-on :parameters (?l)
    :precondition (and (lamp ?l) (not (on ?l)) (at ?l))
    :effect (and (on ?l) (increase (total-cost) 1)))
  (:action walk :parameters (?a ?b)
    :precondition (and (at ?a) (road ?a ?b))
    :effect (and (not (at ?a)) (at ?b) (increase (total-cost) 2))))"""

# the human thinks walking to a lamp switches it off on the way
HUMAN_DOMAIN = DOMAIN.replace(
    "(and (not (at ?a)) (at ?b) (increase", "(and (not (at ?a)) (at ?b) (not (on ?b)) (increase"
)

PROBLEM = """(define (problem p) (:domain lights)
  (:objects a b c)
  (:init (lamp a) (lamp b) (lamp c) (on a) (on b) (at c) (road c a) (road a c) (road c b)
         (road b c) (= (total-cost) 0))
  (:goal (and (not (on a)) (not (on b)) (at c)))
  (:metric minimize (total-cost)))"""

# the human also thinks lamp b may stay on
HUMAN_PROBLEM = PROBLEM.replace(" (not (on b))", "")


def _task() -> TwoModelTask:
    return load_task_from_strings(DOMAIN, PROBLEM, HUMAN_DOMAIN, HUMAN_PROBLEM)


def test_negative_goals_are_read_and_are_updates_of_their_own():
    task = _task()
    assert task.robot.neggoal == {("on", "a"), ("on", "b")} and task.robot.goal == {("at", "c")}
    assert task.names(task.all_updates) == [
        "add-has-negative-goal-state-on b",
        "remove-walk-has-delete-effect-on ?b",
    ]
    assert task.delta[0].feature.kind == NEGGOAL


def test_the_hand_made_task_against_the_lifted_reference_and_the_validators():
    task = _task()
    c_r, points = lifted_frontier(task)
    fr = frontier(task)
    assert fr.exact and fr.robot_optimal_cost == c_r == 10
    assert _pairs(fr.points) == points
    for p in fr.points:  # each plan meets the goal of both models, negative goals included
        assert simulate(task.robot, p.plan).cost == p.robot_cost
        assert simulate(task.updated_model(p.selection), p.plan).cost == p.human_cost
    astar = frontier(task, engine="astar")
    assert _pairs(astar.points) == points  # the baseline's own compilation-free planner path


def test_a_plan_that_leaves_a_negative_goal_true_fails_with_its_reason():
    task = _task()
    plan = [("walk", "c", "a"), ("switch-off", "a"), ("walk", "a", "c")]
    sim = simulate(task.robot, plan)
    assert not sim.valid and sim.reason == "goal (not (on b)) not reached"
    walks = [("walk", "c", "a"), ("walk", "a", "c")]  # the human's walk switches a off
    assert simulate(task.human, walks).valid
    assert simulate(task.robot, walks).reason == "goal (not (on a)) not reached"


def test_complement_atoms_follow_every_effect_under_its_guard():
    task = _task()
    fam = ground(task)
    comp = {fam.atom_index[complement_atom(("on", x))] for x in "ab"}
    assert {p for p, _ in fam.goal} >= comp
    for sel in (frozenset(), task.all_updates):
        member = fam.specialize(sel)
        walk_to_b = member.by_step[("walk", "c", "b")]
        has = fam.atom_index[complement_atom(("on", "b"))] in walk_to_b.add
        assert has == (sel == frozenset())  # only the human's walk switches b off


MOVE_DOMAIN = """(define (domain move-light)
  (:requirements :strips :action-costs)
  (:predicates (on ?l) (lamp ?l))
  (:functions (total-cost) - number (c ?l) - number)
  (:action move-light :parameters (?x ?y)
    :precondition (and (on ?x) (lamp ?y))
    :effect (and (not (on ?x)) (on ?y) (increase (total-cost) (c ?y))))
  (:action off :parameters (?x)
    :precondition (on ?x)
    :effect (and (not (on ?x)) (increase (total-cost) 5))))"""

MOVE_PROBLEM = """(define (problem p) (:domain move-light)
  (:objects a b)
  (:init (lamp a) (lamp b) (on a) (= (c a) 1) (= (c b) 3) (= (total-cost) 0))
  (:goal (not (on a))))"""


def test_an_action_that_adds_and_deletes_a_negative_goal_atom():
    """``(move-light a a)`` deletes and adds ``(on a)``: PDDL's add wins, so it leaves the lamp
    on for the robot; the human, who lacks the add, thinks it switches the lamp off."""
    human = MOVE_DOMAIN.replace(" (on ?y) (increase", " (increase")
    task = load_task_from_strings(MOVE_DOMAIN, MOVE_PROBLEM, human)
    assert task.names(task.all_updates) == ["add-move-light-has-add-effect-on ?y"]
    fam = ground(task)
    off_a = fam.atom_index[complement_atom(("on", "a"))]
    stay = fam.actions[fam.action_index[("move-light", "a", "a")]]
    assert (off_a, (0, False)) in stay.add  # the complement only while the add is absent
    for sel in (frozenset(), task.all_updates):
        member = fam.specialize(sel)
        assert (off_a in member.by_step[("move-light", "a", "a")].add) == (sel == frozenset())
    c_r, points = lifted_frontier(task)
    fr = frontier(task)
    assert fr.robot_optimal_cost == c_r == 3 and _pairs(fr.points) == points == [(1, 3)]


def test_an_add_and_a_delete_under_two_updates_is_one_clear_error():
    """The human lacks both effects of ``move-light``: the complement's add would need a guard
    of two literals."""
    human = MOVE_DOMAIN.replace("(and (not (on ?x)) (on ?y) (increase", "(and (increase")
    task = load_task_from_strings(MOVE_DOMAIN, MOVE_PROBLEM, human)
    with pytest.raises(PDDLError) as info:
        ground(task)
    assert str(info.value) == (
        "robot domain: negative goal (not (on a)): action (move-light a a) both adds and "
        "deletes that atom under two different updates, which mega-sat cannot compile (an "
        "inequality precondition of 'move-light' in both models that rules out this grounding "
        "avoids it)"
    )
    # the way out the message names: (move-light a a) is left out of grounding
    distinct = "(and (on ?x) (lamp ?y) (not (= ?x ?y)))"
    robot = MOVE_DOMAIN.replace("(and (on ?x) (lamp ?y))", distinct)
    human = human.replace("(and (on ?x) (lamp ?y))", distinct)
    task = load_task_from_strings(robot, MOVE_PROBLEM, human)
    c_r, points = lifted_frontier(task)
    assert _pairs(frontier(task).points) == points and c_r == 3
    # a schema only the human has is named in the human's domain
    shift = """  (:action shift :parameters (?x ?y)
    :precondition (and (on ?x) (lamp ?y))
    :effect (and (not (on ?x)) (on ?y) (increase (total-cost) 1)))
  (:action off"""
    task = load_task_from_strings(
        MOVE_DOMAIN, MOVE_PROBLEM, MOVE_DOMAIN.replace("  (:action off", shift), None
    )
    with pytest.raises(PDDLError, match=r"^human domain: .*action \(shift a a\)"):
        ground(task)
    # one lifted atom both added and deleted: no inequality helps, and none is suggested
    same = shift.replace("(?x ?y)", "(?x)").replace("(lamp ?y)", "(lamp ?x)")
    same = same.replace("(not (on ?x)) (on ?y)", "(not (on ?x)) (on ?x)")
    task = load_task_from_strings(
        MOVE_DOMAIN, MOVE_PROBLEM, MOVE_DOMAIN.replace("  (:action off", same), None
    )
    with pytest.raises(PDDLError, match=r"action \(shift a\) .*cannot compile$"):
        ground(task)


def test_commands_about_one_model_ground_it_alone_when_the_family_is_refused(tmp_path):
    """``plan`` and ``verify`` need one model of the family, which is plain STRIPS on its own:
    they take the refused family's models one at a time, and agree with the lifted reference
    on every selection.  The engines still refuse the family."""
    human = MOVE_DOMAIN.replace("(and (not (on ?x)) (on ?y) (increase", "(and (increase")
    for name, text in (
        ("robot-domain.pddl", MOVE_DOMAIN),
        ("robot-problem.pddl", MOVE_PROBLEM),
        ("human-domain.pddl", human),
    ):
        (tmp_path / name).write_text(text)
    task = load_task_from_strings(MOVE_DOMAIN, MOVE_PROBLEM, human)
    with pytest.raises(PDDLError, match="cannot compile"):
        ground(task)

    def cli(*args):
        return CliRunner().invoke(main, [*args, "--task", str(tmp_path)])

    r = cli("plan", "--json")
    assert r.exit_code == 0, r.output
    assert json.loads(r.output)["cost"] == _optimum(task.robot) == 3
    for k in range(len(task.delta) + 1):
        for sel in itertools.combinations(range(len(task.delta)), k):
            lines = "".join(task.delta[i].name + "\n" for i in sel)
            (tmp_path / "e.txt").write_text(lines)
            r = cli("plan", "--json", "--model", "human", "--explanation", str(tmp_path / "e.txt"))
            optimum = _optimum(task.updated_model(sel))
            if optimum is None:
                assert r.exit_code == 3 and "has no plan" in r.output
                continue
            assert r.exit_code == 0, r.output
            got = json.loads(r.output)
            assert got["cost"] == optimum and got["exact"]
            # the plan is optimal in human + E: verify passes it, and fails a dearer one
            (tmp_path / "p.plan").write_text("".join(f"{s}\n" for s in got["plan"]))
            in_robot = simulate(
                task.robot, [tuple(x.strip("()").split()) for x in got["plan"]]
            ).valid
            r = cli(
                "verify",
                "--explanation",
                str(tmp_path / "e.txt"),
                "--plan",
                str(tmp_path / "p.plan"),
            )
            assert r.exit_code == (0 if in_robot else 1), r.output
            assert "ok   optimal in human + E" in r.output
    # with the delete alone, (move-light a a) switches a off for 1; (off a) costs 5
    deletes = [u.name for u in task.delta if "delete-effect" in u.name]
    (tmp_path / "e.txt").write_text(deletes[0] + "\n")
    (tmp_path / "p.plan").write_text("(off a)\n")
    r = cli("verify", "--explanation", str(tmp_path / "e.txt"), "--plan", str(tmp_path / "p.plan"))
    assert r.exit_code == 1 and "FAIL optimal in human + E: optimum of human + E" in r.output
    r = cli("frontier")
    assert r.exit_code == 2 and "cannot compile" in r.output


def test_negative_goals_are_written_back_and_read_again(tmp_path):
    task = _task()
    for model in (task.robot, task.human, task.updated_model(task.all_updates)):
        again = parse_model(domain_to_pddl(model), problem_to_pddl(model))
        assert again.neggoal == model.neggoal and again.goal == model.goal
    assert ":negative-preconditions" in domain_to_pddl(replace(task.robot, schemas={}))


@pytest.mark.skipif(not fd_available(), reason="Fast Downward not installed")
def test_fast_downward_agrees_on_the_original_files():
    task = _task()
    for dom, prob, model in (
        (DOMAIN, PROBLEM, task.robot),
        (HUMAN_DOMAIN, HUMAN_PROBLEM, task.human),
    ):
        assert fd_plan(dom, prob).cost == _optimum(model)
    assert _optimum(task.robot) == 10


@pytest.mark.parametrize(
    ("goal", "message"),
    [
        ("(not (= a b))", r"line 5: equality '\(= \.\.\.\)' in the goal is not supported"),
        ("(not (and (on a) (on b)))", r"line 5: .*is not supported"),
        ("(not (on zz))", r"line 5: undefined .*'zz' in :goal"),
    ],
)
def test_what_a_negative_goal_cannot_be_is_one_clear_error(goal, message):
    bad = PROBLEM.replace("(not (on a))", goal)
    with pytest.raises(PDDLError, match=message):
        parse_model(DOMAIN, bad)


# ---------------------------------------------------------------- random tasks


@st.composite
def _tasks_with_negative_goals(draw):
    task = draw(two_model_tasks(max_delta=4))
    robot, human = task.robot, task.human
    atoms = ground_atoms(dict(robot.predicates), sorted(robot.objects))
    for atom in draw(st.lists(st.sampled_from(atoms), min_size=1, max_size=3, unique=True)):
        owners = draw(st.sampled_from(["robot", "human", "both", "both"]))
        if owners != "human":
            robot = replace(robot, neggoal=robot.neggoal | {atom}, goal=robot.goal - {atom})
        if owners != "robot":
            human = replace(human, neggoal=human.neggoal | {atom}, goal=human.goal - {atom})
    return TwoModelTask.from_models(robot, human)


@oracle_settings(80)
@given(_tasks_with_negative_goals())
def test_random_negative_goals_against_the_lifted_reference(task):
    try:
        fam = ground(task)
    except PDDLError as e:  # an add and a delete of a negative-goal atom under two updates
        assert "both adds and deletes" in str(e)
        assume(False)
    c_r, points = lifted_frontier(task)
    if c_r is None:
        with pytest.raises(UnsolvableError):
            sat_frontier(task, fam)
        return
    fr = sat_frontier(task, fam)
    assert fr.robot_optimal_cost == c_r
    assert _pairs(fr.points) == points
    assert [(k, c) for k, c in points] == _pairs(pareto_filter(fr.points))


def test_the_generator_may_leave_a_negative_goal_out_of_the_human_model():
    from mega_sat.bench.generate import _candidate_updates

    robot = _task().robot
    names = {u.name for u in _candidate_updates(robot, frozenset(robot.init))}
    assert {"add-has-negative-goal-state-on a", "add-has-negative-goal-state-on b"} <= names


@pytest.mark.parametrize("seed", range(6))
def test_generated_human_models_hold_no_complement_atoms(seed, tmp_path):
    """Grounding's complement atoms are no atoms of the model: a draw must not add them to the
    human's initial state or goal (they would be written as a predicate named 'not ...')."""
    from mega_sat.bench.generate import generate_human

    robot = _task().robot
    g = generate_human(robot, 3, seed, time_budget=30)
    assert not any(u.feature.atom and u.feature.atom[0].startswith("not ") for u in g.updates)
    human = g.human
    again = parse_model(domain_to_pddl(human), problem_to_pddl(human))
    assert again.goal == human.goal and again.neggoal == human.neggoal
