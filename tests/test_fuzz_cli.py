"""Fuzzing the command line and the library API with misuse: every case ends in an answer or in
one ``error:`` line with a documented exit code (docs/cli.md), never a traceback or a hang.

Budget as in ``tests/fuzzing.py`` (small and seeded; ``--fuzz-long`` for release checks).
"""

from __future__ import annotations

import shlex
from pathlib import Path

import pytest
from click.testing import CliRunner
from helpers.fuzzing import FUZZ
from hypothesis import given
from hypothesis import strategies as st

from mega_sat import errors
from mega_sat.cli.commands import main

ROOT = Path(__file__).resolve().parent.parent
EXIT_CODES = set(errors.EXIT_CODES)
"""docs/cli.md's table (a test in test_runlimits.py keeps the two equal)."""

COMMANDS = ["diff", "apply", "plan", "validate", "encode", "solve", "frontier", "explain", "verify"]
TASKS = ["domains/usar-fetch/p1", "docs/examples/courier/p1", "domains/nowhere", "README.md", ""]
NUMBERS = ["0", "-1", "1", "0.1", "nan", "inf", "-inf", "1e308", "1e400", "abc", "", "0x10", "2"]


@pytest.fixture(scope="module")
def files(tmp_path_factory) -> dict[str, str]:
    d = tmp_path_factory.mktemp("fuzz-cli")
    (d / "binary.bin").write_bytes(bytes(range(255, -1, -1)))  # not UTF-8 from byte 1
    (d / "bom.txt").write_bytes(b"\xef\xbb\xbfadd-has-initial-state-clear_path p6 p7\n")
    (d / "plan.ipc").write_text("(move p1 p6)\n(move p6 p7)\n(move p7 p5)\n(take_picture p5)\n")
    (d / "garbage.txt").write_text("((( not a plan\n")
    (d / "empty.txt").write_text("")
    (d / "folder").mkdir()
    return {
        "binary": str(d / "binary.bin"),
        "bom": str(d / "bom.txt"),
        "plan": str(d / "plan.ipc"),
        "garbage": str(d / "garbage.txt"),
        "empty": str(d / "empty.txt"),
        "folder": str(d / "folder"),
        "missing": str(d / "missing.txt"),
        "out": str(d / "out"),
    }


@st.composite
def command_lines(draw, files: dict[str, str]) -> list[str]:
    cmd = draw(st.sampled_from(COMMANDS + ["bogus", "--bogus", ""]))
    args = [cmd] if cmd else []
    pool = list(files.values())
    options = [
        ("--task", st.sampled_from(TASKS)),
        ("--alpha", st.sampled_from(NUMBERS)),
        ("--timeout", st.sampled_from(NUMBERS)),
        ("--explanation", st.sampled_from(pool)),
        ("--plan", st.sampled_from(pool)),
        ("--engine", st.sampled_from(["sat", "astar", "bogus", ""])),
        ("--planner", st.sampled_from(["builtin", "sat", "bogus"])),
        ("--hitting-set", st.sampled_from(["rc2", "ilp", "x"])),
        ("--robot-domain", st.sampled_from(pool + ["domains/usar-fetch/robot-domain.pddl"])),
        ("--out", st.sampled_from([files["out"], files["folder"], files["binary"]])),
        ("--json", st.none()),
        ("--force", st.none()),
        ("--model", st.sampled_from(["robot", "human", "martian"])),
        ("--kind", st.sampled_from(["opt", "joint", "both"])),
        ("--robot-bound", st.sampled_from(NUMBERS)),
        ("--nonsense", st.none()),
    ]
    for name, values in draw(st.lists(st.sampled_from(options), max_size=5, unique=True)):
        args.append(name)
        value = draw(values)
        if value is not None:
            args.append(value)
    if cmd in ("solve", "frontier", "explain") and "--timeout" not in args:
        args += ["--timeout", "5"]  # misuse must not turn into a long run
    return args


def _runner() -> CliRunner:
    """A runner that keeps stderr apart (click < 8.2 needs ``mix_stderr=False``)."""
    try:
        return CliRunner(mix_stderr=False)  # type: ignore[call-arg]
    except TypeError:
        return CliRunner()


def _check(args: list[str], result) -> None:
    shown = "mega-sat " + shlex.join(args)
    assert result.exception is None or isinstance(result.exception, SystemExit), (
        f"{shown}: {type(result.exception).__name__}: {result.exception}"
    )
    assert result.exit_code in EXIT_CODES, f"{shown}: exit {result.exit_code}"
    err = [line for line in result.stderr.splitlines() if not line.startswith(("warning:", ";"))]
    assert "Traceback" not in result.stderr, shown
    if result.exit_code not in (0, 1):
        assert len(err) == 1 and err[0].startswith("error: "), f"{shown}: {result.stderr!r}"


@FUZZ
@given(data=st.data())
def test_random_command_lines(data, files):
    args = data.draw(command_lines(files))
    result = _runner().invoke(main, args, catch_exceptions=True)
    if args and args[0] not in ("", "bogus", "--bogus") and args != [args[0]]:
        _check(args, result)
    else:
        assert result.exit_code in EXIT_CODES, args


@pytest.mark.parametrize(
    "args",
    [
        ["bogus"],
        ["solve", "--task", "domains/usar-fetch/p1", "--alpha", "0.1", "--timeout", "abc"],
        ["diff", "--task", "domains/usar-fetch/p1", "--nonsense"],
        ["plan", "--task", "domains/usar-fetch/p1", "--model", "martian"],
        ["validate", "--task", "domains/usar-fetch/p1", "--plan", "README.md/x"],
    ],
)
def test_usage_errors_are_one_line(args):
    result = _runner().invoke(main, args)
    assert result.exit_code == 2
    lines = result.stderr.splitlines()
    assert len(lines) == 1 and lines[0].startswith("error: "), result.stderr


VALUES = [None, 0, -1, 0.1, float("nan"), float("inf"), "5", "abc", "", b"x", [], {}, object(),
          ("MOVE", "P1", "P6"), [("move", "p1", "p6")], "(move p1 p6)", {99}, frozenset({-1})]  # fmt: skip


@pytest.fixture(scope="module")
def usar():
    from mega_sat.pddl.loading import load_task_dir

    return load_task_dir(ROOT / "domains/usar-fetch/p1")


@FUZZ
@given(data=st.data())
def test_random_api_misuse(data, usar):
    """Random argument values for the public API: an answer or a MegaSatError, nothing else."""
    from mega_sat import api
    from mega_sat.errors import MegaSatError

    value = data.draw(st.sampled_from(VALUES))
    task = data.draw(st.sampled_from([usar, None, "domains/usar-fetch/p1"]))
    calls = {
        "solver": lambda: api.MegaSolver(task, timeout=5),
        "engine": lambda: api.MegaSolver(task, engine=value),
        "planner": lambda: api.MegaSolver(task, planner=value),
        "solver_name": lambda: api.MegaSolver(task, solver=value),
        "hitting_set": lambda: api.MegaSolver(task, hitting_set=value),
        "timeout": lambda: api.MegaSolver(task, timeout=value),
        "alpha": lambda: api.solve(task, value, timeout=5),
        "explain": lambda: api.explain(task, value, timeout=5),
        "verify": lambda: api.verify(task, value),
        "verify_plan": lambda: api.verify(task, explanation=value, plan=[("move", "p1", "p6")]),
        "names": lambda: usar.names(value),
        "load": lambda: api.load_task(value, value, value),
        "strings": lambda: api.load_task_from_strings(value, value, value),
    }
    name = data.draw(st.sampled_from(sorted(calls)))
    try:
        calls[name]()
    except MegaSatError as e:
        text = str(e)
        assert text and not text.startswith("error") and "\n" not in text, (name, value, text)


@pytest.mark.parametrize("command", ["verify", "apply", "plan", "validate", "encode"])
@pytest.mark.parametrize(("kind", "message"), [("binary", "is not UTF-8 text"),
                                               ("folder", "is a directory"),
                                               ("missing", "not found")])  # fmt: skip
def test_explanation_files_that_are_not_text(command, kind, message, files):
    extra = {
        "verify": ["--plan", files["plan"]],
        "apply": ["--out", files["out"] + "-apply"],
        "plan": ["--model", "human"],
        "validate": ["--plan", files["plan"], "--model", "human"],
        "encode": ["--out", files["out"] + "-encode"],
    }[command]
    args = [command, "--task", "domains/usar-fetch/p1", "--explanation", files[kind], *extra]
    result = _runner().invoke(main, args)
    assert result.exit_code == 2, result.stderr
    assert result.stderr == f"error: {files[kind]}: explanation file {message}\n"
