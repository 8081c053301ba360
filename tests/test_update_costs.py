"""Weighted updates (``--update-costs``): both engines and MCE against the brute-force oracle
with random costs, the file format and its errors, and the library boundary.

With update costs the explanation cost is the sum of the costs of E's updates; the frontier is
over (cost(E), robot cost) and the objective is cost(E) + alpha * (extra robot cost).
"""

from __future__ import annotations

import json
from fractions import Fraction
from pathlib import Path

import pytest
from click.testing import CliRunner
from helpers.bruteforce import brute_force_frontier, brute_force_mce, check_witnesses
from helpers.fuzzing import oracle_settings
from helpers.minitasks import usar_like
from helpers.randomtasks import two_model_tasks
from helpers.tradeoff_tasks import tradeoff_tasks
from hypothesis import HealthCheck, given
from hypothesis import strategies as st
from test_runlimits import VERIFY_ARGS

from mega_sat.api import MegaSolver, load_task_dir
from mega_sat.cli.commands import main
from mega_sat.engines.astar import astar_frontier, astar_solve
from mega_sat.engines.mce import minimal_explanation
from mega_sat.engines.sat_loop import sat_frontier
from mega_sat.engines.verify import verify_pair
from mega_sat.errors import UnsolvableError
from mega_sat.ground.grounding import ground
from mega_sat.pddl.update_costs import (
    UpdateCostError,
    cost_vector,
    load_update_costs,
    parse_update_costs,
)
from mega_sat.planners.node_planner import NodePlanner
from mega_sat.results import choose
from mega_sat.sat.oracles import SatOracles

ROOT = Path(__file__).resolve().parent.parent
USAR = ROOT / "domains" / "usar-fetch" / "p1"
P6P7 = "add-has-initial-state-clear_path p6 p7"
P7P5 = "add-has-initial-state-clear_path p7 p5"
P1P8 = "remove-has-initial-state-clear_path p1 p8"

SETTINGS = oracle_settings(
    40, suppress_health_check=[HealthCheck.too_slow, HealthCheck.filter_too_much]
)
TASKS = st.one_of(two_model_tasks(max_delta=6), tradeoff_tasks())


def _solvable(task, costs=None):
    fam = ground(task)
    try:
        c_r, pts, results = brute_force_frontier(task, fam, state_limit=20_000, update_costs=costs)
    except ValueError:
        return None
    return fam, c_r, pts, results


def _pairs(points):
    return [(p.explanation_cost, p.robot_cost) for p in points]


def _w(sel, costs):
    return sum(costs[i] for i in sel)


def _costs_for(task, data) -> tuple[int, ...]:
    n = len(task.delta)
    return tuple(data.draw(st.lists(st.integers(1, 6), min_size=n, max_size=n), label="costs"))


# ---------------------------------------------------------------------------- engines


@SETTINGS
@given(TASKS, st.data(), st.sampled_from(["rc2", "ilp"]), st.sampled_from(["sat", "search"]))
def test_sat_frontier_with_costs_equals_brute_force(task, data, hs, joint):
    costs = _costs_for(task, data)
    got = _solvable(task, costs)
    if got is None:
        return
    fam, c_r, pts, results = got
    fr = sat_frontier(task, fam, hitting_set=hs, joint=joint, update_costs=costs)
    assert fr.robot_optimal_cost == c_r
    assert _pairs(fr.points) == _pairs(pts)
    assert fr.complete and fr.exact and fr.update_costs == costs
    assert all(p.weighted_cost == _w(p.selection, costs) for p in fr.points)
    check_witnesses(task, fam, fr.points, results, update_costs=costs)
    # one frontier answers every alpha: the brute-force optimum of the weighted objective
    for alpha in (0, 0.4, 1, 3, 100):
        a = Fraction(repr(float(alpha)))
        best = min(
            (_w(s, costs) + a * (r.robot_cost - c_r), r.robot_cost, _w(s, costs))
            for s, r in results.items()
            if r.robot_cost is not None
        )
        ch = choose(fr, alpha).chosen
        assert (ch.explanation_cost + a * (ch.robot_cost - c_r), ch.robot_cost) == best[:2]
        assert ch.explanation_cost == best[2]


@SETTINGS
@given(TASKS, st.data(), st.sampled_from([0, 0.5, 1, 4]))
def test_astar_with_costs_is_a_sound_baseline(task, data, alpha):
    costs = _costs_for(task, data)
    got = _solvable(task, costs)
    if got is None:
        return
    fam, c_r, pts, _ = got
    a = Fraction(repr(float(alpha)))
    sat = choose(sat_frontier(task, fam, update_costs=costs), alpha)
    ast = astar_solve(task, fam, alpha, planner="builtin", update_costs=costs)
    assert ast.chosen.weighted_cost == _w(ast.chosen.selection, costs)
    assert sat.chosen.explanation_cost + a * (sat.chosen.robot_cost - c_r) <= (
        ast.chosen.explanation_cost + a * (ast.chosen.robot_cost - c_r)
    )
    assert verify_pair(
        task, fam, ast.chosen.selection, ast.chosen.plan, producer="builtin", use_val=False
    ).ok
    afr = astar_frontier(task, fam, planner="builtin", update_costs=costs)
    for p in afr.points:
        assert p.weighted_cost == _w(p.selection, costs)
        assert any(
            q.explanation_cost <= p.explanation_cost and q.robot_cost <= p.robot_cost for q in pts
        )


@oracle_settings(60, suppress_health_check=[HealthCheck.too_slow, HealthCheck.filter_too_much])
@given(TASKS, st.data())
def test_astar_pops_models_in_order_of_cost(task, data):
    """The model-space queue is keyed by cost(E): the per-node planner sees the models in
    non-decreasing cost order (keyed by |E| it would not, whenever costs differ)."""
    costs = _costs_for(task, data)
    fam = ground(task)
    seen = []
    original = NodePlanner.optimal

    def spy(self, sel):
        seen.append(frozenset(sel))
        return original(self, sel)

    with pytest.MonkeyPatch.context() as mp:
        mp.setattr(NodePlanner, "optimal", spy)
        try:
            fr = astar_frontier(task, fam, planner="builtin", update_costs=costs)
        except UnsolvableError:
            return
    nodes = [_w(s, costs) for s in seen[1:]]  # the first call is the robot model's optimum
    assert nodes == sorted(nodes)
    assert len(nodes) == fr.stats["nodes_expanded"]


@SETTINGS
@given(TASKS, st.data())
def test_weighted_mce_equals_brute_force(task, data):
    costs = _costs_for(task, data)
    got = _solvable(task)
    if got is None:
        return
    fam = got[0]
    orc = SatOracles(fam)
    robot = orc.robot_optimal()
    ex = minimal_explanation(task, fam, robot.plan, oracles=orc, update_costs=costs)
    want = brute_force_mce(task, fam, robot.plan, state_limit=20_000, update_costs=costs)
    assert ex.weighted_cost == _w(ex.selection, costs) == want
    assert ex.human_cost == orc.opt(ex.selection).cost


@SETTINGS
@given(TASKS)
def test_all_costs_one_is_the_unweighted_problem(task):
    fam = ground(task)
    ones = (1,) * len(task.delta)
    try:
        plain = sat_frontier(task, fam)
    except UnsolvableError:
        return
    weighted = sat_frontier(task, fam, update_costs=ones)
    assert [(p.explanation, p.robot_cost, p.human_cost) for p in weighted.points] == [
        (p.explanation, p.robot_cost, p.human_cost) for p in plain.points
    ]
    assert [p.weighted_cost for p in weighted.points] == [p.size for p in plain.points]
    for alpha in (0, 0.5, 2, 50):
        assert choose(weighted, alpha).chosen.explanation == choose(plain, alpha).chosen.explanation
    afr = astar_frontier(task, fam, planner="builtin", update_costs=ones)
    aplain = astar_frontier(task, fam, planner="builtin")
    assert [(p.explanation, p.robot_cost) for p in afr.points] == [
        (p.explanation, p.robot_cost) for p in aplain.points
    ]


def test_anytime_lower_bound_is_on_the_cost():
    task = usar_like()
    costs = (4, 2, 3)
    fr = sat_frontier(task, ground(task), timeout=1e-9, update_costs=costs)
    assert not fr.complete
    assert fr.next_size_lower_bound is None and fr.next_cost_lower_bound is not None
    bound = fr.next_cost_lower_bound
    # the bound is worded as cost(E), and left out where it is 0 (true of every solution)
    assert any(f"cost(E) >= {bound}" in n for n in fr.notes) == (bound > 0)
    assert not any("|E| >=" in n for n in fr.notes)
    d = fr.to_dict()
    assert d["next_cost_lower_bound"] == fr.next_cost_lower_bound
    assert d["update_costs"] == dict(zip((u.name for u in task.delta), costs, strict=True))


# ---------------------------------------------------------------------------- usar p1


def test_costs_change_the_chosen_explanation():
    """usar-fetch p1, alpha 1: explaining the three map changes (|E| = 3) beats the detour
    (|E| = 1, 4 extra cost); when the new passage p6-p7 costs 5 to explain, the detour wins."""
    task = load_task_dir(str(USAR))
    plain = MegaSolver(task).solve(1)
    assert plain.chosen.explanation == (P6P7, P7P5, P1P8) and plain.chosen.robot_cost == 4
    s = MegaSolver(task, update_costs={P6P7: 5})
    got = s.solve(1)
    assert got.chosen.explanation == (P1P8,) and got.chosen.robot_cost == 8
    assert got.objective == 1 + 4
    assert _pairs(s.frontier().points) == [(1, 8), (7, 4)]
    ast = MegaSolver(task, engine="astar", update_costs={P6P7: 5}).solve(1)
    assert ast.chosen.explanation == (P1P8,)
    # every explanation needs p1-p8, so making it dear moves both points, not the choice
    dear = MegaSolver(task, update_costs={P1P8: 5})
    assert _pairs(dear.frontier().points) == [(5, 8), (7, 4)]
    assert dear.solve(1).chosen.robot_cost == 4
    rep = s.verify(got.chosen, use_val=False)
    assert rep.ok and rep.explanation_cost == 1 and rep.size == 1


def test_weighted_mce_on_usar():
    task = load_task_dir(str(USAR))
    ex = MegaSolver(task, update_costs={P7P5: 3}).explain()
    assert ex.weighted_cost == 1 + 1 + 3 and ex.to_dict()["explanation_cost"] == 5


# ---------------------------------------------------------------------------- library boundary


@pytest.mark.parametrize(
    ("costs", "words"),
    [
        ({"no-such-update": 2}, "not an update of the model difference"),
        ({P6P7: 0}, "positive integer"),
        ({P6P7: -3}, "positive integer"),
        ({P6P7: 1.5}, "positive integer"),
        ({P6P7: True}, "positive integer"),
        ({P6P7: "2"}, "positive integer"),
        ({P6P7: 10**12}, "larger than"),
        ({3: 1}, "update name is a str"),
        ([(P6P7, 2)], "mapping"),
    ],
)
def test_api_rejects_bad_costs(costs, words):
    task = load_task_dir(str(USAR))
    with pytest.raises(UpdateCostError) as e:
        MegaSolver(task, update_costs=costs)
    assert words in str(e.value) and not str(e.value).startswith("error: ")


def test_parser_format():
    text = (
        "\ufeff# costs for usar p1\n"
        "\n"
        f"{P6P7}   5\n"
        f"Explanation >> {P7P5} 2 ; inline comment\n"
        f"  {P1P8}\t+3   # another\n"
    )
    got = parse_update_costs(text, "x.costs")
    assert got.as_dict() == {P6P7: 5, P7P5: 2, P1P8: 3}
    assert got.lines == (3, 4, 5)
    task = load_task_dir(str(USAR))
    assert cost_vector(task, got) == (5, 2, 3)
    assert cost_vector(task, parse_update_costs(f"{P7P5} 4\n")) == (1, 4, 1)
    assert cost_vector(task, None) is None


# ---------------------------------------------------------------------------- CLI


def run(*args):
    return CliRunner().invoke(main, [str(a) for a in args])


def _error_line(res) -> str:
    lines = [ln for ln in res.output.splitlines() if ln.strip()]
    assert len(lines) == 1, res.output
    assert "Traceback" not in res.output and lines[0].startswith("error: ")
    return lines[0]


@pytest.mark.parametrize(
    ("text", "line", "words"),
    [
        (f"{P6P7} 2\nremove-has-initial-state-clear_path p8 p1 2\n", 2, "not an update"),
        (f"# c\n{P6P7} 0\n", 2, "must be a positive integer, got 0"),
        (f"{P6P7} -4\n", 1, "must be a positive integer, got -4"),
        (f"{P6P7} 2.5\n", 1, "must be a positive integer, got '2.5'"),
        (f"{P6P7}\n", 1, "must be a positive integer, got 'p7'"),
        ("lonely-token\n", 1, "expected an update name and its cost"),
        (f"{P6P7} 2\n\n{P6P7} 3\n", 3, "has a cost already (line 1)"),
        (f"{P6P7} 99999999999\n", 1, "larger than"),
    ],
)
@pytest.mark.parametrize("command", ["frontier", "solve", "verify", "explain"])
def test_cli_cost_file_errors(tmp_path, text, line, words, command):
    f = tmp_path / "bad.costs"
    f.write_text(text)
    extra = {
        "frontier": [],
        "solve": ["--alpha", "1"],
        "verify": [
            "--plan",
            ROOT / "docs/examples/usar-p1-explicable.plan",
            "--explanation",
            ROOT / "docs/examples/usar-p1-low-alpha.explanation",
        ],
        "explain": [],
    }[command]
    res = run(command, "--task", USAR, "--update-costs", f, *extra)
    assert res.exit_code == 2
    err = _error_line(res)
    assert err.startswith(f"error: {f}: line {line}: ") and words in err, err


@pytest.mark.parametrize("kind", ["missing", "folder", "binary"])
def test_cli_unreadable_cost_file(tmp_path, kind):
    f = tmp_path / "c.costs"
    if kind == "folder":
        f.mkdir()
    elif kind == "binary":
        f.write_bytes(b"\xff\xfe\x00bad")
    res = run("frontier", "--task", USAR, "--update-costs", f)
    assert res.exit_code == 2
    assert str(f) in _error_line(res)
    js = run("frontier", "--task", USAR, "--update-costs", f, "--json")
    assert js.exit_code == 2 and json.loads(js.stdout)["exit_code"] == 2


def test_cli_frontier_and_solve_with_costs(tmp_path):
    f = tmp_path / "usar.costs"
    f.write_text(f"# the new passage is hard to explain\n{P6P7} 5\n")
    res = run("frontier", "--task", USAR, "--update-costs", f)
    assert res.exit_code == 0, res.output
    assert "[0] cost(E) = 1, |E| = 1, robot cost 8" in res.output
    assert "[1] cost(E) = 7, |E| = 3, robot cost 4" in res.output
    d = json.loads(run("frontier", "--task", USAR, "--update-costs", f, "--json").stdout)
    assert d["update_costs"] == {P6P7: 5, P7P5: 1, P1P8: 1}
    assert [p["explanation_cost"] for p in d["frontier"]] == [1, 7]
    assert "next_cost_lower_bound" in d
    sol = run("solve", "--task", USAR, "--alpha", "1", "--update-costs", f, "--verify")
    assert sol.exit_code == 0, sol.output
    assert "cost(E) = 1, |E| = 1, objective = 1 + 1 * 4 = 5" in sol.output
    assert "explanation cost as reported: reported 1, update costs give 1" in sol.output
    js = json.loads(
        run("solve", "--task", USAR, "--alpha", "1", "--update-costs", f, "--json").stdout
    )
    assert js["chosen"]["explanation_cost"] == 1 and js["chosen"]["objective"] == 5
    # the same run without costs picks the robot-optimal plan and prints no cost
    plain = run("solve", "--task", USAR, "--alpha", "1")
    assert "|E| = 3, objective = 3 + 1 * 0 = 3" in plain.output and "cost(E)" not in plain.output
    pj = json.loads(run("frontier", "--task", USAR, "--json").stdout)
    assert "update_costs" not in pj and "next_cost_lower_bound" not in pj
    assert all("explanation_cost" not in p for p in pj["frontier"])


def test_cli_all_ones_file_gives_the_plain_frontier(tmp_path):
    f = tmp_path / "ones.costs"
    f.write_text(f"{P6P7} 1\n{P7P5} 1\n{P1P8} 1\n")
    a = json.loads(run("frontier", "--task", USAR, "--update-costs", f, "--json").stdout)
    b = json.loads(run("frontier", "--task", USAR, "--json").stdout)
    keys = ("explanation", "plan", "robot_cost", "human_cost")
    assert [{k: p[k] for k in keys} for p in a["frontier"]] == [
        {k: p[k] for k in keys} for p in b["frontier"]
    ]
    assert [p["explanation_cost"] for p in a["frontier"]] == [
        len(p["explanation"]) for p in b["frontier"]
    ]


def test_cli_verify_states_the_cost(tmp_path):
    f = tmp_path / "usar.costs"
    f.write_text(f"{P1P8} 4\n")
    args = [*VERIFY_ARGS, "--update-costs", f]  # the verify of docs/examples' usar-p1 pair
    res = run(*args)
    assert res.exit_code == 0, res.output
    assert "explanation cost under the update costs: cost(E) = 4, |E| = 1" in res.output
    d = json.loads(run(*args, "--json").stdout)
    assert d["explanation_cost"] == 4 and d["size"] == 1 and d["ok"]
    ex = run("explain", "--task", USAR, "--update-costs", f)
    assert ex.exit_code == 0 and "cost(E) = 6, |E| = 3" in ex.output


def test_load_update_costs_from_docs_example():
    costs = load_update_costs(ROOT / "docs/examples/usar-p1.costs")
    assert costs.as_dict() == {P6P7: 5}


def test_update_costs_built_in_code_are_checked():
    """An ``UpdateCosts`` made in code gets the checks a file or a mapping gets (a cost of 0
    once failed deep in the hitting set; a name given twice was taken silently)."""
    from mega_sat import api
    from mega_sat.pddl.update_costs import UpdateCostError, UpdateCosts

    task = api.load_task_dir(Path(__file__).resolve().parent.parent / "domains/usar-fetch/p1")
    name = task.delta[0].name
    for costs, message in [
        (((name, 0),), "must be a positive integer, got 0"),
        (((name, "x"),), "must be a positive integer, got 'x'"),
        (("x",), r"holds \(update name, cost\) pairs"),
        (((name, 2), (name, 3)), "is given twice"),
    ]:
        with pytest.raises(UpdateCostError, match=message):
            api.MegaSolver(task, update_costs=UpdateCosts(costs))
    ok = api.MegaSolver(task, update_costs=UpdateCosts(((name, 2),), (None, None)))
    assert ok.update_costs[0] == 2


def test_update_names_in_a_costs_file_in_any_case_and_spacing():
    from mega_sat.pddl.update_costs import parse_update_costs

    text = "\ufeffExplanation >> ADD-Has-Initial-State-clear_path  P6\tp7 4\n"
    assert parse_update_costs(text).costs == (("add-has-initial-state-clear_path p6 p7", 4),)
