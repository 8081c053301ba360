"""The mega-sat command line, end to end: outputs, files written, and every user-error path
(one line naming file, place and problem; the documented exit code; never a traceback)."""

from __future__ import annotations

import json
from pathlib import Path

import pytest
from click.testing import CliRunner

from mega_sat.cli.commands import main

ROOT = Path(__file__).resolve().parent.parent
USAR = ROOT / "domains" / "usar-fetch" / "p1"

DOMAIN = """(define (domain d) (:requirements :strips :action-costs)
 (:predicates (at ?x) (road ?x ?y))
 (:functions (total-cost) - number)
 (:action go :parameters (?x ?y) :precondition (and (at ?x) (road ?x ?y))
  :effect (and (not (at ?x)) (at ?y) (increase (total-cost) 1))))"""
PROBLEM = """(define (problem p) (:domain d) (:objects a b c)
 (:init (at a) (road a b) (= (total-cost) 0)) (:goal (at {goal})) (:metric minimize (total-cost)))"""


def run(*args: str):
    return CliRunner().invoke(main, [str(a) for a in args])


def _single_error_line(res) -> str:
    lines = [ln for ln in res.output.splitlines() if ln.strip()]
    assert len(lines) == 1, res.output
    assert "Traceback" not in res.output
    assert lines[0].startswith("error: ")
    return lines[0]


@pytest.fixture
def toy(tmp_path):
    (tmp_path / "d.pddl").write_text(DOMAIN)
    (tmp_path / "p.pddl").write_text(PROBLEM.format(goal="b"))
    (tmp_path / "unsolvable.pddl").write_text(PROBLEM.format(goal="c"))
    return tmp_path


def test_diff_usar():
    res = run("diff", "--task", USAR)
    assert res.exit_code == 0
    assert res.output.splitlines() == [
        "add-has-initial-state-clear_path p6 p7",
        "add-has-initial-state-clear_path p7 p5",
        "remove-has-initial-state-clear_path p1 p8",
    ]
    js = json.loads(run("diff", "--task", USAR, "--json").output)
    assert js["size"] == 3


def test_solve_usar_low_and_high_alpha():
    low = run("solve", "--task", USAR, "--alpha", "0.1")
    assert low.exit_code == 0, low.output
    assert "Explanation >> remove-has-initial-state-clear_path p1 p8" in low.output
    assert "(clear_passage p2 p3)" in low.output
    assert low.output.count("Explanation >>") == 1
    high = run("solve", "--task", USAR, "--alpha", "10")
    assert high.exit_code == 0
    assert [ln for ln in high.output.splitlines() if ln.startswith("Explanation >>")] == [
        "Explanation >> add-has-initial-state-clear_path p6 p7",
        "Explanation >> add-has-initial-state-clear_path p7 p5",
        "Explanation >> remove-has-initial-state-clear_path p1 p8",
    ]
    assert "exact: yes" in high.output


def test_solve_json_schema_and_verify():
    res = run("solve", "--task", USAR, "--alpha", "0.1", "--json", "--verify")
    assert res.exit_code == 0, res.output
    d = json.loads(res.output)
    for key in (
        "robot_optimal_cost",
        "model_difference",
        "frontier",
        "alpha",
        "chosen",
        "engine",
        "exact",
        "time_s",
        "stats",
    ):
        assert key in d
    assert d["exact"] is True and d["engine"] == "sat"
    assert [len(p["explanation"]) for p in d["frontier"]] == sorted(
        len(p["explanation"]) for p in d["frontier"]
    )
    for p in d["frontier"] + [d["chosen"]]:
        assert set(p) >= {"explanation", "plan", "robot_cost", "human_cost"}
    assert "objective" in d["chosen"]
    assert all(v["ok"] for v in d["verify"])


def test_frontier_both_engines_agree():
    sat = json.loads(run("frontier", "--task", USAR, "--json").output)
    ast = json.loads(run("frontier", "--task", USAR, "--json", "--engine", "astar").output)
    pairs = lambda d: [(len(p["explanation"]), p["robot_cost"]) for p in d["frontier"]]  # noqa: E731
    assert pairs(sat) == pairs(ast) == [(1, 8), (3, 4)]
    assert ast["exact"] is False and ast["stats"]["nodes_expanded"] >= 1


@pytest.mark.parametrize("joint", ["sat", "search"])
def test_frontier_joint_methods_agree(joint):
    res = run("frontier", "--task", USAR, "--json", "--joint", joint)
    d = json.loads(res.output)
    assert res.exit_code == 0 and d["exact"] is True
    assert [(len(p["explanation"]), p["robot_cost"]) for p in d["frontier"]] == [(1, 8), (3, 4)]
    searched = d["stats"]["joint_searches"]
    assert searched == (0 if joint == "sat" else d["stats"]["joint_calls"])


def test_write_model_and_verify_files(tmp_path):
    out = tmp_path / "models"
    res = run("solve", "--task", USAR, "--alpha", "0.1", "--write-model", out)
    assert res.exit_code == 0, res.output
    (point,) = list(out.iterdir())
    for f in ("human-domain.pddl", "human-problem.pddl", "plan.ipc", "explanation.txt"):
        assert (point / f).is_file()
    # the footer is the plan's cost in the model beside it (it was the robot cost, which VAL
    # on these files does not give); the robot cost is a comment above the plan
    sol = json.loads(run("solve", "--task", USAR, "--alpha", "0.1", "--json").stdout)["chosen"]
    text = (point / "plan.ipc").read_text().splitlines()
    assert text[0] == f"; robot cost = {sol['robot_cost']}"
    assert text[-1] == f"; cost = {sol['human_cost']} (general cost)"
    # writing again without --force is refused, with --force allowed
    again = run("solve", "--task", USAR, "--alpha", "0.1", "--write-model", out)
    assert again.exit_code == 2 and "exists" in _single_error_line(again)
    assert (
        run("solve", "--task", USAR, "--alpha", "0.1", "--write-model", out, "--force").exit_code
        == 0
    )

    def verify(explanation, plan):
        return run("verify", "--task", USAR, "--explanation", explanation, "--plan", plan)

    ok = verify(point / "explanation.txt", point / "plan.ipc")
    assert ok.exit_code == 0 and "verify: passed" in ok.output
    # tampering: drop the explanation line -> the plan is no longer optimal for the human
    (tmp_path / "empty.txt").write_text("")
    bad = verify(tmp_path / "empty.txt", point / "plan.ipc")
    assert bad.exit_code == 1 and "FAIL" in bad.output
    # tampering: swap two plan steps -> not executable
    steps = (point / "plan.ipc").read_text().splitlines()
    steps[1], steps[2] = steps[2], steps[1]
    (tmp_path / "swapped.ipc").write_text("\n".join(steps) + "\n")
    bad2 = verify(point / "explanation.txt", tmp_path / "swapped.ipc")
    assert bad2.exit_code == 1 and "FAIL valid in robot model" in bad2.output


def test_explain_default_plan():
    res = run("explain", "--task", USAR, "--json")
    assert res.exit_code == 0, res.output
    d = json.loads(res.output)
    assert len(d["explanation"]) == 3 and d["exact"] is True


def test_plan_takes_the_library_default_planner(tmp_path):
    """portfolio, or builtin when some action costs 0 (bounded horizons prove nothing there)."""
    res = run("plan", "--task", USAR, "--json")
    assert res.exit_code == 0 and json.loads(res.output)["planner"] == "portfolio"
    dom = """(define (domain z) (:requirements :strips :action-costs)
      (:predicates (at ?x) (seen ?x)) (:functions (total-cost) - number)
      (:action go :parameters (?a ?b) :precondition (at ?a)
        :effect (and (at ?b) (not (at ?a)) (increase (total-cost) 1)))
      (:action look :parameters (?a) :precondition (at ?a) :effect (seen ?a)))"""
    prob = "(define (problem z1) (:domain z) (:objects a b) (:init (at a)) (:goal (seen b)))"
    (tmp_path / "d.pddl").write_text(dom)
    (tmp_path / "p.pddl").write_text(prob)
    res = run("plan", "--domain", tmp_path / "d.pddl", "--problem", tmp_path / "p.pddl", "--json")
    d = json.loads(res.output)
    assert res.exit_code == 0 and d["planner"] == "builtin" and d["cost"] == 1


def test_plan_validate_apply_encode(toy, tmp_path):
    res = run("plan", "--domain", toy / "d.pddl", "--problem", toy / "p.pddl")
    assert res.exit_code == 0
    assert res.output.splitlines() == ["(go a b)", "; cost = 1 (general cost)"]
    for planner in ("sat", "builtin", "portfolio"):
        r = run(
            "plan",
            "--domain",
            toy / "d.pddl",
            "--problem",
            toy / "p.pddl",
            "--planner",
            planner,
            "--json",
        )
        assert json.loads(r.output)["cost"] == 1
    (tmp_path / "plan.ipc").write_text("(go a b)\n")
    ok = run(
        "validate",
        "--plan",
        tmp_path / "plan.ipc",
        "--domain",
        toy / "d.pddl",
        "--problem",
        toy / "p.pddl",
    )
    assert ok.exit_code == 0 and "valid: 1 steps, cost 1" in ok.output
    (tmp_path / "bad.ipc").write_text("(go b a)\n")
    bad = run(
        "validate",
        "--plan",
        tmp_path / "bad.ipc",
        "--domain",
        toy / "d.pddl",
        "--problem",
        toy / "p.pddl",
    )
    assert bad.exit_code == 1 and "step 1" in bad.output and "(at b)" in bad.output
    # apply writes human + E; encode writes DIMACS files
    (tmp_path / "e.txt").write_text("remove-has-initial-state-clear_path p1 p8\n")
    ap = run("apply", "--task", USAR, "--explanation", tmp_path / "e.txt", "--out", tmp_path / "hE")
    assert ap.exit_code == 0
    assert "clear_path p1 p8" not in (tmp_path / "hE" / "problem.pddl").read_text()
    en = run("encode", "--task", USAR, "--out", tmp_path / "cnf")
    assert en.exit_code == 0, en.output
    assert any(p.suffix == ".cnf" for p in (tmp_path / "cnf").iterdir())


# ----------------------------------------------------------------------------- error paths


def test_error_malformed_pddl(toy):
    (toy / "broken.pddl").write_text("(define (domain d) (:predicates (at ?x)")
    res = run("plan", "--domain", toy / "broken.pddl", "--problem", toy / "p.pddl")
    assert res.exit_code == 2
    assert "broken.pddl" in _single_error_line(res)


def test_error_unsupported_construct(toy):
    (toy / "when.pddl").write_text(DOMAIN.replace("(at ?y)", "(when (at ?x) (at ?y))"))
    res = run("plan", "--domain", toy / "when.pddl", "--problem", toy / "p.pddl")
    line = _single_error_line(res)
    assert res.exit_code == 2 and "when.pddl" in line and "when" in line and "line" in line


def test_error_unsolvable_robot(toy):
    res = run("plan", "--domain", toy / "d.pddl", "--problem", toy / "unsolvable.pddl")
    assert res.exit_code == 3 and "no plan" in _single_error_line(res)
    res = run(
        "solve",
        "--robot-domain",
        toy / "d.pddl",
        "--robot-problem",
        toy / "unsolvable.pddl",
        "--human-domain",
        toy / "d.pddl",
        "--alpha",
        "1",
    )
    line = _single_error_line(res)
    assert res.exit_code == 3 and "unsolvable.pddl" in line and "no plan" in line


def test_error_mismatched_signatures(toy):
    (toy / "h.pddl").write_text(DOMAIN.replace(":parameters (?x ?y)", ":parameters (?x ?y ?z)"))
    res = run(
        "diff",
        "--robot-domain",
        toy / "d.pddl",
        "--robot-problem",
        toy / "p.pddl",
        "--human-domain",
        toy / "h.pddl",
    )
    line = _single_error_line(res)
    assert res.exit_code == 2 and "'go'" in line and "parameter" in line


@pytest.mark.parametrize("alpha", ["-1", "abc", "nan", "inf"])
def test_error_bad_alpha(alpha):
    res = run("solve", "--task", USAR, "--alpha", alpha)
    line = _single_error_line(res)
    assert res.exit_code == 2 and "alpha" in line


def test_error_unknown_update(tmp_path):
    (tmp_path / "e.txt").write_text("add-has-initial-state-clear_path p9 p9\n")
    res = run("apply", "--task", USAR, "--explanation", tmp_path / "e.txt", "--out", tmp_path / "o")
    line = _single_error_line(res)
    assert res.exit_code == 2 and "e.txt: line 1" in line and "not an update" in line


def test_error_missing_task_files(tmp_path):
    res = run("diff", "--task", tmp_path)
    assert res.exit_code == 2 and "robot-problem.pddl" in _single_error_line(res)
    res = run("diff", "--robot-domain", USAR.parent / "robot-domain.pddl")
    assert res.exit_code == 2 and "--robot-problem" in _single_error_line(res)


def test_error_apply_refuses_overwrite(tmp_path):
    (tmp_path / "e.txt").write_text("")
    out = tmp_path / "hE"
    assert (
        run("apply", "--task", USAR, "--explanation", tmp_path / "e.txt", "--out", out).exit_code
        == 0
    )
    res = run("apply", "--task", USAR, "--explanation", tmp_path / "e.txt", "--out", out)
    assert res.exit_code == 2 and "exists" in _single_error_line(res)


def test_generate_is_reproducible_and_its_time_budget_is_honoured(tmp_path):
    """The same seed writes the same human model; a search that runs out of its time budget
    is a one-line usage error, not a hang."""
    args = [
        "generate",
        "--robot-domain",
        USAR.parent / "robot-domain.pddl",
        "--robot-problem",
        USAR / "robot-problem.pddl",
        "--delta",
        "3",
        "--seed",
        "5",
    ]
    for name in ("a", "b"):
        res = run(*args, "--out", tmp_path / name)
        assert res.exit_code == 0, res.output
        assert "|Delta| = 3" in res.output
    for f in ("human-domain.pddl", "human-problem.pddl"):
        assert (tmp_path / "a" / f).read_text() == (tmp_path / "b" / f).read_text()
    res = run(*args, "--out", tmp_path / "c", "--time-budget", "0")
    assert res.exit_code == 2
    line = _single_error_line(res)
    assert "|Delta| = 3" in line and "within 0s" in line
    assert not (tmp_path / "c").exists()


def test_a_checker_that_fails_during_verify_keeps_the_answer(monkeypatch):
    """VAL or a planner failing inside --verify (it cannot read its file, it crashes) does not
    take the proven answer with it: the answer is printed, the points not checked say so, and
    the exit code is the tool's (4)."""
    import mega_sat.planners.val as val
    from mega_sat.errors import EXIT_TOOL, PlannerError

    def broken(*args, **kwargs):
        raise PlannerError("VAL failed (exit code 255): Problem in domain definition!")

    monkeypatch.setattr(val, "val_available", lambda: True)
    monkeypatch.setattr(val, "val_validate", broken)
    for command in (["frontier"], ["solve", "--alpha", "1"], ["explain"]):
        res = run(*command, "--task", USAR, "--verify")
        assert res.exit_code == EXIT_TOOL, res.output
        assert "exact: yes" in res.output and "Explanation >>" in res.output
        assert (
            "--verify could not finish: VAL could not check the plan in robot model" in res.output
        )
    d = json.loads(run("frontier", "--task", USAR, "--verify", "--json").stdout)
    assert d["frontier"] and d["complete"] is False and "verify" not in d
    assert any(n.startswith("--verify could not finish") for n in d["notes"])
