"""Several human models on the command line and in the API: loading, output, errors."""

from __future__ import annotations

import json
import shutil
from pathlib import Path

import pytest
from click.testing import CliRunner
from helpers.multi_bruteforce import multi_brute_force_frontier

from mega_sat import api
from mega_sat.cli.commands import main
from mega_sat.errors import ModelMismatchError, UsageError
from mega_sat.ground.grounding import ground
from mega_sat.pddl.loading import load_task_dir
from mega_sat.pddl.multi_task import MultiHumanTask, load_multi_task_dir, resolve_multi_task_dir

ROOT = Path(__file__).resolve().parent.parent
TWO = ROOT / "domains" / "usar-two-commanders"
USAR = ROOT / "domains" / "usar-fetch" / "p1"
FILES = [
    "--robot-domain",
    TWO / "robot-domain.pddl",
    "--robot-problem",
    TWO / "robot-problem.pddl",
]


def run(*args):
    return CliRunner().invoke(main, [str(a) for a in args])


def _error_line(res) -> str:
    lines = [ln for ln in res.output.splitlines() if ln.strip()]
    assert len(lines) == 1, res.output
    assert "Traceback" not in res.output and lines[0].startswith("error: ")
    assert res.exit_code == 2
    return lines[0]


def test_example_frontier_equals_brute_force():
    task = load_multi_task_dir(TWO)
    assert isinstance(task, MultiHumanTask) and len(task.tasks) == 2
    fr = api.frontier(task)
    _, pts, _ = multi_brute_force_frontier(task, [ground(t) for t in task.tasks])
    pairs = [(p.size, p.robot_cost) for p in fr.points]
    assert pairs == [(p.size, p.robot_cost) for p in pts] == [(2, 8), (3, 5), (4, 4)]
    assert fr.exact
    # every update is a no-op for one of the commanders, except the shared new passages
    own = [{u.name for u in t.delta} for t in task.tasks]
    assert own[0] != own[1] and own[0] & own[1]


def test_task_folder_and_repeated_options_give_the_same_frontier():
    by_dir = run("frontier", "--task", TWO, "--json")
    assert by_dir.exit_code == 0, by_dir.output
    by_files = run(
        "frontier",
        *FILES,
        "--human-domain",
        TWO / "human-domain.pddl",
        "--human-problem",
        TWO / "human-1" / "human-problem.pddl",
        "--human-domain",
        TWO / "human-domain.pddl",
        "--human-problem",
        TWO / "human-2" / "human-problem.pddl",
        "--json",
    )
    assert by_files.exit_code == 0, by_files.output
    a, b = json.loads(by_dir.output), json.loads(by_files.output)
    assert a["frontier"] == b["frontier"]
    assert [p["human_costs"] for p in a["frontier"]] == [[8, 8], [5, 5], [4, 4]]
    assert len(a["human_models"]) == 2 and a["exact"] is True


def test_solve_text_names_every_human_cost_and_verifies():
    res = run("solve", "--task", TWO, "--alpha", "0.5", "--verify")
    assert res.exit_code == 0, res.output
    assert "human costs (5, 5)" in res.output
    assert "human model 2: optimal in human + E" in res.output
    assert "exact: yes" in res.output


def test_one_human_output_is_unchanged():
    res = run("solve", "--task", USAR, "--alpha", "0.1")
    assert "human cost 8," in res.output and "human costs" not in res.output
    js = json.loads(run("frontier", "--task", USAR, "--json").output)
    assert "human_models" not in js and "human_cost" in js["frontier"][0]


def test_one_human_folder_takes_the_one_human_path(tmp_path):
    d = tmp_path / "t"
    shutil.copytree(TWO, d)
    shutil.rmtree(d / "human-2")
    task = load_multi_task_dir(d)
    assert not isinstance(task, MultiHumanTask)
    res = run("diff", "--task", d)
    assert res.exit_code == 0 and len(res.output.splitlines()) == 4


@pytest.mark.parametrize(
    ("args", "words"),
    [
        (["frontier", "--task", TWO, "--engine", "astar"], "engine 'astar' takes one human"),
        (["frontier", "--task", TWO, "--joint", "search"], "--joint does not apply"),
        (["frontier", "--task", TWO, "--write-model", "x"], "--write-model takes one human"),
        (["diff", "--task", TWO], "only 'solve' and 'frontier'"),
        (["explain", "--task", TWO], "only 'solve' and 'frontier'"),
        (
            [
                "frontier",
                *FILES,
                "--human-domain",
                TWO / "human-domain.pddl",
                "--human-domain",
                TWO / "human-domain.pddl",
                "--human-problem",
                TWO / "human-1" / "human-problem.pddl",
            ],
            "2 --human-domain and 1 --human-problem",
        ),
    ],
)
def test_refusals_are_one_line(args, words):
    assert words in _error_line(run(*args))


def test_folder_errors_name_the_file(tmp_path):
    d = tmp_path / "t"
    shutil.copytree(TWO, d)
    (d / "human-2" / "human-problem.pddl").unlink()
    line = _error_line(run("frontier", "--task", d))
    assert "human-2" in line and "no human-problem.pddl" in line
    (d / "human-2").rename(d / "human-3")
    assert "expected human-2, found human-3" in _error_line(run("frontier", "--task", d))


def test_mismatched_action_signature_names_the_files(tmp_path):
    d = tmp_path / "t"
    shutil.copytree(TWO, d)
    text = (d / "human-domain.pddl").read_text()
    bad = text.replace(
        ":parameters (?loc - waypoint)", ":parameters (?loc - waypoint ?x - waypoint)"
    )
    assert bad != text
    (d / "human-2" / "human-domain.pddl").write_text(bad)
    line = _error_line(run("frontier", "--task", d))
    assert "take_picture" in line and "human-2" in line
    with pytest.raises(ModelMismatchError):
        load_multi_task_dir(d)


def test_the_one_human_loader_refuses_a_folder_of_several():
    with pytest.raises(UsageError, match="human-K folders"):
        load_task_dir(TWO)
    paths = resolve_multi_task_dir(TWO)
    assert [p[1].parent.name for p in paths["humans"]] == ["human-1", "human-2"]


def test_api_solve_and_verify_dispatch():
    task = api.load_multi_task(
        TWO / "robot-domain.pddl",
        TWO / "robot-problem.pddl",
        [(TWO / "human-domain.pddl", TWO / f"human-{k}" / "human-problem.pddl") for k in (1, 2)],
    )
    sol = api.solve(task, alpha=10)
    assert sol.chosen.robot_cost == 4 and sol.chosen.human_costs == (4, 4)
    assert api.verify(task, sol.chosen, use_val=False).ok
    with pytest.raises(UsageError):
        api.solve(task, alpha=1, engine="astar")


def test_update_costs_on_the_example(tmp_path):
    costs = tmp_path / "costs.txt"
    costs.write_text("remove-has-initial-state-clear_path p2 p5 5\n")
    res = run("frontier", "--task", TWO, "--update-costs", costs, "--json")
    assert res.exit_code == 0, res.output
    js = json.loads(res.output)
    assert [(p["explanation_cost"], p["robot_cost"]) for p in js["frontier"]] == [
        (6, 8),
        (7, 5),
        (8, 4),
    ]
    res = run("frontier", "--task", TWO, "--update-costs", tmp_path / "missing.txt")
    assert res.exit_code != 0 and "Traceback" not in res.output
