"""Loading two-model tasks from files, strings and ``--task`` directories."""

from __future__ import annotations

import shutil
from pathlib import Path

import pytest

from mega_sat.errors import ModelMismatchError, PDDLError, UsageError
from mega_sat.pddl.loading import load_task, load_task_from_strings, resolve_task_dir

DATA = Path(__file__).parent / "data" / "frontend"
TYPES = DATA / "pair-types"
ARITY = DATA / "pair-arity"


def test_task_dir_with_domains_in_parent():
    paths = resolve_task_dir(TYPES / "p1")
    assert paths == {
        "robot_domain": TYPES / "robot-domain.pddl",
        "robot_problem": TYPES / "p1" / "robot-problem.pddl",
        "human_domain": TYPES / "human-domain.pddl",
        "human_problem": TYPES / "p1" / "robot-problem.pddl",  # defaults to the robot's
    }


def test_different_type_hierarchies_become_explainable_differences():
    task = load_task(**resolve_task_dir(TYPES / "p1"))
    names = {u.name for u in task.delta}
    # the robot thinks a drone is a vehicle, the human does not
    assert names == {"add-has-initial-state-vehicle d1"}
    # the human's parameter names are aligned to the robot's by position
    assert task.human.schemas["deliver"].params == ("?v", "?o", "?p")
    assert task.sources["human_domain"] == str(TYPES / "human-domain.pddl")
    assert task.sources["human_problem"] == str(TYPES / "p1" / "robot-problem.pddl")


def test_human_problem_defaults_to_robot_problem():
    task = load_task(TYPES / "robot-domain.pddl", TYPES / "p1" / "robot-problem.pddl",
                     TYPES / "human-domain.pddl")  # fmt: skip
    assert task.human.goal == task.robot.goal
    assert task.sources["human_problem"] == task.sources["robot_problem"]


def test_mismatched_arity_names_both_files():
    paths = resolve_task_dir(ARITY)
    assert paths["human_problem"] == ARITY / "human-problem.pddl"
    with pytest.raises(ModelMismatchError) as info:
        load_task(**paths)
    msg = str(info.value)
    assert msg.startswith(f"{ARITY / 'human-domain.pddl'}: line 3: ")  # where it is declared
    assert "predicate 'at' has 2 argument(s)" in msg and "but 1" in msg
    assert str(ARITY / "robot-domain.pddl") in msg and str(ARITY / "human-domain.pddl") in msg


def test_pddl_error_names_the_human_file():
    # the robot problem does not fit the human domain's arity for 'at'
    with pytest.raises(PDDLError) as info:
        load_task(ARITY / "robot-domain.pddl", ARITY / "robot-problem.pddl",
                  ARITY / "human-domain.pddl")  # fmt: skip
    assert str(info.value).startswith(f"{ARITY / 'robot-problem.pddl'}: line 4: ")
    assert "predicate 'at' takes 1 argument(s), got 2 in :init" in str(info.value)


def test_missing_file_in_load_task(tmp_path):
    with pytest.raises(PDDLError, match="human domain file not found"):
        load_task(TYPES / "robot-domain.pddl", TYPES / "p1" / "robot-problem.pddl",
                  tmp_path / "human-domain.pddl")  # fmt: skip


def test_load_task_from_strings():
    rd = (TYPES / "robot-domain.pddl").read_text()
    hd = (TYPES / "human-domain.pddl").read_text()
    rp = (TYPES / "p1" / "robot-problem.pddl").read_text()
    task = load_task_from_strings(rd, rp, hd)
    assert [u.name for u in task.delta] == ["add-has-initial-state-vehicle d1"]
    with pytest.raises(PDDLError) as info:
        load_task_from_strings(rd, rp, hd.replace("(:types", "(:typez"))
    assert str(info.value).startswith("human domain: line 4: unknown domain section")


def test_load_task_from_strings_mismatch_names_models():
    texts = [(ARITY / f).read_text() for f in ("robot-domain.pddl", "robot-problem.pddl",
                                                "human-domain.pddl", "human-problem.pddl")]  # fmt: skip
    with pytest.raises(ModelMismatchError) as info:
        load_task_from_strings(*texts)
    assert "in robot domain but 1 in human domain" in str(info.value)
    assert str(info.value).startswith("human domain: line 3: ")


def test_mismatches_name_the_line_of_their_cause():
    dom = """(define (domain d) (:requirements :strips :action-costs)
      (:predicates (at ?x)) (:functions (len ?x) - number (total-cost) - number)
      (:action go :parameters (?x ?y) :precondition (at ?x)
        :effect (and (at ?y) (not (at ?x)) (increase (total-cost) (len ?y)))))"""
    prob = """(define (problem p) (:domain d) (:objects a b)
      (:init (at a)
             (= (len a) 1) (= (len b) 2))
      (:goal (at b)))"""
    short = prob.replace(" (= (len b) 2)", "")
    with pytest.raises(ModelMismatchError) as info:
        load_task_from_strings(dom, prob, dom, short)
    assert str(info.value).startswith("robot problem: line 3: cost function value (len b)")
    with pytest.raises(ModelMismatchError) as info:
        load_task_from_strings(dom, short, dom, prob)
    assert str(info.value).startswith("human problem: line 3: cost function value (len b)")
    three = dom.replace("(?x ?y) :precondition", "(?x ?y ?z) :precondition")
    with pytest.raises(ModelMismatchError) as info:
        load_task_from_strings(dom, prob, three, prob)
    assert str(info.value).startswith("human domain: line 3: action 'go' has 2 parameter(s)")


def _copy(src: Path, dst: Path) -> None:
    dst.parent.mkdir(parents=True, exist_ok=True)
    shutil.copy(src, dst)


def test_task_dir_prefers_its_own_domains_and_human_problem(tmp_path):
    task_dir = tmp_path / "p1"
    _copy(TYPES / "robot-domain.pddl", tmp_path / "robot-domain.pddl")
    _copy(TYPES / "human-domain.pddl", tmp_path / "human-domain.pddl")
    _copy(TYPES / "robot-domain.pddl", task_dir / "human-domain.pddl")  # overrides the parent's
    _copy(TYPES / "p1" / "robot-problem.pddl", task_dir / "robot-problem.pddl")
    _copy(TYPES / "p1" / "robot-problem.pddl", task_dir / "human-problem.pddl")
    paths = resolve_task_dir(task_dir)
    assert paths["robot_domain"] == tmp_path / "robot-domain.pddl"
    assert paths["human_domain"] == task_dir / "human-domain.pddl"
    assert paths["human_problem"] == task_dir / "human-problem.pddl"
    assert load_task(**paths).delta == ()


def test_task_dir_errors(tmp_path):
    with pytest.raises(UsageError) as info:
        resolve_task_dir(tmp_path / "absent")
    assert str(info.value) == f"{tmp_path / 'absent'}: task directory not found"
    (tmp_path / "a-file").write_text("x")
    with pytest.raises(UsageError) as info:
        resolve_task_dir(tmp_path / "a-file")
    assert str(info.value) == (
        f"{tmp_path / 'a-file'}: is not a folder (--task takes a task folder)"
    )

    task_dir = tmp_path / "p1"
    task_dir.mkdir()
    with pytest.raises(UsageError) as info:
        resolve_task_dir(task_dir)
    assert str(info.value) == f"{task_dir}: no robot-problem.pddl in the task directory"

    _copy(TYPES / "p1" / "robot-problem.pddl", task_dir / "robot-problem.pddl")
    _copy(TYPES / "robot-domain.pddl", tmp_path / "robot-domain.pddl")
    with pytest.raises(UsageError) as info:
        resolve_task_dir(task_dir)
    msg = str(info.value)
    assert "no human-domain.pddl in the task directory or its parent" in msg
    assert str(task_dir / "human-domain.pddl") in msg
    assert str(tmp_path / "human-domain.pddl") in msg


@pytest.mark.parametrize("human_has", ["function", "predicate"])
def test_a_name_that_is_a_predicate_in_one_model_and_a_function_in_the_other(tmp_path, human_has):
    """PDDL has one name space for predicates and functions: `apply` would write a model that
    declares ``dist`` twice (VAL crashes on it), so the pair is refused at load, with the
    line of the human domain's declaration."""
    as_predicate = """(define (domain d) (:requirements :strips :action-costs)
  (:predicates (at ?x) (road ?x ?y) (dist ?x ?y))
  (:functions (total-cost) - number)
  (:action go :parameters (?x ?y) :precondition (and (at ?x) (road ?x ?y))
    :effect (and (at ?y) (not (at ?x)) (increase (total-cost) 1))))"""
    as_function = """(define (domain d) (:requirements :strips :action-costs)
  (:predicates (at ?x) (road ?x ?y))
  (:functions (total-cost) - number
              (dist ?x ?y) - number)
  (:action go :parameters (?x ?y) :precondition (and (at ?x) (road ?x ?y))
    :effect (and (at ?y) (not (at ?x)) (increase (total-cost) (dist ?x ?y)))))"""
    values = "(= (dist a b) 2) (= (dist b c) 3)"
    robot, human = (as_predicate, as_function)
    if human_has == "predicate":
        robot, human = human, robot
    for name, text in (("robot-domain", robot), ("human-domain", human)):
        (tmp_path / f"{name}.pddl").write_text(text)
        init = values if text is as_function else "(dist a b)"
        (tmp_path / f"{name.replace('domain', 'problem')}.pddl").write_text(
            f"(define (problem p) (:domain d) (:objects a b c)\n"
            f"  (:init (at a) (road a b) (road b c) {init})\n"
            "  (:goal (at c)) (:metric minimize (total-cost)))"
        )
    with pytest.raises(ModelMismatchError) as info:
        load_task(**resolve_task_dir(tmp_path))
    line = 2 if human_has == "predicate" else 4
    other = "function" if human_has == "predicate" else "predicate"
    assert str(info.value) == (
        f"{tmp_path / 'human-domain.pddl'}: line {line}: 'dist' is a {human_has} in "
        f"{tmp_path / 'human-domain.pddl'} but a {other} in {tmp_path / 'robot-domain.pddl'} "
        "(a name stands for one kind of symbol in both models; rename one of them)"
    )
