"""The tuning knobs reach the engines (``MegaSolver(options=...)``, ``--option``), the docs list
every knob, planner calls answer with one result type and one status vocabulary, and a run
that runs out of time says so instead of blaming its input."""

from __future__ import annotations

import json
import re
from dataclasses import fields, replace
from pathlib import Path

import pytest
from click.testing import CliRunner
from helpers.minitasks import usar_like

from mega_sat import api
from mega_sat.cli.commands import main
from mega_sat.deadline import Deadline, TimeLimitReached
from mega_sat.errors import PlannerError, UsageError
from mega_sat.options import Options, markdown_table
from mega_sat.planners.fast_downward import fd_available
from mega_sat.planners.node_planner import NodePlan, NodePlanner
from mega_sat.search.astar import PlanResult
from mega_sat.status import Status

ROOT = Path(__file__).resolve().parent.parent
USAR = ROOT / "domains" / "usar-fetch" / "p1"


def test_cli_docs_list_exactly_the_options():
    text = (ROOT / "docs" / "cli.md").read_text()
    table = re.search(r"<!-- table: options -->\n(.*?)<!-- /table -->", text, re.S)
    assert table is not None
    listed = re.findall(r"^\| `(\w+)` \| `([^`]*)` \| (.+) \|$", table.group(1), re.M)
    assert [name for name, _, _ in listed] == [f.name for f in fields(Options)]
    assert table.group(1) == markdown_table()  # defaults and sentences as in the code


def test_solver_hands_its_options_to_every_planner_call(monkeypatch):
    """``blind_nodes`` reaches the built-in planner of the astar engine, MCE and verification;
    the answers do not change."""
    import mega_sat.search.astar as search

    seen = []
    real = search.solve_optimal

    def spy(task, **kw):
        seen.append(kw["blind_nodes"])
        return real(task, **kw)

    monkeypatch.setattr(search, "solve_optimal", spy)
    task = usar_like()
    own = Options(builtin_fd_after_blind=False)  # the built-in LM-cut, whether FD is there or not
    plain = api.MegaSolver(task, engine="astar", planner="builtin", options=own).frontier()
    n = len(seen)
    tuned = api.MegaSolver(
        task, engine="astar", planner="builtin", options=replace(own, blind_nodes=7)
    )
    fr = tuned.frontier()
    ex = tuned.explain()
    tuned.verify(ex, producer="sat")
    assert [(p.size, p.robot_cost) for p in fr.points] == [
        (p.size, p.robot_cost) for p in plain.points
    ]
    assert n and set(seen[:n]) == {300_000} and len(seen) > n and set(seen[n:]) == {7}


def test_sat_engine_takes_quick_nodes_and_core_work():
    task = usar_like()
    plain = api.MegaSolver(task, planner="sat").frontier()
    tuned = api.MegaSolver(
        task, planner="sat", options=Options(quick_nodes=1, unsolvable_core_work=10)
    ).frontier()
    assert [(p.selection, p.robot_cost) for p in tuned.points] == [
        (p.selection, p.robot_cost) for p in plain.points
    ]
    assert tuned.stats["opt_by_quick_search"] <= plain.stats["opt_by_quick_search"]


def test_a_joint_call_sat_has_not_settled_goes_to_the_search():
    """Under ``--joint sat`` a JOINT call past ``joint_sat_conflicts`` is answered by the
    paired-state search: the same frontier, still exact."""
    root = Path(__file__).resolve().parents[1]
    task = api.load_task_dir(root / "domains/blocksworld/delta/7/p1")
    plain = api.MegaSolver(task, joint="sat", options=Options(joint_sat_conflicts=0)).frontier()
    capped = api.MegaSolver(task, joint="sat", options=Options(joint_sat_conflicts=1)).frontier()
    assert [(p.size, p.robot_cost) for p in capped.points] == [
        (p.size, p.robot_cost) for p in plain.points
    ]
    assert capped.exact and plain.exact
    assert capped.stats["joint_searches"] > plain.stats["joint_searches"]


def test_a_joint_call_past_the_action_steps_goes_to_the_search_without_sat():
    """Under ``--joint sat`` a JOINT call that needs SAT at a horizon where ground actions
    times steps exceed ``joint_sat_action_steps`` is answered by the paired-state search before
    the JOINT encoding grows: the same frontier, still exact.  blocksworld Δ7 p1 asks SAT at
    horizon 7 over 60 ground actions (420 action steps)."""
    root = Path(__file__).resolve().parents[1]
    task = api.load_task_dir(root / "domains/blocksworld/delta/7/p1")
    plain = api.MegaSolver(task, joint="sat", options=Options(joint_sat_action_steps=0))
    small = api.MegaSolver(task, joint="sat", options=Options(joint_sat_action_steps=419))
    wide = api.MegaSolver(task, joint="sat", options=Options(joint_sat_action_steps=420))
    fp, fs, fw = plain.frontier(), small.frontier(), wide.frontier()
    assert [(p.size, p.robot_cost) for p in fs.points] == [
        (p.size, p.robot_cost) for p in fp.points
    ]
    assert fs.exact and fp.exact
    assert fp.stats["sat_joint_horizon"] == 7 and fp.stats["joint_searches"] == 0
    assert fs.stats["sat_joint_horizon"] == 0 and fs.stats["joint_searches"] > 0

    def untimed(f):
        return {k: v for k, v in f.stats.items() if "time" not in k}

    assert untimed(fw) == untimed(fp)  # at the limit itself SAT still answers
    # the oracle on its own: the call stops before SAT, with nothing proven
    r = small.oracles.joint(frozenset(), None, 7, max_action_steps=1)
    assert r.status == Status.LIMIT and not r.exact and "action steps" in r.reason


def test_the_size_limit_holds_for_the_joint_portfolio_and_the_plan_below_robot():
    """``joint_sat_action_steps`` also sends ``--joint portfolio`` calls to the search before
    the encoding grows (blocksworld Δ7 p1), and skips the SAT call for a plan below the robot
    optimum (barman-bar Δ2 p3): the same frontiers, still exact."""
    for name, grown in (("blocksworld/delta/7/p1", "sat_joint_horizon"),
                        ("barman-bar/delta/2/p3", "sat_plan_within_calls")):  # fmt: skip
        task = api.load_task_dir(ROOT / "domains" / name)
        free = api.MegaSolver(task, joint="portfolio").frontier()
        tight = api.MegaSolver(task, joint="portfolio", options=Options(joint_sat_action_steps=1))
        ft = tight.frontier()
        assert [(p.size, p.robot_cost) for p in ft.points] == [
            (p.size, p.robot_cost) for p in free.points
        ]
        assert ft.exact and free.exact
        assert free.stats[grown] > 0 and ft.stats.get(grown, 0) == 0


@pytest.mark.skipif(not fd_available(), reason="Fast Downward not installed")
def test_joint_calls_for_the_search_go_to_fast_downward_first():
    """With FD installed, the JOINT calls the paired-state search would answer go to FD on
    the product task (``joint_fd``; at once with ``joint_fd_after_work=0``); off, the search
    answers them.  Same frontier, exact."""
    task = api.load_task_dir(ROOT / "domains/blocksworld/delta/7/p1")
    runs = {}
    for on in (True, False):
        opts = Options(joint_sat_conflicts=1, joint_fd=on, joint_fd_after_work=0)
        runs[on] = api.MegaSolver(task, joint="sat", options=opts).frontier()
    assert [(p.size, p.robot_cost) for p in runs[True].points] == [
        (p.size, p.robot_cost) for p in runs[False].points
    ]
    assert runs[True].exact and runs[False].exact
    assert runs[True].stats["joint_by_fd"] > 0 and runs[True].stats["joint_fd_runs"] > 0
    assert runs[False].stats["joint_by_fd"] == 0 and runs[False].stats["joint_fd_runs"] == 0
    assert runs[False].stats["joint_searches"] > 0


def test_solver_refuses_options_of_another_type():
    with pytest.raises(UsageError, match="mega_sat.options.Options"):
        api.MegaSolver(usar_like(), options={"quick_nodes": 1})


@pytest.mark.parametrize("command", ["frontier", "solve", "explain", "verify", "plan"])
def test_cli_option_pairs_are_checked(command, tmp_path):
    extra = {"solve": ["--alpha", "1"], "verify": ["--explanation", "x", "--plan", "y"]}
    res = CliRunner().invoke(
        main, [command, "--task", str(USAR), *extra.get(command, []), "--option", "nope=1"]
    )
    lines = [ln for ln in res.output.splitlines() if ln.strip()]
    assert res.exit_code == 2 and len(lines) == 1, res.output
    assert lines[0].startswith("error: --option 'nope=1': unknown option 'nope'")


def test_cli_options_change_no_answer():
    def points(*extra):
        res = CliRunner().invoke(main, ["frontier", "--task", str(USAR), "--json", *extra])
        assert res.exit_code == 0, res.output
        return [(p["explanation"], p["robot_cost"]) for p in json.loads(res.output)["frontier"]]

    assert points("--option", "quick_nodes=1", "--option", "unsolvable-core-work=10") == points()


STARVED = (
    ("counting_time_limit=0.001",),
    ("counting_time_limit=0.001", "monotone_cores=false"),
    (
        "quick_nodes=1",
        "race_first_conflicts=1",
        "counting_time_limit=0.001",
        "race_processes=false",
    ),
)
"""Knob settings that starve the cheap proofs: each must still give the same frontier (a CBC
call cut short by a 1 ms limit once counted as a proof of "no plan", which dropped points and
moved others while the run said exact)."""


@pytest.mark.parametrize("task", ["blocksworld/delta/10/p3", "blocksworld/p2", "usar-fetch/p3"])
def test_starved_knobs_change_no_frontier(task):
    def pairs(*knobs: str):
        solver = api.MegaSolver(
            api.load_task_dir(ROOT / "domains" / task), options=Options().with_pairs(knobs)
        )
        fr = solver.frontier()
        assert fr.exact
        return [(p.size, p.robot_cost) for p in fr.points]

    want = pairs()
    for knobs in STARVED:
        assert pairs(*knobs) == want, knobs


def test_one_result_type_and_status_for_planner_calls():
    task = usar_like()
    solver = api.MegaSolver(task)
    for kind in ("builtin", "sat"):
        r = NodePlanner(task, solver.family, kind).optimal(solver.family.robot_selection)
        assert type(r) is PlanResult and r.status is Status.OPTIMAL and r.exact
        assert r.status == "optimal" and r.planner == kind
    assert NodePlan is PlanResult


def _undecided(self, selection):
    self.deadline.check()
    return PlanResult(Status.TIMEOUT, None, None, False, self.kind, 0.0, "timeout")


class _ExpiresSoon:
    """A deadline that passes after a few looks at the clock."""

    at = None
    seconds = 1.0
    limited = True

    def __init__(self):
        self.calls = 0

    def expired(self) -> bool:
        self.calls += 1
        return self.calls > 3

    def check(self) -> None:
        if self.expired():
            raise TimeLimitReached(self.seconds)

    def remaining(self):
        return None

    def cap(self, seconds):
        return seconds


def test_mce_out_of_time_is_a_time_limit_not_bad_input(monkeypatch):
    """A candidate whose optimum the planner could not decide is no evidence against the plan:
    at the deadline MCE raises TimeLimitReached (exit 124), and without a deadline it says the
    optimum was undecided, never that no explanation exists."""
    from mega_sat.engines.mce import minimal_explanation

    task = usar_like()
    fam = api.MegaSolver(task).family
    plan = NodePlanner(task, fam, "builtin").optimal(fam.robot_selection).plan
    monkeypatch.setattr(NodePlanner, "optimal", _undecided)
    # the robot's plan fails in the human model: candidates need an OPT call
    with pytest.raises(PlannerError, match="not decided"):
        minimal_explanation(task, fam, plan, deadline=Deadline())
    with pytest.raises(TimeLimitReached):
        minimal_explanation(task, fam, plan, deadline=_ExpiresSoon())


@pytest.mark.parametrize(
    "knob",
    [
        {"counting_time_limit": float("nan")},
        {"counting_time_limit": float("inf")},
        {"quick_nodes": "x"},
        {"horizon_cap": -1},
        {"horizon_cap": 2.5},
        {"step_first": "no"},
        {"step_first": 1},
    ],
)
def test_options_in_code_are_checked_like_the_cli_option(knob):
    """``Options(...)`` refuses what ``--option`` refuses: a nan time limit once made CBC's
    cut-short "infeasible" count as a proof (usar-fetch/p1 lost its point (3, 4), exact)."""
    with pytest.raises(UsageError, match=f"option {next(iter(knob))}="):
        Options(**knob)


def test_zero_is_kept_for_the_knobs_that_take_it():
    assert Options(race_fd_after_work=0, plan_below_robot_nodes=0).race_fd_after_work == 0


@pytest.mark.skipif(not fd_available(), reason="Fast Downward not installed")
def test_large_families_default_to_fast_downward():
    """``fd_from_actions``: at and above that many ground actions the sat engine's default OPT
    planner is FD; below it, with the knob at 0, for zero-cost actions and for the astar
    engine, the defaults stay.  The answers are the same."""
    from mega_sat.engines.sat_loop import default_planner

    task = api.load_task_dir(USAR)
    fam = api.MegaSolver(task).family
    n = len(fam.actions)
    at = Options(fd_from_actions=n)
    assert default_planner("sat", fam, at) == "fd"
    assert default_planner("sat", fam, Options(fd_from_actions=n + 1)) == "portfolio"
    assert default_planner("sat", fam, Options(fd_from_actions=0)) == "portfolio"
    assert default_planner("sat", fam) == "portfolio"  # the shipped suites stay below it
    assert default_planner("astar", fam, at) == "builtin"
    small = api.MegaSolver(task, options=at)
    assert small.planner == "fd"
    pairs = [[(len(p.explanation), p.robot_cost) for p in s.frontier().points] for s in (
        small, api.MegaSolver(task))]  # fmt: skip
    assert pairs[0] == pairs[1] and small.frontier().exact
    res = CliRunner().invoke(
        main, ["plan", "--task", str(USAR), "--json", "--option", f"fd_from_actions={n}"]
    )
    assert res.exit_code == 0 and json.loads(res.output)["planner"] == "fd"
