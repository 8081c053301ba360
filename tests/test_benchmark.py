"""The benchmark harness: a real smoke run through subprocess workers, and the table formatting
(speedups with time-outs) on fabricated records."""

from __future__ import annotations

import ast
import csv
import json
import re
import subprocess
import sys
from pathlib import Path

import pytest
from click.testing import CliRunner

import mega_sat.bench
from mega_sat.bench.harness import bench_command
from mega_sat.bench.tables import (
    disagreements,
    fmt_seconds,
    fmt_speedup,
    paper_table,
    render_markdown,
    scaling_table,
    speedup,
    summary,
)


def _cells(line: str) -> list[str]:
    """Cells of a markdown row; ``\\|`` inside a cell is an escaped pipe, not a separator."""
    return [c.strip() for c in re.split(r"(?<!\\)\|", line.strip().strip("|"))]


DOMAINS = Path(__file__).resolve().parent.parent / "domains"


def _rec(
    dom,
    prob,
    delta,
    engine,
    status="ok",
    seconds=1.0,
    e=2,
    limit=60.0,
    suite="paper",
    objective=None,
):
    return {
        "suite": suite,
        "domain": dom,
        "problem": prob,
        "delta": delta,
        "engine": engine,
        "planner": "fd" if engine == "astar" else "sat",
        "status": status,
        "seconds": seconds if status == "ok" else None,
        "time_limit_s": limit,
        "E_ropt": e if status == "ok" else None,
        "objective_alpha1": float(objective if objective is not None else e),
        "robot_optimal_cost": 10,
    }


# --------------------------------------------------------------------------- formatting


def test_speedup_both_finished():
    v, kind = speedup(
        _rec("d", "p1", 2, "astar", seconds=30.0), _rec("d", "p1", 2, "sat", seconds=0.5)
    )
    assert kind == "exact" and v == pytest.approx(60.0)
    assert (
        fmt_speedup(
            _rec("d", "p1", 2, "astar", seconds=30.0), _rec("d", "p1", 2, "sat", seconds=0.5)
        )
        == "60.0"
    )


def test_speedup_astar_timeout_is_a_lower_bound():
    a = _rec("d", "p1", 10, "astar", status="timeout", limit=300.0)
    s = _rec("d", "p1", 10, "sat", seconds=2.0)
    v, kind = speedup(a, s)
    assert kind == "lower" and v == pytest.approx(150.0)
    assert fmt_speedup(a, s) == "> 150"
    assert fmt_seconds(a) == "> 300"


def test_speedup_sat_timeout_is_an_upper_bound_and_both_timeout_is_unknown():
    a = _rec("d", "p1", 10, "astar", seconds=6.0)
    s = _rec("d", "p1", 10, "sat", status="timeout", limit=60.0)
    assert fmt_speedup(a, s) == "< 0.10"
    a2 = _rec("d", "p1", 10, "astar", status="timeout")
    assert speedup(a2, s) == (None, "none")
    assert fmt_speedup(a2, s) == "—"
    assert fmt_speedup(None, s) == "—"
    assert fmt_speedup(_rec("d", "p1", 2, "astar", status="error"), s) == "—"
    assert fmt_seconds(_rec("d", "p1", 2, "astar", status="error")) == "err"


def _grid():
    recs = []
    for prob, a10 in (("p1", 100.0), ("p2", None), ("p3", 40.0)):
        for k in (2, 7, 10):
            a_status = "timeout" if (k == 10 and a10 is None) else "ok"
            recs.append(
                _rec(
                    "rover",
                    prob,
                    k,
                    "astar",
                    status=a_status,
                    seconds=(a10 or 1.0) if k == 10 else 1.0,
                    e=3,
                )
            )
            recs.append(_rec("rover", prob, k, "sat", seconds=2.0 if k == 10 else 0.5, e=3))
    return recs


def test_paper_table_layout_and_summary():
    recs = _grid()
    table = paper_table(recs)
    lines = table.strip().splitlines()
    assert len(lines) == 2 + 3  # header, rule, three problems
    header = _cells(lines[0])
    assert header[:2] == ["Domain", "Problem"] and len(header) == 2 + 3 * 5
    p2 = _cells(lines[3])
    assert p2[0] == "rover" and p2[1] == "p2"
    # Delta = 10 block of p2: |E| astar, s astar, |E| sat, s sat, speedup
    assert p2[12:17] == ["—", "> 60.0", "3", "2.00", "> 30.0"]
    p1 = _cells(lines[2])
    assert p1[12:17] == ["3", "100", "3", "2.00", "50.0"]
    s = summary(recs)
    assert "Median speedup" in s[0] and "30.0" in s[0] and "lower bound" in s[0]
    assert "2.00 s" in s[1]
    assert "not run" in s[2]


def test_disagreements_classify_tie_weakness_and_bugs():
    recs = [
        _rec("d", "p1", 7, "astar", e=5),
        _rec("d", "p1", 7, "sat", e=4),
        _rec("d", "p2", 7, "astar", e=2),
        _rec("d", "p2", 7, "sat", e=3),
        _rec("d", "p3", 7, "astar", status="timeout"),
        _rec("d", "p3", 7, "sat", e=9),
    ]
    dis = disagreements(recs)
    by = {(d["problem"], d["column"]): d["kind"] for d in dis}
    assert by[("p1", "E_ropt")].startswith("astar tie weakness")
    assert by[("p2", "E_ropt")].startswith("BUG")
    assert not any(p == "p3" for p, _ in by)
    assert "†" in paper_table(recs)


def test_scaling_table_counts_astar_timeouts():
    recs = [
        _rec("d", "p1", 15, "astar", suite="scaling"),
        _rec("d", "p1", 15, "sat", suite="scaling"),
        _rec("d", "p1", 20, "astar", status="timeout", suite="scaling"),
        _rec("d", "p1", 20, "sat", seconds=3.0, suite="scaling"),
    ]
    text = scaling_table(recs)
    assert "| 20 | 1 | 0 | 1 | 1 | 0 |" in text
    assert "d/p1 Δ=20" in text
    md = render_markdown(recs, {"cpu": "x", "cores": 1}, ())
    assert "## Scaling" in md and "Paper grid" not in md


# --------------------------------------------------------------------------- smoke run


@pytest.mark.skipif(not (DOMAINS / "usar-fetch" / "p1").is_dir(), reason="usar-fetch absent")
def test_smoke_suite_end_to_end(tmp_path):
    out = tmp_path / "res"
    r = CliRunner().invoke(
        bench_command,
        [
            "--suite",
            "smoke",
            "--domains",
            str(DOMAINS),
            "--baseline-planner",
            "builtin",
            "--out",
            str(out),
            "--time-limit",
            "60",
            "--no-progress",
        ],
    )
    assert r.exit_code == 0, r.output
    for name in ("results.json", "results.csv", "table.md"):
        assert (out / name).is_file()
    data = json.loads((out / "results.json").read_text())
    assert data["machine"]["cores"] and data["machine"]["python"]
    recs = {r["engine"]: r for r in data["records"]}
    assert set(recs) == {"astar", "sat"}
    assert all(r["status"] == "ok" for r in recs.values()), recs
    assert recs["astar"]["E_ropt"] == recs["sat"]["E_ropt"]
    assert recs["astar"]["robot_optimal_cost"] == recs["sat"]["robot_optimal_cost"]
    assert recs["astar"]["planner"] == "builtin"
    assert recs["sat"]["exact"] is True and recs["sat"]["peak_rss_mb"] > 0
    assert recs["sat"]["robot_call_builtin_s"] is not None
    assert recs["sat"]["ratio_sat_vs_builtin_call"] is not None
    assert recs["astar"]["nodes_expanded"] >= 1 and recs["sat"]["iterations"] >= 1
    with (out / "results.csv").open() as f:
        rows = list(csv.DictReader(f))
    assert {row["engine"] for row in rows} == {"astar", "sat"}
    assert {row["status"] for row in rows} == {"ok"}
    assert len({row["E_ropt"] for row in rows}) == 1
    md = (out / "table.md").read_text()
    assert "usar-fetch/p1 astar" in md and "usar-fetch/p1 sat" in md
    assert "None where both engines finished" in md


# --------------------------------------------------------------------------- layout

BENCH = Path(mega_sat.bench.__file__).parent


def test_bench_modules_import_only_public_names():
    """The benchmark measures the engine through what it offers everyone: no bench module
    imports a name with a leading underscore from another mega_sat module."""
    private = []
    for path in sorted(BENCH.glob("*.py")):
        for node in ast.walk(ast.parse(path.read_text())):
            if isinstance(node, ast.ImportFrom) and (node.module or "").startswith("mega_sat"):
                private += [
                    f"{path.name}: {node.module}.{a.name}"
                    for a in node.names
                    if a.name.startswith("_") and a.name != "__future__"
                ]
    assert private == []


def test_harness_runs_as_a_module():
    """``python -m mega_sat.bench.harness`` is the command bench/README.md shows, and ``_run``
    the worker every engine run is spawned as."""
    for args, words in ((["--help"], "--suite"), (["_run", "--help"], "--robot-calls")):
        r = subprocess.run(
            [sys.executable, "-m", "mega_sat.bench.harness", *args],
            capture_output=True,
            text=True,
            timeout=120,
        )
        assert r.returncode == 0, r.stderr
        assert words in r.stdout


# --------------------------------------------------------------------------- generation


def _one_problem_domains(root: Path) -> Path:
    """``root/usar-fetch`` with the shipped domain files and problem p1 only."""
    import shutil

    d = root / "usar-fetch"
    (d / "p1").mkdir(parents=True)
    for name in ("robot-domain.pddl", "human-domain.pddl"):
        shutil.copyfile(DOMAINS / "usar-fetch" / name, d / name)
    for name in ("robot-problem.pddl", "human-problem.pddl"):
        src = DOMAINS / "usar-fetch" / "p1" / name
        if src.is_file():
            shutil.copyfile(src, d / "p1" / name)
    return root


@pytest.mark.skipif(not (DOMAINS / "usar-fetch" / "p1").is_dir(), reason="usar-fetch absent")
def test_generate_suite_and_bench_generate_share_one_loop(tmp_path):
    """``mega-sat generate-suite`` and ``mega-sat bench --generate`` draw the same instances
    (same per-instance seeds); ``--generate`` passes over folders already there, the CLI
    without --force reports them as not generated."""
    from mega_sat.bench.suites import generate_missing
    from mega_sat.cli.commands import main

    cli_root = _one_problem_domains(tmp_path / "cli")
    bench_root = _one_problem_domains(tmp_path / "bench")
    r = CliRunner().invoke(main, ["generate-suite", str(cli_root), "--deltas", "2"])
    assert r.exit_code == 0, r.output
    assert "usar-fetch/delta/2/p1: |Delta| = 2" in r.output
    log = generate_missing(bench_root, [2], seed=0)
    assert [(g["domain"], g["problem"], g["delta"], g["status"]) for g in log] == [
        ("usar-fetch", "p1", 2, "ok")
    ]
    for name in ("human-domain.pddl", "human-problem.pddl", "robot-problem.pddl"):
        got = (bench_root / "usar-fetch/delta/2/p1" / name).read_text()
        assert got == (cli_root / "usar-fetch/delta/2/p1" / name).read_text(), name
    assert generate_missing(bench_root, [2], seed=0) == []
    again = CliRunner().invoke(main, ["generate-suite", str(cli_root), "--deltas", "2"])
    assert again.exit_code == 1
    assert "skipped: file exists" in again.output


@pytest.mark.skipif(not (DOMAINS / "usar-fetch" / "p1").is_dir(), reason="usar-fetch absent")
@pytest.mark.parametrize("engine", ["astar", "sat"])
def test_a_run_stopped_by_its_limit_before_any_answer_is_a_timeout(engine):
    """The engines raise TimeLimitReached when the limit comes before they have anything to
    report; the record says ``timeout`` (the table's "> limit"), not ``error``."""
    from mega_sat.bench.runner import run_engine

    rec = run_engine(str(DOMAINS / "usar-fetch" / "p1"), engine, "builtin", 1e-6)
    assert rec["status"] == "timeout", rec
    assert "time limit" in rec["error"] and rec["seconds"] >= 0
    assert fmt_seconds({**rec, "time_limit_s": 1e-6}).startswith("> ")


def test_generate_skips_draws_whose_cost_terms_are_undefined():
    """A cost table defined only where a precondition allows the action (elevators' travel
    costs): a draw that drops that precondition makes undefined terms reachable.  Such a draw is
    no task; generate moves on to the next one instead of stopping with the grounding error."""
    from mega_sat.bench.generate import generate_human
    from mega_sat.ground.grounding import ground
    from mega_sat.model.task import TwoModelTask
    from mega_sat.pddl.reader import parse_model

    domain = """(define (domain d) (:requirements :strips :action-costs)
      (:predicates (at ?x) (road ?x ?y) (seen ?x))
      (:functions (total-cost) - number (dist ?x ?y) - number)
      (:action go :parameters (?x ?y) :precondition (and (at ?x) (road ?x ?y))
        :effect (and (at ?y) (not (at ?x)) (increase (total-cost) (dist ?x ?y))))
      (:action look :parameters (?x) :precondition (at ?x)
        :effect (and (seen ?x) (increase (total-cost) 1))))"""
    problem = """(define (problem p) (:domain d) (:objects a b c)
      (:init (at a) (road a b) (road b c) (= (dist a b) 2) (= (dist b c) 3))
      (:goal (and (at c) (seen b))) (:metric minimize (total-cost)))"""
    robot = parse_model(domain, problem)
    dropped = 0
    for seed in range(12):
        g = generate_human(robot, 2, seed, time_budget=30)
        task = TwoModelTask.from_models(robot, g.human)
        ground(task)  # every model the generated task stands for has its costs
        assert len(task.delta) == 2
        dropped += g.attempts > 1
    assert dropped > 0  # some seed met a draw without costs and went on


@pytest.mark.parametrize("domain,k", [("blocksworld", 7), ("rover-martian", 10), ("barman-bar", 7)])
def test_generate_keeps_the_same_draws_with_or_without_its_greedy_test(domain, k):
    """Each draw is checked for a plan first by greedy search, then by the optimal planner.
    The greedy test may only make a check faster: the kept draw, and how many draws it took,
    are those of the optimal planner alone, and every kept human problem has a plan.  (On
    barman-bar, seeds 2 and 3 meet a draw whose human problem has no goals left: its plan is
    empty, and still a plan.)"""
    from mega_sat.bench.generate import _has_plan, generate_human
    from mega_sat.ground.grounding import ground
    from mega_sat.model.task import TwoModelTask
    from mega_sat.pddl.reader import parse_model

    d = DOMAINS / domain
    robot = parse_model(
        (d / "robot-domain.pddl").read_text(), (d / "p1" / "robot-problem.pddl").read_text()
    )
    skipped = 0
    for seed in range(1, 4):
        fast = generate_human(robot, k, seed, time_budget=60)
        plain = generate_human(robot, k, seed, time_budget=60, greedy_evaluations=0)
        assert (fast.human, fast.updates, fast.attempts) == (
            plain.human,
            plain.updates,
            plain.attempts,
        )
        skipped += fast.attempts > 1
        alone = TwoModelTask.from_models(fast.human, fast.human)
        assert _has_plan(alone, ground(alone), float("inf"), None, 0) is True
    assert skipped > 0  # some seed met a draw without a plan, which both tests turned down


def test_has_plan_answers_no_for_a_model_without_a_plan():
    from mega_sat.bench.generate import _has_plan
    from mega_sat.ground.grounding import ground
    from mega_sat.model.task import TwoModelTask
    from mega_sat.pddl.reader import parse_model

    domain = """(define (domain d) (:requirements :strips)
      (:predicates (p) (q) (r))
      (:action a :parameters () :precondition (p) :effect (and (q) (not (p))))
      (:action b :parameters () :precondition (and (p) (q)) :effect (r)))"""
    for goal, want in (("(r)", False), ("(q)", True)):
        problem = f"(define (problem x) (:domain d) (:init (p)) (:goal {goal}))"
        m = parse_model(domain, problem)
        alone = TwoModelTask.from_models(m, m)
        for greedy in (0, 100):
            assert _has_plan(alone, ground(alone), float("inf"), None, greedy) is want
