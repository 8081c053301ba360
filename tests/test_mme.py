"""MME (minimally monotonic explanation) against a brute-force oracle, and its CLI and API.

The oracle (``helpers.bruteforce.brute_force_mme``) simulates the plan and computes the
optimum of every ``human + E'`` by explicit-state Dijkstra over all ``2^|Delta|`` subsets; it
shares no code with the hitting-set loop or the superset searches of ``mega_sat.engines.mme``.
"""

from __future__ import annotations

import json
from dataclasses import replace
from pathlib import Path

import pytest
from click.testing import CliRunner
from helpers.bruteforce import _Space, brute_force_mme
from helpers.fuzzing import oracle_settings
from helpers.minitasks import _nav_model, hidden_trap, usar_like
from helpers.randomtasks import two_model_tasks
from helpers.tradeoff_tasks import tradeoff_tasks
from hypothesis import HealthCheck, given
from hypothesis import strategies as st

from mega_sat.api import MegaSolver, load_task_dir
from mega_sat.cli.commands import main
from mega_sat.deadline import NO_DEADLINE
from mega_sat.engines.mce import minimal_explanation
from mega_sat.engines.mme import cheaper_superset, failing_superset, minimally_monotonic_explanation
from mega_sat.errors import MegaSatError, UsageError
from mega_sat.ground.grounding import ground
from mega_sat.ground.simulate import simulate_ground
from mega_sat.model.task import TwoModelTask

ROOT = Path(__file__).resolve().parent.parent
USAR = ROOT / "domains" / "usar-fetch" / "p1"
TRAP = ROOT / "docs" / "examples" / "usar-trap"
EXPLICABLE = ROOT / "docs" / "examples" / "usar-p1-explicable.plan"

SETTINGS = oracle_settings(
    80, suppress_health_check=[HealthCheck.too_slow, HealthCheck.filter_too_much]
)


@st.composite
def nav_maps(draw) -> TwoModelTask:
    """Random corridor maps whose human map differs in a few corridors: revealing one new
    corridor often opens a route that only revealing a closed one shuts (hidden traps)."""
    nodes = ["s", "a", "b", "c", "g"]
    edges = [(x, y) for x in nodes for y in nodes if x != y and x != "g" and y != "s"]
    edges.remove(("s", "g"))
    u, v = draw(st.permutations(nodes[1:4]))[:2]
    route = {("s", u), (u, v), (v, "g")}  # the robot can always reach g
    robot_paths = route | set(draw(st.lists(st.sampled_from(edges), max_size=6)))
    rubble = set(draw(st.lists(st.sampled_from(edges), max_size=2))) - robot_paths
    flips = set(draw(st.lists(st.sampled_from(edges), min_size=1, max_size=4)))
    if draw(st.booleans()):
        # a trap candidate: a corridor s->m only the robot knows, m->g only the human believes
        m = draw(st.sampled_from(nodes[1:4]))
        robot_paths = (robot_paths | {("s", m)}) - {(m, "g")}
        flips |= {("s", m), (m, "g")}
    robot = _nav_model(robot_paths, rubble)
    robot = replace(robot, objects=frozenset(nodes))
    human_init = set(robot.init) ^ {("clear_path", *e) for e in flips}
    return TwoModelTask.from_models(robot, replace(robot, init=frozenset(human_init)))


@st.composite
def cost_tasks(draw) -> TwoModelTask:
    """2-4 schemas reaching ``done`` directly or through ``half``, with random costs 0-3 in
    each model: the plan's own cost and its rivals' change with the updates (and may be 0)."""
    from mega_sat.model.lifted import Model, Schema

    shapes = [
        (frozenset(), frozenset({("done",)})),
        (frozenset(), frozenset({("half",)})),
        (frozenset({("half",)}), frozenset({("done",)})),
    ]
    names = [f"s{k}" for k in range(draw(st.integers(2, 4)))]
    shape = {n: draw(st.sampled_from(shapes)) for n in names}

    def model(costs):
        schemas = {n: Schema(n, (), pre=shape[n][0], add=shape[n][1], cost=costs[n]) for n in names}
        return Model("d", "p", {"done": 0, "half": 0}, schemas, frozenset(), frozenset(),
                     frozenset({("done",)}), uses_costs=True)  # fmt: skip

    robot = {n: draw(st.integers(0, 3)) for n in names}
    human = {n: draw(st.integers(0, 3)) for n in names}
    return TwoModelTask.from_models(model(robot), model(human))


TASKS = st.one_of(
    two_model_tasks(max_delta=6),
    two_model_tasks(max_delta=5, allow_zero_cost=True),
    tradeoff_tasks(),
    nav_maps(),
    cost_tasks(),
)


def _optimal_in_every_superset(task, fam, sel, plan) -> bool:
    n = len(task.delta)
    rest = [i for i in range(n) if i not in sel]
    for mask in range(1 << len(rest)):
        t = fam.specialize(sel | {rest[k] for k in range(len(rest)) if mask >> k & 1})
        sim = simulate_ground(t, plan)
        if not (sim.valid and sim.cost == _Space(t, 20_000).opt):
            return False
    return True


def _robot_plan(fam):
    robot = _Space(fam.specialize(fam.robot_selection), 20_000)
    if robot.opt is None:
        return None
    from mega_sat.search.astar import solve_optimal

    return solve_optimal(fam.specialize(fam.robot_selection)).plan


def _family_and_plan(task):
    """The ground family and a robot-optimal plan, or None where the oracle cannot follow
    (no robot plan, or a state space too large for it)."""
    fam = ground(task)
    try:
        plan = _robot_plan(fam)
    except RuntimeError:  # state space too large for the oracle
        return None
    return None if plan is None else (fam, plan)


@SETTINGS
@given(TASKS, st.sampled_from(["rc2", "ilp"]), st.sampled_from(["builtin", "sat"]))
def test_mme_equals_brute_force(task, hs, planner):
    got = _family_and_plan(task)
    if got is None:
        return
    fam, plan = got
    ex = minimally_monotonic_explanation(task, fam, plan, hitting_set=hs, planner=planner)
    assert ex.kind == "mme" and ex.exact
    assert len(ex.explanation) == brute_force_mme(task, fam, plan, state_limit=20_000)
    assert _optimal_in_every_superset(task, fam, ex.selection, plan)
    assert ex.explanation == tuple(task.names(ex.selection))
    mce = minimal_explanation(task, fam, plan)
    assert len(mce.explanation) <= len(ex.explanation)


@SETTINGS
@given(TASKS, st.data())
def test_cheapest_mme_under_update_costs_equals_brute_force(task, data):
    """With update costs the loop returns the cheapest monotonic E (its clauses do not depend
    on the costs; only the hitting set minimises their sum)."""
    got = _family_and_plan(task)
    if got is None:
        return
    fam, plan = got
    n = len(task.delta)
    costs = tuple(data.draw(st.lists(st.integers(1, 5), min_size=n, max_size=n)))
    hs = data.draw(st.sampled_from(["rc2", "ilp"]))
    ex = minimally_monotonic_explanation(task, fam, plan, hitting_set=hs, update_costs=costs)
    want = brute_force_mme(task, fam, plan, state_limit=20_000, update_costs=costs)
    assert ex.weighted_cost == sum(costs[i] for i in ex.selection) == want
    assert _optimal_in_every_superset(task, fam, ex.selection, plan)


@SETTINGS
@given(TASKS, st.data())
def test_superset_searches_equal_enumeration(task, data):
    """``failing_superset`` / ``cheaper_superset`` find a witness exactly when one of the
    supersets of ``E`` has the plan failing / a cheaper plan, and the witness is real."""
    got = _family_and_plan(task)
    if got is None:
        return
    fam, plan = got
    n = len(task.delta)
    sel = data.draw(st.frozensets(st.integers(0, n - 1)) if n else st.just(frozenset()))
    rest = [i for i in range(n) if i not in sel]
    fails = cheaper = False
    for mask in range(1 << len(rest)):
        t = fam.specialize(sel | {rest[k] for k in range(len(rest)) if mask >> k & 1})
        sim = simulate_ground(t, plan)
        if not sim.valid:
            fails = True
        elif sim.cost > _Space(t, 20_000).opt:
            cheaper = True
    got = failing_superset(fam, plan, sel)
    assert (got is not None) == fails
    if got is not None:
        assert sel <= got and not simulate_ground(fam.specialize(got), plan).valid
    if not fails:
        found = cheaper_superset(fam, plan, sel, NO_DEADLINE)
        assert (found is not None) == cheaper
        if found is not None:
            bigger, other = found
            t = fam.specialize(bigger)
            assert sel <= bigger
            assert simulate_ground(t, other).valid
            assert simulate_ground(t, other).cost < simulate_ground(t, plan).cost


def test_hidden_trap_tells_mme_from_mce():
    task = hidden_trap()
    fam = ground(task)
    plan = (("move", "s", "x"), ("move", "x", "y"), ("move", "y", "g"))
    mce = minimal_explanation(task, fam, plan)
    mme = minimally_monotonic_explanation(task, fam, plan)
    assert mce.explanation == ()
    assert mme.explanation == ("remove-has-initial-state-clear_path a g",)
    assert brute_force_mme(task, fam, plan) == 1
    s = MegaSolver(task)
    assert s.explain(kind="mme").explanation == mme.explanation
    assert s.explain().explanation == ()


def test_a_passed_deadline_stops_the_superset_search_at_its_next_expansion():
    """Each expansion of ``cheaper_superset`` passes over every action and takes h^max of the
    successors; on large families a few hundred take seconds, so the deadline is looked at
    on each one (``explain --mme --timeout`` then ends on time)."""
    from mega_sat.deadline import Deadline, TimeLimitReached

    task = hidden_trap()
    fam = ground(task)
    plan = (("move", "s", "x"), ("move", "x", "y"), ("move", "y", "g"))
    counter: dict[str, int] = {}
    assert cheaper_superset(fam, plan, frozenset(), NO_DEADLINE, counter) is not None
    assert 0 < counter["expanded"] < 256
    with pytest.raises(TimeLimitReached):
        cheaper_superset(fam, plan, frozenset(), Deadline.after(1, elapsed=2))


def _cost_trap(robot_costs: dict[str, int], human_costs: dict[str, int]) -> TwoModelTask:
    from mega_sat.model.lifted import Model, Schema

    def model(costs):
        schemas = {n: Schema(n, (), add=frozenset({("done",)}), cost=c) for n, c in costs.items()}
        return Model("d", "p", {"done": 0}, schemas, frozenset(), frozenset(),
                     frozenset({("done",)}), uses_costs=True)  # fmt: skip

    return TwoModelTask.from_models(model(robot_costs), model(human_costs))


def test_cost_updates_of_the_plan_are_a_trap_too():
    """The plan (a) costs 2 for the robot and 1 for the human; b costs 3 and 1.  Both cost 1
    for the human: (a) is optimal; told only a's true cost, the human prefers b, so the MME
    must also correct b's cost.  (The abstraction's bound must use the plan's greatest cost
    over the supersets, not its cost in the candidate.)"""
    task = _cost_trap({"a": 2, "b": 3}, {"a": 1, "b": 1})
    fam = ground(task)
    plan = (("a",),)
    assert minimal_explanation(task, fam, plan).explanation == ()
    mme = minimally_monotonic_explanation(task, fam, plan)
    assert mme.explanation == ("add-b-has-cost-3",)
    assert brute_force_mme(task, fam, plan) == 1


def test_usar_like_mme_equals_mce():
    s = MegaSolver(usar_like())
    assert len(s.explain(kind="mme").explanation) == len(s.explain().explanation) == 3


def test_api_refuses_a_plan_not_robot_optimal():
    task = usar_like()
    s = MegaSolver(task)
    detour = [
        ("clear_passage", "s", "a"),
        ("move", "s", "a"),
        ("move", "a", "g"),
    ]
    with pytest.raises(UsageError, match="costs 7, the robot optimum is 3"):
        s.explain(detour, kind="mme")
    assert len(s.explain(detour).explanation) == 1  # its MCE exists


def test_api_validates_kind():
    s = MegaSolver(usar_like())
    with pytest.raises(
        MegaSatError, match=r"unknown explanation kind 'mmx' \(choose from mce, mme\)"
    ):
        s.explain(kind="mmx")


# ------------------------------------------------------------------ shipped base problems

BASE = sorted(
    str(p.relative_to(ROOT / "domains"))
    for p in (ROOT / "domains").glob("*/p[123]")
    if (p / "robot-problem.pddl").exists()
)


@pytest.mark.parametrize("rel", BASE)
def test_shipped_base_problems_equal_brute_force(rel):
    task = load_task_dir(str(ROOT / "domains" / rel))
    if len(task.delta) > 10:
        pytest.skip("|Delta| > 10")
    s = MegaSolver(task, planner="builtin")
    ex = s.explain(kind="mme")
    fam = s.family
    mce = s.explain(ex.plan)
    try:
        want = brute_force_mme(task, fam, ex.plan, state_limit=100_000)
    except RuntimeError:
        # rover-martian p2, p3: beyond the oracle; the MME is still optimal in every
        # superset (by the built-in planner) and no smaller than the MCE
        from mega_sat.search.astar import solve_optimal

        rest = sorted(set(range(len(task.delta))) - ex.selection)
        for k in range(1 << len(rest)):
            t = fam.specialize(ex.selection | {rest[j] for j in range(len(rest)) if k >> j & 1})
            assert simulate_ground(t, ex.plan).cost == solve_optimal(t).cost
        assert len(mce.explanation) <= len(ex.explanation)
        return
    assert len(ex.explanation) == want
    assert len(mce.explanation) <= want


def _enumerated_mme(task, fam, plan) -> int:
    """The MME size by optimal A* (``solve_optimal``) on every subset of Delta, for tasks
    whose full state spaces are beyond ``brute_force_mme`` (MME's searches share no code
    with it; its OPT calls only propose witnesses)."""
    from mega_sat.search.astar import solve_optimal

    n = len(task.delta)
    good = []
    for mask in range(1 << n):
        t = fam.specialize(i for i in range(n) if mask >> i & 1)
        sim = simulate_ground(t, plan)
        good.append(sim.valid and sim.cost == solve_optimal(t).cost)
    mono = [False] * (1 << n)
    for mask in reversed(range(1 << n)):
        mono[mask] = good[mask] and all(mono[mask | 1 << i] for i in range(n) if not mask >> i & 1)
    return min(bin(m).count("1") for m in range(1 << n) if mono[m])


@pytest.mark.parametrize(
    ("rel", "mce_size", "mme_size"),
    [
        ("blocksworld/delta/7/p1", 2, 2),
        ("blocksworld/delta/7/p2", 3, 3),
        ("barman-bar/delta/7/p1", 1, 1),
        ("barman-bar/delta/7/p2", 1, 2),  # traps among the generated instances
        ("usar-fetch/delta/7/p1", 1, 2),
        ("blocksworld/delta/10/p1", 0, 1),
        ("blocksworld/delta/10/p2", 1, 4),
    ],
)
def test_generated_instances_equal_enumeration(rel, mce_size, mme_size):
    task = load_task_dir(str(ROOT / "domains" / rel))
    s = MegaSolver(task, planner="builtin")
    ex = s.explain(kind="mme")
    assert len(s.explain(ex.plan).explanation) == mce_size
    assert len(ex.explanation) == mme_size == _enumerated_mme(task, s.family, ex.plan)


# ------------------------------------------------------------------ CLI


def run(*args):
    return CliRunner().invoke(main, [str(a) for a in args])


def test_cli_text_and_json_on_the_trap():
    mce = run("explain", "--task", TRAP)
    assert mce.exit_code == 0, mce.output
    assert "Explanation >> (none needed)" in mce.output
    assert "(MME)" not in mce.output
    res = run("explain", "--task", TRAP, "--mme")
    assert res.exit_code == 0, res.output
    lines = res.output.splitlines()
    assert lines[0] == "Plan (4 steps, robot cost 4, human cost after explanation 4):"
    assert "Explanation >> remove-has-initial-state-clear_path p9 p5" in lines
    assert lines[-1].startswith("|E| = 1 (MME); time ") and lines[-1].endswith("exact: yes")
    js = run("explain", "--task", TRAP, "--mme", "--json")
    d = json.loads(js.output)
    assert d["kind"] == "mme"
    assert d["explanation"] == ["remove-has-initial-state-clear_path p9 p5"]
    assert d["exact"] is True and d["robot_cost"] == d["human_cost"] == 4
    assert "kind" not in json.loads(run("explain", "--task", TRAP, "--json").output)


def test_cli_plan_file_and_verify(tmp_path):
    plan = tmp_path / "robot.plan"
    plan.write_text("(move p1 p6)\n(move p6 p7)\n(move p7 p5)\n(take_picture p5)\n")
    res = run("explain", "--task", USAR, "--mme", "--plan", plan, "--verify")
    assert res.exit_code == 0, res.output
    assert "|E| = 3 (MME)" in res.output
    assert "verify: passed" in res.output


def test_cli_refuses_a_plan_not_robot_optimal():
    res = run("explain", "--task", USAR, "--mme", "--plan", EXPLICABLE)
    assert res.exit_code == 2
    lines = [ln for ln in res.output.splitlines() if ln.strip()]
    assert lines == [
        "error: the plan is not optimal in the robot model (it costs 8, the robot optimum is "
        "4): only a robot-optimal plan has an MME"
    ]
    js = run("explain", "--task", USAR, "--mme", "--plan", EXPLICABLE, "--json")
    assert js.exit_code == 2
    assert json.loads(js.stdout)["exit_code"] == 2


def test_verify_covers_the_supersets():
    """``verify`` of an MME re-checks every strict superset with another planner: the MME of
    the trap passes, the MCE passed off as an MME fails on the superset with the new corridor,
    and past the limit the check is listed as skipped."""
    from dataclasses import replace

    task = load_task_dir(str(TRAP))
    s = MegaSolver(task)
    mme = s.explain(kind="mme")
    rep = s.verify(mme, use_val=False)
    assert rep.ok, rep.lines()
    assert rep.lines()[-1].startswith("ok   optimal in every human + E' with E < E' <= Delta")
    fake = replace(mme, explanation=(), selection=frozenset(), kind="mme")
    bad = s.verify(fake, use_val=False)
    assert not bad.ok
    assert bad.lines()[-1] == (
        "FAIL optimal in every human + E' with E < E' <= Delta: with "
        "add-has-initial-state-clear_path p1 p9 also explained: optimum 3; plan: 4"
    )
    from mega_sat.engines.verify import verify_supersets

    skipped = verify_supersets(task, s.family, frozenset(), mme.plan, checker="builtin", limit=2)
    assert skipped == "optimal in every human + E' with E < E' <= Delta: 3 supersets, more than 2"
    assert s.verify(s.explain(), use_val=False).lines()[-1].startswith("ok   optimal in human + E")
