"""The shipped benchmark domains: they load, have the documented model differences, round-trip
through the PDDL writer, agree across planners, and give oracle-checked, verified answers."""

from __future__ import annotations

from pathlib import Path

import pytest

from mega_sat.api import MegaSolver
from mega_sat.bruteforce import brute_force_frontier
from mega_sat.fast_downward import fd_available
from mega_sat.features import gamma
from mega_sat.grounding import ground
from mega_sat.loading import load_task, resolve_task_dir
from mega_sat.node_planner import NodePlanner
from mega_sat.pddl_reader import parse_model
from mega_sat.pddl_writer import domain_to_pddl, problem_to_pddl
from mega_sat.verify import verify_pair

ROOT = Path(__file__).resolve().parent.parent
DOMAINS = ROOT / "domains"
BASE = sorted(p.relative_to(DOMAINS).as_posix() for p in DOMAINS.glob("*/p?"))
DELTA = sorted(p.relative_to(DOMAINS).as_posix() for p in DOMAINS.glob("*/delta/*/p?"))

# |Delta| of each base problem, as documented in domains/<name>/README.md
DOCUMENTED_DELTA = {
    "barman-bar/p1": 5, "barman-bar/p2": 5, "barman-bar/p3": 5,
    "blocksworld/p1": 2, "blocksworld/p2": 2, "blocksworld/p3": 3,
    "rover-martian/p1": 5, "rover-martian/p2": 5, "rover-martian/p3": 5,
    "usar-fetch/p1": 3, "usar-fetch/p2": 4, "usar-fetch/p3": 5,
}  # fmt: skip
# where the explicit brute-force oracle (2^|Delta| models, paired-state search) runs in seconds
ORACLE_FAST = [
    "barman-bar/p1",
    "blocksworld/p1",
    "blocksworld/p2",
    "blocksworld/p3",
    "rover-martian/p1",
    "usar-fetch/p1",
    "usar-fetch/p2",
    "usar-fetch/p3",
]
# where SAT OPT proves optimality in well under a second per model
SAT_OPT_FAST = [
    "blocksworld/p1",
    "blocksworld/p2",
    "blocksworld/p3",
    "usar-fetch/p1",
    "usar-fetch/p2",
    "usar-fetch/p3",
    "barman-bar/p1",
]


def _task(rel: str):
    return load_task(**resolve_task_dir(DOMAINS / rel))


def test_every_base_problem_is_shipped_and_documented():
    assert sorted(DOCUMENTED_DELTA) == BASE
    for name in {b.split("/")[0] for b in BASE}:
        readme = (DOMAINS / name / "README.md").read_text()
        assert "## Frontier" in readme


@pytest.mark.parametrize("rel", BASE)
def test_base_delta_size(rel):
    assert len(_task(rel).delta) == DOCUMENTED_DELTA[rel]


def test_generated_instances_have_their_delta():
    assert DELTA, "no generated Delta-k instances (run: mega-sat generate-suite domains)"
    for rel in DELTA:
        k = int(rel.split("/")[2])
        assert len(_task(rel).delta) == k, rel


@pytest.mark.parametrize("rel", BASE)
def test_round_trip_through_writer(rel):
    task = _task(rel)
    models = [
        task.robot,
        task.human,
        task.updated_model(task.all_updates),
        task.updated_model(range(0, len(task.delta), 2)),
    ]
    for m in models:
        back = parse_model(domain_to_pddl(m), problem_to_pddl(m))
        assert gamma(back) == gamma(m)


@pytest.mark.skipif(not fd_available(), reason="Fast Downward not installed")
@pytest.mark.parametrize("rel", BASE)
def test_builtin_equals_fast_downward(rel):
    task = _task(rel)
    fam = ground(task)
    for sel in (frozenset(), task.all_updates, frozenset(range(0, len(task.delta), 2))):
        a = NodePlanner(task, fam, "builtin").optimal(sel)
        b = NodePlanner(task, fam, "fd").optimal(sel)
        assert (a.status, a.cost) == (b.status, b.cost), sel


@pytest.mark.parametrize("rel", SAT_OPT_FAST)
def test_sat_opt_equals_builtin(rel):
    task = _task(rel)
    fam = ground(task)
    sat, builtin = NodePlanner(task, fam, "sat"), NodePlanner(task, fam, "builtin")
    for sel in (frozenset(), task.all_updates, frozenset(range(1, len(task.delta), 2))):
        a, b = sat.optimal(sel), builtin.optimal(sel)
        assert (a.status, a.cost) == (b.status, b.cost)
        assert a.exact


@pytest.mark.parametrize("rel", ORACLE_FAST)
def test_sat_frontier_equals_oracle_and_verifies(rel):
    task = _task(rel)
    solver = MegaSolver(task)
    fr = solver.frontier()
    c_r, pts, _ = brute_force_frontier(task, solver.family)
    assert fr.exact and fr.robot_optimal_cost == c_r
    assert [(p.size, p.robot_cost) for p in fr.points] == [(p.size, p.robot_cost) for p in pts]
    for p in fr.points:
        rep = verify_pair(
            task,
            solver.family,
            p.selection,
            p.plan,
            producer="builtin",
            robot_cost=p.robot_cost,
            human_cost=p.human_cost,
        )
        assert rep.ok, rep.lines()
    # MCE of the robot-optimal plan found is never smaller than the frontier's robot-optimal end
    assert len(solver.explain().explanation) >= fr.points[-1].size


# Frontiers computed by domains/check_domains.py --frontier: Fast Downward on every subset of
# Delta plus a joint robot/human problem, no mega-sat code involved (our own brute force takes
# minutes on these).  Regenerate with: python domains/check_domains.py --frontier rover-martian/p2
FD_BRUTE_FORCE = {"rover-martian/p2": [(0, 28), (1, 24), (2, 20), (3, 18)]}


@pytest.mark.parametrize("rel", sorted(FD_BRUTE_FORCE))
def test_sat_frontier_equals_fd_brute_force(rel):
    solver = MegaSolver(_task(rel))
    fr = solver.frontier()
    assert fr.exact
    assert [(p.size, p.robot_cost) for p in fr.points] == FD_BRUTE_FORCE[rel]
    for p in fr.points:
        assert solver.verify(p, use_val=False).ok


def test_usar_paper_outputs_exactly():
    solver = MegaSolver(_task("usar-fetch/p1"))
    low = solver.solve(0.1).chosen
    assert low.explanation == ("remove-has-initial-state-clear_path p1 p8",)
    assert ("clear_passage", "p2", "p3") in low.plan
    high = solver.solve(10).chosen
    assert high.explanation == (
        "add-has-initial-state-clear_path p6 p7",
        "add-has-initial-state-clear_path p7 p5",
        "remove-has-initial-state-clear_path p1 p8",
    )
    assert high.robot_cost == solver.frontier().robot_optimal_cost
    for p in (low, high):
        assert solver.verify(p).ok
    # the astar baseline reproduces the paper's answers too
    base = MegaSolver(solver.task, engine="astar")
    assert base.solve(0.1).chosen.explanation == low.explanation
    assert base.solve(10).chosen.explanation == high.explanation
