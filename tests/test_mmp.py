"""``mega-sat mmp``, the drop-in for the original MEGA code's command line: the same flags, the
same outputs (``Explanation >>`` lines, ``exp.dat``, ``final_plan.sol``), and the answers of
mega-sat's own commands."""

from __future__ import annotations

import json
import subprocess
import sys
from pathlib import Path

import pytest

ROOT = Path(__file__).resolve().parents[1]
USAR = ROOT / "domains" / "usar-fetch"
CLI = [sys.executable, "-c", "import sys; from mega_sat.cli.commands import main; sys.exit(main())"]
MODELS = [
    "-m",
    str(USAR / "robot-domain.pddl"),
    "-n",
    str(USAR / "human-domain.pddl"),
    "-p",
    str(USAR / "p1" / "robot-problem.pddl"),
    "-q",
    str(USAR / "p1" / "human-problem.pddl"),
]


def _run(cwd: Path, *args: str) -> subprocess.CompletedProcess:
    return subprocess.run([*CLI, *args], cwd=cwd, capture_output=True, text=True, timeout=300)


def _mega(*args: str) -> dict:
    r = _run(ROOT, *args, "--task", str(USAR / "p1"), "--json")
    assert r.returncode == 0, r.stderr
    return json.loads(r.stdout)


def _plan_lines(path: Path) -> list[str]:
    return [x for x in path.read_text().splitlines() if x and not x.startswith(";")]


@pytest.mark.parametrize("alpha", ["0.1", "10"])
def test_ee_is_mega_at_alpha(tmp_path, alpha):
    r = _run(tmp_path, "mmp", "-s", "EE", "-a", alpha, *MODELS)
    assert r.returncode == 0, r.stderr
    sol = _mega("solve", "--alpha", alpha)
    expected = [f"Explanation >> {e}" for e in sol["chosen"]["explanation"]]
    assert r.stdout.splitlines() == expected
    assert (tmp_path / "exp.dat").read_text().splitlines() == expected
    assert _plan_lines(tmp_path / "final_plan.sol") == sol["chosen"]["plan"]
    cost = f"; cost = {sol['chosen']['robot_cost']} (general cost)"
    assert cost in (tmp_path / "final_plan.sol").read_text()


def test_me_is_the_mce_and_mce_is_the_mme(tmp_path):
    examples = ROOT / "docs" / "examples"
    for search, kind, plan in (
        ("ME", [], examples / "usar-p1-explicable.plan"),
        ("MCE", ["--mme"], examples / "usar-p1-robot-optimal.plan"),
    ):
        r = _run(tmp_path, "mmp", "-s", search, *MODELS, "-f", str(plan))
        assert r.returncode == 0, r.stderr
        ex = _mega("explain", *kind, "--plan", str(plan))
        assert r.stdout.splitlines() == [f"Explanation >> {e}" for e in ex["explanation"]]
        assert _plan_lines(tmp_path / "final_plan.sol") == ex["plan"]
    # without -f: a robot-optimal plan, as in the original
    r = _run(tmp_path, "mmp", "-s", "ME", *MODELS)
    assert r.returncode == 0 and len(r.stdout.splitlines()) == 3
    # the monotonic search of a plan the robot would not choose: refused, as explain --mme
    r = _run(tmp_path, "mmp", "-s", "MCE", *MODELS, "-f", str(examples / "usar-p1-explicable.plan"))
    assert r.returncode == 2 and "not optimal in the robot model" in r.stderr


def test_the_trap_tells_the_two_searches_apart(tmp_path):
    trap = ROOT / "docs" / "examples" / "usar-trap"
    models = ["-m", str(trap / "robot-domain.pddl"), "-n", str(trap / "human-domain.pddl")]
    models += ["-p", str(trap / "robot-problem.pddl"), "-q", str(trap / "human-problem.pddl")]
    me = _run(tmp_path, "mmp", "-s", "ME", *models)
    mce = _run(tmp_path, "mmp", "-s", "MCE", *models)
    assert me.returncode == mce.returncode == 0
    assert len(me.stdout.splitlines()) < len(mce.stdout.splitlines())


def test_the_original_flags_are_accepted_and_each_says_what_it_does(tmp_path):
    r = _run(
        tmp_path,
        "mmp",
        "--search",
        "ee",
        "--alpha",
        "0.1",
        "--model",
        MODELS[1],
        "--nmodel",
        MODELS[3],
        "--problem",
        MODELS[5],
        "--hproblem",
        MODELS[7],
        "-t",
        "template-domain.pddl",
        "-r",
        "template-problem.pddl",
        "--approx",
        "--heuristic",
        "--ground",
    )
    assert r.returncode == 0, r.stderr
    notes = [x for x in r.stderr.splitlines() if "has no effect" in x or "not needed" in x]
    assert len(notes) == 5 and len(set(notes)) == 5
    assert r.stdout == "Explanation >> remove-has-initial-state-clear_path p1 p8\n"


def test_outputs_of_other_tools_are_not_replaced_without_force(tmp_path):
    (tmp_path / "exp.dat").write_text("my notes\n")
    r = _run(tmp_path, "mmp", "-s", "EE", "-a", "1", *MODELS)
    assert r.returncode == 2
    assert r.stderr.strip() == (
        f"error: {tmp_path / 'exp.dat'}: exists and is not an earlier answer of mega-sat mmp "
        "(use --force to replace it)"
    )
    assert (tmp_path / "exp.dat").read_text() == "my notes\n"
    assert not (tmp_path / "final_plan.sol").exists()
    r = _run(tmp_path, "mmp", "-s", "EE", "-a", "1", *MODELS, "--force")
    assert r.returncode == 0
    r = _run(tmp_path, "mmp", "-s", "EE", "-a", "10", *MODELS)  # its own answer: replaced
    assert r.returncode == 0 and len((tmp_path / "exp.dat").read_text().splitlines()) == 3


def test_bad_use_is_one_line(tmp_path):
    r = _run(tmp_path, "mmp", "-s", "EE", *MODELS)
    assert r.returncode == 2 and r.stderr.strip().startswith("error: -s EE needs -a/--alpha")
    r = _run(tmp_path, "mmp", "-s", "XX", *MODELS)
    assert r.returncode == 2 and len(r.stderr.strip().splitlines()) == 1
    r = _run(tmp_path, "mmp", "-s", "EE", "-a", "-1", *MODELS)
    assert r.returncode == 2 and "alpha" in r.stderr and len(r.stderr.strip().splitlines()) == 1
    assert not (tmp_path / "exp.dat").exists()
