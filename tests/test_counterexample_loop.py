"""The counterexample loop (mega_sat/engines/counterexample_loop.py) against brute force.

The frontier must be the oracle's on random small tasks, and the two facts the loop's
exactness rests on are checked on their own: a counterexample's symbolic run holds in exactly
the models where its plan runs at its cost, and ``uncovered`` finds a model in which no cheap
counterexample runs whenever one exists.
"""

from __future__ import annotations

from itertools import combinations

from helpers.bruteforce import brute_force_frontier, check_witnesses
from helpers.fuzzing import oracle_settings
from helpers.randomtasks import two_model_tasks
from helpers.tradeoff_tasks import tradeoff_tasks
from hypothesis import HealthCheck, assume, given
from hypothesis import strategies as st

from mega_sat.deadline import Deadline
from mega_sat.engines.counterexample_loop import Counterexample, CounterexampleFormula
from mega_sat.engines.sat_loop import sat_frontier
from mega_sat.ground.grounding import ground
from mega_sat.ground.simulate import ground_plan_cost
from mega_sat.options import Options
from mega_sat.pddl.loading import load_task_dir
from mega_sat.sat.oracles import SatOracles
from mega_sat.status import Status

SETTINGS = oracle_settings(
    80, suppress_health_check=[HealthCheck.too_slow, HealthCheck.filter_too_much]
)
ALWAYS = Options(counterexample_loop_updates=1)
TASKS = st.one_of(two_model_tasks(max_delta=6), tradeoff_tasks())


def _pairs(points):
    return [(p.size, p.robot_cost) for p in points]


@SETTINGS
@given(TASKS, st.sampled_from([None, "builtin", "sat"]))
def test_counterexample_frontier_equals_brute_force(task, planner):
    fam = ground(task)
    try:
        c_r, pts, results = brute_force_frontier(task, fam, state_limit=20_000)
    except ValueError:
        return  # no robot plan: the hitting-set loop's tests cover the error
    fr = sat_frontier(task, fam, planner=planner, options=ALWAYS)
    assert fr.robot_optimal_cost == c_r
    assert _pairs(fr.points) == _pairs(pts)
    assert fr.complete
    if fam.min_cost > 0 and fam.n_updates:
        assert fr.stats["loop"] == "counterexamples"
        assert fr.exact
    check_witnesses(task, fam, fr.points, results)
    assert all(results[p.selection].human_cost == p.human_cost for p in fr.points)


def _selections(n):
    return [frozenset(c) for k in range(n + 1) for c in combinations(range(n), k)]


def _agree(formula, sel):
    return [formula.enc.e(i) if i in sel else -formula.enc.e(i) for i in range(formula.n)]


@oracle_settings(80, suppress_health_check=[HealthCheck.too_slow, HealthCheck.filter_too_much])
@given(two_model_tasks(max_delta=5), st.data())
def test_a_counterexample_holds_exactly_where_its_plan_runs(task, data):
    fam = ground(task)
    assume(fam.n_updates and fam.min_cost > 0)
    sel = data.draw(st.sampled_from(_selections(fam.n_updates)))
    with SatOracles(fam) as orc:
        opt = orc.opt(sel)
        assume(opt.status == Status.OPTIMAL)
        formula = CounterexampleFormula(orc, 1, "cadical195")
        try:
            formula.add(Counterexample(opt.plan, opt.cost, sel))
            ((_, v),) = formula.covered
            one_cost = all(
                len({c for _, c in fam.actions[fam.action_index[s]].cost}) == 1 for s in opt.plan
            )
            for other in _selections(fam.n_updates):
                holds = not formula.cover.solve(assumptions=_agree(formula, other) + [-v])
                runs_at = ground_plan_cost(orc.task(other), opt.plan)
                if holds:
                    assert runs_at == opt.cost, (sorted(other), runs_at)
                elif one_cost:
                    assert runs_at is None, (sorted(other), runs_at)
        finally:
            formula.close()


@oracle_settings(60, suppress_health_check=[HealthCheck.too_slow, HealthCheck.filter_too_much])
@given(two_model_tasks(max_delta=5), st.data())
def test_uncovered_finds_a_model_without_a_cheap_counterexample(task, data):
    fam = ground(task)
    assume(fam.n_updates and fam.min_cost > 0)
    sels = _selections(fam.n_updates)
    with SatOracles(fam) as orc:
        formula = CounterexampleFormula(orc, 1, "cadical195")
        try:
            cexs = []
            for sel in data.draw(st.lists(st.sampled_from(sels), max_size=4)):
                opt = orc.opt(sel)
                if opt.status == Status.OPTIMAL:
                    cexs.append(Counterexample(opt.plan, opt.cost, sel))
                    formula.add(cexs[-1])
            k = data.draw(st.integers(0, fam.n_updates))
            below = data.draw(st.integers(0, 12))

            def runs_cheap(c, s):
                return c.cost < below and ground_plan_cost(orc.task(s), c.plan) == c.cost

            def one_cost(c):
                return all(
                    len({v for _, v in fam.actions[fam.action_index[s]].cost}) == 1 for s in c.plan
                )

            got = formula.uncovered(k, below, lambda s, a: s.solve(assumptions=a))
            if got is not None:
                # no cheap counterexample runs there (where a plan has several cost cases the
                # formula may also leave out a model where it runs at another case's cost)
                assert len(got) <= k
                assert not any(runs_cheap(c, got) for c in cexs if one_cost(c))
            else:
                assert all(any(runs_cheap(c, s) for c in cexs) for s in sels if len(s) <= k)
        finally:
            formula.close()


ROVER = "domains/rover-martian/delta/2/p1"


def test_a_horizon_past_the_cap_hands_the_task_to_the_hitting_set_loop():
    task = load_task_dir(ROVER)
    fam = ground(task)
    classic = sat_frontier(task, fam)
    fr = sat_frontier(task, fam, options=Options(counterexample_loop_updates=1, horizon_cap=3))
    assert fr.stats["loop"] == "hitting set"
    assert any("handed over" in n for n in fr.notes)
    assert _pairs(fr.points) == _pairs(classic.points)


def test_the_loop_runs_from_its_number_of_updates_on():
    task = load_task_dir(ROVER)
    fam = ground(task)
    n = fam.n_updates
    on = sat_frontier(task, fam, options=Options(counterexample_loop_updates=n))
    off = sat_frontier(task, fam, options=Options(counterexample_loop_updates=n + 1))
    never = sat_frontier(task, fam, options=Options(counterexample_loop_updates=0))
    assert on.stats["loop"] == "counterexamples"
    assert off.stats["loop"] == never.stats["loop"] == "hitting set"
    assert _pairs(on.points) == _pairs(off.points) == _pairs(never.points)
    assert on.exact and on.complete


def test_the_hitting_set_loops_own_parts_ask_for_that_loop():
    task = load_task_dir(ROVER)
    fam = ground(task)
    for kw in ({"hitting_set": "ilp"}, {"joint": "search"}):
        fr = sat_frontier(task, fam, options=ALWAYS, **kw)
        assert fr.stats["loop"] == "hitting set", kw
    assert sat_frontier(task, fam, options=ALWAYS, joint="sat").stats["loop"] == "counterexamples"


def test_a_time_limit_gives_the_points_so_far_and_a_lower_bound():
    # the whole frontier takes some 20 s on this machine
    task = load_task_dir("domains/rover-martian/delta/10/p3")
    fam = ground(task)
    fr = sat_frontier(task, fam, deadline=Deadline.after(1.0), options=ALWAYS)
    assert fr.stats["loop"] == "counterexamples"
    assert not fr.complete and not fr.exact
    assert fr.next_size_lower_bound is not None
    assert any("time limit" in n for n in fr.notes)
