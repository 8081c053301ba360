"""The live progress line on stderr: what it says, and when it is shown (a terminal, or
MEGA_SAT_PROGRESS=always; never with --quiet or into a pipe)."""

from __future__ import annotations

import fcntl
import os
import pty
import re
import struct
import subprocess
import sys
import termios
from pathlib import Path

import pytest
from click.testing import CliRunner

from mega_sat import api
from mega_sat.cli.commands import main
from mega_sat.deadline import Deadline
from mega_sat.engines import progress
from mega_sat.engines.progress import PROGRESS_ENV, LiveProgress, Progress, progress_wanted

ROOT = Path(__file__).resolve().parent.parent
USAR = ROOT / "domains" / "usar-fetch" / "p1"
BLOCKS = ROOT / "domains" / "blocksworld" / "p2"
ROVER = ROOT / "domains" / "rover-martian" / "p2"


def test_the_line_follows_the_run():
    live = LiveProgress("frontier", Deadline.after(60))
    assert re.fullmatch(r"frontier: reading and grounding the models, \d+\.\ds of 60s", live.text())
    s = api.MegaSolver(api.load_task_dir(BLOCKS))
    live.watch(s.progress)
    s.frontier()
    it = s.progress.iteration
    assert it >= 3 and s.progress.size == 2
    assert re.fullmatch(
        rf"frontier: iteration {it}, searching \|E\| = 2, 3 points found, \d+\.\ds of 60s",
        live.text(),
    )
    s.explain()
    assert s.progress.engine == "mce"
    assert re.fullmatch(
        r"frontier: iteration \d+, searching \|E\| = 2, \d+\.\ds of 60s", live.text()
    )
    fresh = Progress()
    fresh.start("sat", ("u",))
    live.watch(fresh)
    live.deadline = Deadline()
    assert re.fullmatch(r"frontier: computing the robot optimum, \d+\.\ds", live.text())


def test_wanted_on_a_terminal_only_and_never_with_quiet(monkeypatch):
    monkeypatch.delenv(PROGRESS_ENV, raising=False)

    class Tty:
        def isatty(self) -> bool:
            return True

    assert progress_wanted(stream=Tty())
    assert not progress_wanted(quiet=True, stream=Tty())
    assert not progress_wanted(stream=open(os.devnull, "w"))  # noqa: SIM115
    monkeypatch.setenv(PROGRESS_ENV, "never")
    assert not progress_wanted(stream=Tty())
    monkeypatch.setenv(PROGRESS_ENV, "always")
    assert progress_wanted(stream=open(os.devnull, "w"))  # noqa: SIM115
    assert not progress_wanted(quiet=True)


@pytest.fixture
def fast_display(monkeypatch):
    monkeypatch.setattr(progress, "SHOW_AFTER", 0.0)
    monkeypatch.setattr(progress, "REFRESH", 0.005)


@pytest.mark.parametrize(
    "args",
    [
        ["frontier", "--task", BLOCKS],
        ["solve", "--task", BLOCKS, "--alpha", "0.3", "--timeout", "60"],
        ["explain", "--task", BLOCKS],
    ],
)
def test_forced_progress_goes_to_stderr_and_is_cleared(monkeypatch, fast_display, args):
    monkeypatch.setenv(PROGRESS_ENV, "always")
    quiet = CliRunner().invoke(main, [str(a) for a in args])
    res = CliRunner().invoke(main, [str(a) for a in args])
    assert res.exit_code == 0, res.output
    assert res.stdout == quiet.stdout.replace(  # same answer (timings aside)
        re.search(r"time \S+s", quiet.stdout).group(0), re.search(r"time \S+s", res.stdout).group(0)
    )
    assert f"\r{args[0]}: " in res.stderr
    assert res.stderr.endswith("\r")  # the line is cleared before the answer
    if "--timeout" in args:
        assert " of 60s" in res.stderr


@pytest.mark.parametrize("command", ["frontier", "explain"])
def test_quiet_and_pipes_get_no_progress(monkeypatch, fast_display, command):
    monkeypatch.delenv(PROGRESS_ENV, raising=False)
    res = CliRunner().invoke(main, [command, "--task", USAR])
    assert res.exit_code == 0 and res.stderr == ""  # CliRunner's stderr is not a terminal
    monkeypatch.setenv(PROGRESS_ENV, "always")
    res = CliRunner().invoke(main, [command, "--task", USAR, "--quiet"])
    assert res.exit_code == 0 and res.stderr == ""


def test_bench_quiet_flag(monkeypatch, tmp_path):
    monkeypatch.setenv(PROGRESS_ENV, "always")
    res = CliRunner().invoke(
        main,
        ["bench", "--suite", "smoke", "--only", "usar-fetch/p1", "--baseline-planner", "builtin"]
        + ["--time-limit", "60", "--out", str(tmp_path / "r"), "--quiet"],
    )
    assert res.exit_code == 0, res.output
    assert res.stderr == ""


def _on_a_terminal(args: list[str]) -> tuple[str, str]:
    """Run the CLI with stderr on a pseudo-terminal (stdout a pipe): (stdout, stderr)."""
    parent, child = pty.openpty()
    fcntl.ioctl(child, termios.TIOCSWINSZ, struct.pack("HHHH", 24, 120, 0, 0))  # 120 columns
    env = {k: v for k, v in os.environ.items() if k != PROGRESS_ENV}
    proc = subprocess.Popen(
        [sys.executable, "-m", "mega_sat.cli.commands", *args],
        cwd=ROOT,
        stdout=subprocess.PIPE,
        stderr=child,
        env=env,
        text=True,
    )
    os.close(child)
    chunks = []
    while True:
        try:
            data = os.read(parent, 4096)
        except OSError:  # the terminal closed with the process
            break
        if not data:
            break
        chunks.append(data)
    out = proc.stdout.read()
    proc.wait(timeout=120)
    os.close(parent)
    return out, b"".join(chunks).decode("utf-8", "replace")


@pytest.mark.slow
def test_a_real_terminal_shows_progress_after_a_second_unless_quiet():
    out, err = _on_a_terminal(["frontier", "--task", str(ROVER), "--timeout", "120"])
    assert "exact: yes" in out
    assert "\rfrontier: " in err and "points found" in err and " of 120s" in err
    out, err = _on_a_terminal(["frontier", "--task", str(ROVER), "--quiet"])
    assert "exact: yes" in out and err == ""


def test_astar_counts_only_pareto_optimal_points():
    s = api.MegaSolver(api.load_task_dir(BLOCKS), engine="astar")
    live = LiveProgress("frontier", Deadline())
    live.watch(s.progress)
    fr = s.frontier()
    assert len(s.progress.points) > len(fr.points)  # every evaluated node the robot can run
    assert f", {len(fr.points)} points found, " in live.text()
