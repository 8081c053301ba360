"""Input a user writes by hand: byte-order marks, mismatched domain names, wrong argument types
at the library boundary, plans in any of the forms a user writes them."""

from __future__ import annotations

import subprocess
import sys
import warnings
from pathlib import Path

import pytest

from mega_sat.errors import MegaSatError, UsageError
from mega_sat.pddl.loading import load_task, load_task_from_strings
from mega_sat.pddl.planio import as_plan
from mega_sat.pddl.reader import PDDLWarning

ROOT = Path(__file__).resolve().parent.parent
USAR = ROOT / "domains" / "usar-fetch"
FILES = (
    USAR / "robot-domain.pddl",
    USAR / "p1" / "robot-problem.pddl",
    USAR / "human-domain.pddl",
    USAR / "p1" / "human-problem.pddl",
)


def _usar():
    return load_task(*FILES)


def test_a_utf8_byte_order_mark_is_accepted(tmp_path):
    bom = tmp_path / "robot-domain.pddl"
    bom.write_bytes(b"\xef\xbb\xbf" + FILES[0].read_bytes())
    task = load_task(bom, *FILES[1:])
    assert [u.name for u in task.delta] == [u.name for u in _usar().delta]
    texts = [p.read_text() for p in FILES]
    texts[1] = "\ufeff" + texts[1]
    assert len(load_task_from_strings(*texts).delta) == 3


def test_explanation_lines_with_a_byte_order_mark_and_invisible_characters():
    task = _usar()
    first = task.delta[0].name
    assert task.selection_from_names(["\ufeff" + first]) == frozenset({0})
    with pytest.raises(UsageError) as info:
        task.selection_from_names([first + "\u200b"])
    assert "\\u200b" in str(info.value)  # shown, not invisible


def test_a_problem_naming_another_domain_is_read_with_a_warning(tmp_path):
    problem = tmp_path / "human-problem.pddl"
    problem.write_text(FILES[3].read_text().replace("(:domain usar-fetch)", "(:domain other)"))
    with warnings.catch_warnings(record=True) as caught:
        warnings.simplefilter("always")
        task = load_task(*FILES[:3], problem)
    assert len(task.delta) == 3
    msgs = [str(w.message) for w in caught if issubclass(w.category, PDDLWarning)]
    assert len(msgs) == 1
    assert msgs[0].startswith(f"{problem}: line ")
    assert "names domain 'other' but the domain file defines 'usar-fetch'" in msgs[0]


def test_the_cli_prints_the_warning_as_one_line(tmp_path):
    problem = tmp_path / "human-problem.pddl"
    problem.write_text(FILES[3].read_text().replace("(:domain usar-fetch)", "(:domain other)"))
    r = subprocess.run(
        [sys.executable, "-m", "mega_sat.cli.commands", "diff"]
        + ["--robot-domain", str(FILES[0]), "--robot-problem", str(FILES[1])]
        + ["--human-domain", str(FILES[2]), "--human-problem", str(problem)],
        capture_output=True,
        text=True,
        cwd=ROOT,
    )
    assert r.returncode == 0, r.stderr
    assert r.stderr.startswith("warning: ") and r.stderr.count("\n") == 1
    assert len(r.stdout.splitlines()) == 3


def test_load_task_given_pddl_text_says_so():
    with pytest.raises(UsageError, match="looks like PDDL text, not a file path"):
        load_task(FILES[0].read_text(), *FILES[1:])


@pytest.mark.parametrize("bad", [None, 5, b"(define)"])
def test_load_task_from_strings_refuses_non_text(bad):
    texts = [p.read_text() for p in FILES]
    with pytest.raises(UsageError, match="robot_domain must be PDDL text"):
        load_task_from_strings(bad, *texts[1:])


@pytest.mark.parametrize("bad", [{99}, {-1}, {3}, {"0"}, {True}, "0"])
def test_selections_outside_delta_are_refused(bad):
    task = _usar()
    with pytest.raises(UsageError):
        task.names(bad)
    with pytest.raises(UsageError):
        task.updated_model(bad)


def test_plans_in_any_form_and_case():
    want = (("move", "p1", "p6"), ("take_picture", "p6"))
    assert as_plan([("MOVE", "P1", "P6"), ["take_picture", "p6"]]) == want
    assert as_plan("(move p1 p6)\n(TAKE_PICTURE p6)\n; cost = 2") == want
    assert as_plan(["move p1 p6", "(take_picture p6)"]) == want
    assert as_plan(()) == ()


@pytest.mark.parametrize("bad", [5, [5], [()], ["(a"], [("a b",)], [("a", 3)], b"(a)"])
def test_malformed_plans_are_one_clear_error(bad):
    with pytest.raises(MegaSatError) as info:
        as_plan(bad)
    assert str(info.value).startswith("plan")
    assert "\n" not in str(info.value)


def test_a_task_folder_loads_in_one_call_and_a_starred_dict_is_explained():
    from mega_sat.pddl.loading import load_task_dir, resolve_task_dir

    paths = resolve_task_dir(USAR / "p1")
    assert load_task_dir(USAR / "p1").delta == load_task(**paths).delta
    with pytest.raises(UsageError, match=r"load_task\(\*\*paths\)"):
        load_task(*paths)


@pytest.mark.parametrize(
    "args",
    [
        ["diff"],
        ["apply", "--explanation", "{e}", "--out", "{tmp}/apply"],
        ["plan"],
        ["validate", "--plan", "{p}"],
        ["encode", "--out", "{tmp}/enc"],
        ["solve", "--alpha", "1"],
        ["frontier"],
        ["explain"],
        ["verify", "--explanation", "{e}", "--plan", "{p}"],
    ],
)
def test_every_command_reports_the_grounding_sizes_with_v(args, tmp_path):
    from click.testing import CliRunner

    from mega_sat.cli.commands import main

    e, p = tmp_path / "e.txt", tmp_path / "p.ipc"
    e.write_text("add-has-initial-state-clear_path p6 p7\n")
    p.write_text("(move p1 p2)\n")
    args = [a.format(e=e, p=p, tmp=tmp_path) for a in args]
    r = CliRunner().invoke(main, [*args, "--task", str(USAR / "p1"), "-v"])
    assert r.exception is None or isinstance(r.exception, SystemExit)
    sizes = [line for line in r.stderr.splitlines() if line.startswith("; |Delta| = 3; grounded")]
    assert len(sizes) == 1, r.stderr
    assert "39 atoms, 23 ground actions, 3 updates in " in sizes[0]


def test_explanation_lines_in_any_case_and_spacing():
    """Update names are lower case with single spaces; a hand-typed line with capitals, tabs or
    doubled spaces names the same update, in one human model or several."""
    from mega_sat.pddl.multi_task import MultiHumanTask

    task = _usar()
    name = task.delta[0].name
    typed = "  " + name.upper().replace(" ", " \t ") + "  "
    assert task.selection_from_names([typed, "Explanation >>  " + name]) == frozenset({0})
    multi = MultiHumanTask.from_tasks([task, task])
    assert multi.selection_from_names([typed]) == frozenset({multi.update_index[name]})


def test_a_plan_file_with_a_byte_order_mark(tmp_path):
    from mega_sat.pddl.planio import read_plan

    plan = tmp_path / "bom.plan"
    plan.write_bytes(b"\xef\xbb\xbf(MOVE p1 p2)\r\n(take_picture p2)\r\n")
    assert read_plan(plan) == (("move", "p1", "p2"), ("take_picture", "p2"))


def test_the_robot_problem_read_as_the_human_problem_says_so(tmp_path):
    """Without a human problem the robot's is read with the human domain; an error there names
    the robot problem's file, which was just read without fault for the robot."""
    human = tmp_path / "human-domain.pddl"
    human.write_text(FILES[2].read_text().replace("clearable", "debris"))
    with pytest.raises(MegaSatError) as info:
        load_task(FILES[0], FILES[1], human)
    msg = str(info.value)
    assert msg.startswith(f"{FILES[1]}: line ") and "undefined predicate 'clearable'" in msg
    assert msg.endswith(f"(read as the human problem, with {human}: give the human's own "
                        "problem if it differs)")  # fmt: skip
    with pytest.raises(MegaSatError) as info:
        load_task(FILES[0], FILES[1], human, FILES[1])  # given twice: the same reading
    assert "read as the human problem" in str(info.value)


def test_verify_says_a_plan_that_does_not_run_in_human_e_is_not_executable():
    from mega_sat.api import MegaSolver

    robot = """(define (domain d) (:predicates (p ?x) (q ?x) (r ?x))
      (:action a :parameters (?x) :precondition (p ?x) :effect (q ?x)))"""
    human = """(define (domain d) (:predicates (p ?x) (q ?x) (r ?x))
      (:action a :parameters (?x) :precondition (and (p ?x) (r ?x)) :effect (q ?x))
      (:action b :parameters (?x) :precondition (p ?x) :effect (q ?x)))"""
    prob = "(define (problem p1) (:domain d) (:objects o) (:init (p o)) (:goal (q o)))"
    solver = MegaSolver(load_task_from_strings(robot, prob, human, prob))
    report = solver.verify(explanation=[], plan=[("a", "o")], use_val=False)
    optimal = [c for c in report.checks if c.name == "optimal in human + E"]
    assert not report.ok and optimal[0].detail.endswith("; plan: not executable")


def test_parameters_listed_in_another_order_give_a_warning():
    robot = """(define (domain dl) (:requirements :strips :typing) (:types pkg place)
      (:predicates (at ?p - pkg ?l - place) (holding ?p - pkg))
      (:action drop :parameters (?p - pkg ?l - place) :precondition (holding ?p)
        :effect (and (at ?p ?l) (not (holding ?p)))))"""
    human = robot.replace("(?p - pkg ?l - place)", "(?l - place ?p - pkg)")
    prob = """(define (problem p) (:domain dl) (:objects b - pkg r - place)
      (:init (holding b)) (:goal (at b r)))"""
    with warnings.catch_warnings(record=True) as caught:
        warnings.simplefilter("always")
        task = load_task_from_strings(robot, prob, human)
        load_task_from_strings(robot, prob, robot)  # the same order: no warning
    msgs = [str(w.message) for w in caught if issubclass(w.category, PDDLWarning)]
    assert msgs == [
        "human domain: action 'drop' has parameters of the types (place pkg) where robot "
        "domain has (pkg place): parameters are matched by position, so their types and the "
        "atoms that use them differ"
    ]
    assert len(task.delta) == 10  # 2 x (types of 2, holding, the add and the delete)
