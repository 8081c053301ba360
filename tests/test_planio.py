"""IPC plan files: tolerant of planner output, strict about unreadable lines."""

from __future__ import annotations

import pytest

from mega_sat.errors import PDDLError, UsageError
from mega_sat.pddl.planio import format_plan, parse_plan, read_plan, write_plan


def test_parse_fast_downward_output():
    text = "(pick-up b)\n(stack b c)\n; cost = 2 (unit cost)\n"
    assert parse_plan(text) == (("pick-up", "b"), ("stack", "b", "c"))


def test_comments_blank_lines_case_and_spacing():
    text = "; a plan\n\n  ( PICK-UP   B )  ; first\n\t(HandEmpty)\n;(ignored x)\n"
    assert parse_plan(text) == (("pick-up", "b"), ("handempty",))


def test_timestamps_and_durations_are_tolerated():
    text = "0: (move r1 a b) [1]\n1.000: (sample r1 b)\n2:(drop r1)[1.5]\n"
    assert parse_plan(text) == (("move", "r1", "a", "b"), ("sample", "r1", "b"), ("drop", "r1"))


def test_empty_plan():
    assert parse_plan("; cost = 0 (unit cost)\n") == ()
    assert parse_plan("") == ()


@pytest.mark.parametrize(
    ("text", "line", "shown"),
    [
        ("(a b)\nmove r1 a b\n", 2, "move r1 a b"),
        ("(a b)\n\n(a b) (c d)\n", 3, "(a b) (c d)"),
        ("()\n", 1, "()"),
        ("(a (b))\n", 1, "(a (b))"),
        ("(a b\n", 1, "(a b"),
    ],
)
def test_malformed_lines_name_path_and_line(text, line, shown):
    with pytest.raises(PDDLError) as info:
        parse_plan(text, path="my.plan")
    assert str(info.value) == (
        f"my.plan: line {line}: expected one '(action arg ...)' per line, got '{shown}'"
    )


def test_format_plan():
    plan = (("pick-up", "b"), ("stack", "b", "c"))
    assert format_plan(plan) == "(pick-up b)\n(stack b c)\n"
    assert format_plan(plan, 2) == "(pick-up b)\n(stack b c)\n; cost = 2 (general cost)\n"
    assert format_plan((), 0) == "; cost = 0 (general cost)\n"
    assert parse_plan(format_plan(plan, 7)) == plan


def test_write_and_read_plan(tmp_path):
    path = tmp_path / "plan.txt"
    plan = (("move", "r1", "a", "b"),)
    assert write_plan(path, plan, 3) == path
    assert read_plan(path) == plan
    with pytest.raises(UsageError) as info:
        write_plan(path, (), 0)
    assert str(info.value).startswith(f"{path}: file exists")
    assert read_plan(path) == plan
    write_plan(path, (), 0, overwrite=True)
    assert read_plan(path) == ()


def test_read_missing_plan(tmp_path):
    missing = tmp_path / "none.plan"
    with pytest.raises(PDDLError) as info:
        read_plan(missing)
    assert str(info.value) == f"{missing}: plan file not found"
