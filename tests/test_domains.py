"""The shipped benchmark domains: they load, have the documented model differences, round-trip
through the PDDL writer, agree across planners, and give oracle-checked, verified answers."""

from __future__ import annotations

import json
from pathlib import Path

import pytest
from helpers.bruteforce import brute_force_frontier

from mega_sat.api import MegaSolver
from mega_sat.engines.verify import verify_pair
from mega_sat.ground.grounding import ground
from mega_sat.model.features import gamma
from mega_sat.options import Options
from mega_sat.pddl.loading import load_task, resolve_task_dir
from mega_sat.pddl.reader import parse_model
from mega_sat.pddl.writer import domain_to_pddl, problem_to_pddl
from mega_sat.planners.fast_downward import fd_available
from mega_sat.planners.node_planner import NodePlanner

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


@pytest.mark.parametrize("rel", BASE)
def test_sat_opt_equals_builtin(rel):
    """SAT OPT on the human, robot and a mixed model of every base problem.  Built-in == Fast
    Downward on the same models is test_builtin_equals_fast_downward."""
    task = _task(rel)
    fam = ground(task)
    sat, builtin = NodePlanner(task, fam, "sat"), NodePlanner(task, fam, "builtin")
    race = NodePlanner(task, fam, "portfolio", options=Options(race_first_conflicts=1))
    sels = [frozenset(), task.all_updates, frozenset(range(1, len(task.delta), 2))]
    for sel in sels:
        a, b, c = sat.optimal(sel), builtin.optimal(sel), race.optimal(sel)
        assert (a.status, a.cost) == (b.status, b.cost) == (c.status, c.cost)
        assert a.exact and c.exact and c.planner in ("builtin", "sat")


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


# The independent oracle: domains/check_domains.py (no mega-sat code) enumerated every subset E
# of Delta of every shipped instance with |Delta| <= 8 (the 12 base problems and the generated
# Delta = 2 and Delta = 7 ones) with Fast Downward astar(lmcut()) for c*(E) and for the cheapest
# robot plan among plans optimal in human + E (a product task), and VAL-checked each frontier
# witness.  It takes about 10 minutes, so its output is stored; regenerate with:
#   python domains/check_domains.py --json tests/data/oracle_frontiers.json --deltas 2,7 --force
ORACLE_FILE = Path(__file__).resolve().parent / "data" / "oracle_frontiers.json"
ORACLE = json.loads(ORACLE_FILE.read_text())["instances"]


def test_oracle_covers_every_shipped_instance_up_to_delta_8():
    small = [rel for rel in BASE + DELTA if len(_task(rel).delta) <= 8]
    assert sorted(small) == sorted(ORACLE)
    assert all("error" not in v for v in ORACLE.values())


@pytest.mark.parametrize("rel", sorted(ORACLE))
def test_sat_frontier_equals_independent_oracle(rel):
    want = ORACLE[rel]
    task = _task(rel)
    assert sorted(u.name for u in task.delta) == sorted(want["delta"])
    solver = MegaSolver(task)
    fr = solver.frontier()
    assert fr.exact and fr.complete
    assert fr.robot_optimal_cost == want["robot_optimal_cost"]
    assert [(p.size, p.robot_cost) for p in fr.points] == [
        (p["explanation_size"], p["robot_cost"]) for p in want["frontier"]
    ]
    for p in fr.points:
        assert solver.verify(p, use_val=False).ok
    optima = want.get("human_optimum")
    if optima is None:
        return
    # MCE of the robot-optimal plan the solver picks: the smallest E in whose model the plan
    # runs at the oracle's optimum c*(E) (plans simulated by our simulator, optima from FD)
    from mega_sat.ground.simulate import simulate_ground

    mce = solver.explain()
    index = {u.name: i for i, u in enumerate(task.delta)}
    best = None
    for entry in optima:
        sel = frozenset(index[n] for n in entry["explanation"])
        if entry["cost"] is None or (best is not None and len(sel) >= best):
            continue
        sim = simulate_ground(solver.family.specialize(sel), mce.plan)
        if sim.valid and sim.cost == entry["cost"]:
            best = len(sel)
    assert mce.exact and len(mce.explanation) == best


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
