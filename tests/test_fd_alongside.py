"""Fast Downward started ahead of need (mega_sat/planners/tiered_opt.py, node_planner.py): a run
that is not needed leaves nothing behind, and the sat engine's answers with FD as OPT's planner
are the same whether FD starts alongside the quick search and the robot's call or only once
the quick search has given up.  With FD, the search for a plan below the robot optimum can be
switched off."""

from __future__ import annotations

import os
import tempfile
from dataclasses import replace
from pathlib import Path

import pytest
from helpers.pddl_tasks import pigeonhole

from mega_sat.api import MegaSolver, load_task_dir
from mega_sat.errors import PlannerError
from mega_sat.ground.grounding import ground_model
from mega_sat.options import Options
from mega_sat.planners.fast_downward import FdRun, fd_available, fd_plan
from mega_sat.planners.node_planner import NodePlanner
from mega_sat.search.astar import astar
from mega_sat.status import Status

ROOT = Path(__file__).resolve().parent.parent
needs_fd = pytest.mark.skipif(not fd_available(), reason="Fast Downward not installed")

# nothing started ahead: FD only after the quick search gives up, one model at a time
SEQUENTIAL = Options(fd_alongside_quick_nodes=0, fd_first_candidate_ahead=False)


@pytest.fixture(autouse=True)
def _own_temp_folder(tmp_path, monkeypatch):
    """FD's folders go to this test's own temporary folder, where other tests running at the
    same time put none."""
    monkeypatch.setattr(tempfile, "tempdir", str(tmp_path))


def _fd_folders() -> set[str]:
    return {n for n in os.listdir(tempfile.gettempdir()) if n.startswith("mega-sat-fd-")}


def _alive(pid: int) -> bool:
    try:
        os.killpg(pid, 0)  # FD's driver leads its own process group
    except ProcessLookupError:
        return False
    return True


@needs_fd
def test_a_cancelled_run_leaves_no_process_and_no_folder():
    before = _fd_folders()
    run = FdRun(*pigeonhole(12))
    pid = run._proc.pid
    assert _alive(pid) and _fd_folders() - before
    run.cancel()
    assert not _alive(pid)
    assert _fd_folders() == before
    with pytest.raises(PlannerError, match="cancelled or has answered"):
        run.result()
    run.cancel()  # a second cancel is a no-op


@needs_fd
def test_a_run_answers_as_fd_plan_and_cleans_up():
    domain, problem = pigeonhole(3)
    before = _fd_folders()
    assert FdRun(domain, problem).result().status == fd_plan(domain, problem).status
    assert fd_plan(domain, problem).status == Status.UNSOLVABLE
    assert _fd_folders() == before


def test_the_search_calls_after_once_past_that_many_expansions():
    task = load_task_dir(ROOT / "domains/rover-martian/delta/2/p3")
    ground = ground_model(task.robot)
    calls: list[int] = []
    r = astar(ground, heuristic="blind", node_limit=600, after=(64, lambda: calls.append(1)))
    assert r.status == Status.LIMIT and calls == [1]
    done = astar(ground, heuristic="blind", after=(10**9, lambda: calls.append(2)))
    assert done.status == Status.OPTIMAL and calls == [1]  # ended before 10**9 expansions


@needs_fd
def test_prepare_then_discard_ends_the_run_and_optimal_takes_a_prepared_one():
    task = load_task_dir(ROOT / "domains/rover-martian/delta/2/p3")
    solver = MegaSolver(task, planner="fd")
    planner = NodePlanner(task, solver.family, "fd")
    before = _fd_folders()
    empty = frozenset()
    planner.prepare(empty)
    planner.prepare(empty)  # already running: not started twice
    assert len(_fd_folders() - before) == 1
    planner.discard()
    assert _fd_folders() == before
    planner.prepare(empty)
    prepared = planner.optimal(empty)
    assert _fd_folders() == before  # the prepared run answered the call
    plain = NodePlanner(task, solver.family, "fd").optimal(empty)
    assert (prepared.status, prepared.cost) == (plain.status, plain.cost) == (Status.OPTIMAL, 23)


@needs_fd
@pytest.mark.parametrize(
    ("name", "below"),
    [
        ("rover-martian/delta/2/p3", True),
        ("rover-martian/delta/2/p3", False),
        ("barman-bar/delta/7/p3", False),
        ("blocksworld/delta/7/p3", True),
    ],
)
def test_fd_started_ahead_gives_the_same_frontier(name, below):
    """Tasks whose quick searches miss (FD starts alongside them, and on E = {} alongside the
    robot's call) and hit (FD started past the threshold is ended), with and without the
    search for a plan below the robot optimum."""
    task = load_task_dir(ROOT / "domains" / name)
    before = _fd_folders()

    def frontier(options: Options):
        fr = MegaSolver(task, planner="fd", options=options).frontier()
        return fr, [(p.explanation, p.plan, p.robot_cost, p.human_cost) for p in fr.points]

    ahead, ahead_points = frontier(
        replace(Options(), fd_alongside_quick_nodes=64, plan_below_robot_with_fd=below)
    )
    sequential, sequential_points = frontier(replace(SEQUENTIAL, plan_below_robot_with_fd=below))
    assert ahead.exact and sequential.exact
    assert ahead_points == sequential_points
    assert ahead.stats["opt_planner_fd"] == sequential.stats["opt_planner_fd"]
    assert _fd_folders() == before  # every run started ahead and not needed was ended


@needs_fd
def test_with_fd_the_search_below_the_robot_optimum_can_be_switched_off():
    task = load_task_dir(ROOT / "domains/rover-martian/delta/2/p3")
    default = MegaSolver(task, planner="fd").frontier()
    off = Options(plan_below_robot_with_fd=False)
    without = MegaSolver(task, planner="fd", options=off).frontier()
    assert default.stats["sat_plan_within_calls"] >= 1
    assert not without.stats.get("sat_plan_within_calls")
    assert [(p.explanation, p.robot_cost) for p in default.points] == [
        (p.explanation, p.robot_cost) for p in without.points
    ]
    assert default.exact and without.exact
