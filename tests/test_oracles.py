"""OPT and JOINT against explicit-state ground truth on random families and selections."""

from __future__ import annotations

import pytest
from helpers.fuzzing import oracle_settings
from helpers.sat_families import (
    agreeing,
    dijkstra,
    families,
    joint_brute,
    plan_cost,
    selections,
    symmetric_families,
)
from hypothesis import given
from hypothesis import strategies as st

from mega_sat.analysis.monotone import drop_relaxing
from mega_sat.deadline import Deadline
from mega_sat.ground.family import GroundAction, GroundFamily, holds
from mega_sat.options import Options
from mega_sat.sat.oracles import JointResult, OptResult, SatOracles
from mega_sat.status import Status

SETTINGS = oracle_settings(150)


def check_opt(fam: GroundFamily, orc: SatOracles, sel: frozenset[int]) -> OptResult:
    task = fam.specialize(sel)
    r = orc.opt(sel)
    best = dijkstra(task)
    if best is None:
        assert r.status == "unsolvable" and r.exact and r.plan is None
    else:
        assert r.status == "optimal" and r.cost == best
        assert plan_cost(task, r.plan) == best
    return r


@pytest.mark.parametrize(
    "options",
    [
        {},
        {"options": Options(step_first=False)},
        {"symmetry_breaking": False},
        {"unary_max_units": 0},
    ],
    ids=["step-queries", "cost-only", "step-queries-no-symmetry-breaking", "binary-costs"],
)
@SETTINGS
@given(fam=families(), data=st.data())
def test_opt_matches_dijkstra_and_astar(options, fam: GroundFamily, data):
    from mega_sat.search.astar import astar

    with SatOracles(fam, **options) as orc:
        for _ in range(3):
            sel = data.draw(selections(fam.n_updates))
            r = check_opt(fam, orc, sel)
            assert r.exact
            a = astar(fam.specialize(sel), heuristic="hmax")
            assert a.cost == r.cost and (a.status == "unsolvable") == (r.status == "unsolvable")
        rob = orc.robot_optimal()
        assert rob == orc.opt(fam.robot_selection)
        assert orc.stats.opt_vars > 0 and orc.stats.opt_calls >= 1


@SETTINGS
@given(fam=families(), data=st.data())
def test_opt_reachability_proofs_match_dijkstra(fam: GroundFamily, data):
    """OPT tries the reachability proof of unsolvability after its first horizon here: every
    answer still matches Dijkstra (an unsolvable verdict only when there is no plan)."""
    with SatOracles(fam, options=Options(opt_reachability_steps=1)) as orc:
        for _ in range(3):
            check_opt(fam, orc, data.draw(selections(fam.n_updates)))


def test_opt_proves_a_large_model_unsolvable_by_reachability():
    """blocksworld Delta20 p2 with update 18: no relaxation, pair or counting argument sees
    that the goal is unreachable; exhausting the 887,291 reachable states does."""
    from pathlib import Path

    from mega_sat.ground.grounding import ground
    from mega_sat.pddl.loading import load_task_dir

    d = Path(__file__).resolve().parent.parent / "domains" / "blocksworld" / "delta" / "20" / "p2"
    fam = ground(load_task_dir(d))
    with SatOracles(fam, options=Options(opt_reachability_steps=1)) as orc:
        r = orc.opt(frozenset({18}))
        assert r.status == Status.UNSOLVABLE and r.exact and "no reachable state" in r.reason
        assert orc.stats.opt_by_reachability == 1
    # within too few states the check proves nothing: SAT carries on
    from mega_sat.search.vector_search import Reachability

    with SatOracles(fam, options=Options(opt_reachability_nodes=1000)) as orc:
        reach = Reachability(fam.specialize(frozenset({18})))
        assert orc.opt_oracle._reachability(reach, 1000) == Status.LIMIT
        assert orc.stats.opt_by_reachability is None
        assert orc.solving.side_work == 0  # nor does the referee count its states


@SETTINGS
@given(fam=families(), data=st.data())
def test_opt_reachability_alongside_sat_matches_dijkstra(fam: GroundFamily, data):
    """With one-conflict solver chunks and the check from the first conflict on, the
    reachability proof runs between SAT's chunks: every answer still matches Dijkstra."""
    opts = Options(
        first_chunk=1, solve_chunk=1, opt_reachability_conflicts=1, opt_reachability_probe_rate=1
    )
    with SatOracles(fam, options=opts) as orc:
        for _ in range(3):
            check_opt(fam, orc, data.draw(selections(fam.n_updates)))


def test_opt_proves_unsolvable_alongside_a_hard_sat_horizon():
    """usar-fetch Delta30 p2 with updates {19, 20}: every horizon up to 16 steps is UNSAT and
    the 16-step call alone takes tens of seconds; the relevant part of the model has 894
    reachable states, exhausted between the first solver chunks once SAT has spent
    ``opt_reachability_conflicts`` conflicts."""
    from pathlib import Path

    from mega_sat.ground.grounding import ground
    from mega_sat.pddl.loading import load_task_dir

    d = Path(__file__).resolve().parent.parent / "domains" / "usar-fetch" / "delta" / "30" / "p2"
    fam = ground(load_task_dir(d))
    opts = Options(opt_reachability_conflicts=2000)
    with SatOracles(fam, options=opts) as orc:
        r = orc.opt(frozenset({19, 20}))
        assert r.status == Status.UNSOLVABLE and r.exact
        assert "while SAT looked for a plan" in r.reason
        assert orc.stats.opt_by_reachability == 1
        assert orc.solving.conflicts() < 20_000


@SETTINGS
@given(fam=families(min_cost=0), data=st.data())
def test_opt_zero_cost_never_claims_a_false_proof(fam: GroundFamily, data):
    """With zero-cost actions the horizon argument fails: whatever is claimed exact is right,
    and the found plan is always valid with the reported cost."""
    with SatOracles(fam) as orc:
        sel = data.draw(selections(fam.n_updates))
        task = fam.specialize(sel)
        r = orc.opt(sel)
        best = dijkstra(task)
        if r.status == "optimal":
            assert plan_cost(task, r.plan) == r.cost and best is not None and r.cost >= best
            if r.exact:
                assert r.cost == best
        if r.status == "unsolvable":
            assert best is None and r.exact
        if fam.min_cost == 0 and r.status == "optimal" and r.cost > 0 and not r.exact:
            assert "zero-cost" in r.reason


@pytest.mark.parametrize("options", [{}, {"unary_max_units": 0}], ids=["unary", "binary"])
@SETTINGS
@given(fam=families(max_atoms=3, max_actions=5, max_updates=4), data=st.data())
def test_joint_matches_paired_search_and_cores_are_sound(options, fam: GroundFamily, data):
    robot = fam.specialize(fam.robot_selection)
    with SatOracles(fam, **options) as orc:
        for _ in range(2):
            sel = data.draw(selections(fam.n_updates))
            hb = data.draw(st.integers(0, 7))
            rb = data.draw(st.one_of(st.none(), st.integers(0, 7)))
            r = orc.joint(sel, rb, hb)
            assert isinstance(r, JointResult) and r.exact
            best = joint_brute(fam, sel, rb, hb)
            if best is None:
                assert r.status == "infeasible" and r.plan is None and r.core is not None
                assert all(v == (i in sel) for i, v in r.core)  # literals of the selection
                alone = orc.joint_lits(r.core, rb, hb)
                assert alone.status == "infeasible"
                for other in agreeing(r.core, fam.n_updates):
                    assert joint_brute(fam, other, rb, hb) is None
            else:
                assert r.status == "plan" and r.robot_cost == best and r.selection == sel
                assert plan_cost(robot, r.plan) == r.robot_cost
                assert plan_cost(fam.specialize(sel), r.plan) == r.human_cost <= hb


def _chain(n: int) -> GroundFamily:
    """p0 -> p1 -> ... -> pn: the only plan has n steps."""
    acts = tuple(
        GroundAction(
            "step", (str(i),), None, ((i, None),), (), ((i + 1, None),), ((i, None),), (((), 1),)
        )
        for i in range(n)
    )
    return GroundFamily(
        tuple((f"p{i}",) for i in range(n + 1)), 0, acts, ((0, None),), ((n, None),)
    )


def test_horizon_cap_is_reported_not_hidden():
    fam = _chain(8)
    with SatOracles(fam, options=Options(horizon_cap=4)) as orc:
        r = orc.opt(frozenset())
        # the SAT search cannot reach 8 steps; the explicit-search fallback decides exactly
        assert r.status == "optimal" and r.cost == 8 and r.exact
        assert "horizon cap" in r.reason
        # JOINT past the cap: the explicit paired search answers, exactly, and says so
        j = orc.joint(frozenset(), None, 8)
        assert j.exact and j.status == "plan" and j.robot_cost == 8
        assert "horizon cap" in j.reason and "explicit search" in j.reason
        assert orc.stats.joint_by_search == 1
        assert orc.joint(frozenset(), None, 7).core == frozenset()
        # on a partial assignment there is no search: SAT at the cap, marked not exact
        part = orc.joint_lits([], None, 8)
        assert not part.exact and "horizon cap" in part.reason
    with SatOracles(fam, options=Options(horizon_cap=4, fallback_node_limit=2)) as orc:
        r = orc.opt(frozenset())
        assert r.status == Status.LIMIT and not r.exact
    with SatOracles(fam) as orc:
        assert orc.opt(frozenset()).cost == 8
        j = orc.joint(frozenset(), None, 8)
        assert j.status == "plan" and j.exact and j.robot_cost == 8
        assert orc.joint(frozenset(), None, 7).core == frozenset()


def test_horizon_cap_fallback_stops_at_the_deadline():
    """Past the horizon cap OPT falls back to explicit search; with a deadline that search
    gets only the time left, and a search cut short raises (nothing proven, nothing cached)
    instead of answering "unknown" for good.  Twenty-four free switches make the state space
    2^24 times the chain's, too large to exhaust in 0.3 s."""
    import time
    from dataclasses import replace

    from mega_sat.sat.oracles import OracleInterrupted

    n, k = 8, 24
    fam = _chain(n)
    switches = tuple(
        GroundAction(name, (str(i),), None, (), (), add, delete, (((), 1),))
        for i in range(k)
        for name, add, delete in (
            ("on", ((n + 1 + i, None),), ()),
            ("off", (), ((n + 1 + i, None),)),
        )
    )
    fam = replace(
        fam,
        atoms=fam.atoms + tuple((f"q{i}",) for i in range(k)),
        actions=fam.actions + switches,
    )
    with SatOracles(fam, options=Options(horizon_cap=4), operator_counting=False) as orc:
        t0 = time.perf_counter()
        orc.deadline = Deadline(t0 + 0.3)
        with pytest.raises(OracleInterrupted):
            orc.opt(frozenset())
        assert time.perf_counter() - t0 < 2.0
        assert orc.opt_oracle.cached(frozenset()) is None


def test_core_is_minimized():
    """Goal g needs action a, which needs update 0 selected (human side); updates 1..3 are
    irrelevant decoys. Not selecting 0 is the whole core."""
    a = GroundAction("a", (), (0, True), (), (), ((0, None),), (), (((), 1),))
    b = GroundAction(
        "b", (), None, (), (), ((1, None),), (), ((((1, True),), 1), (((1, False),), 2))
    )
    fam = GroundFamily((("g",), ("h",)), 4, (a, b), ((1, (2, True)),), ((0, None),))
    with SatOracles(fam) as orc:
        r = orc.joint(frozenset({3}), None, 5)
        assert r.status == "infeasible" and r.core == frozenset({(0, False)})
        r = orc.joint(frozenset({0, 3}), None, 5)
        assert r.status == "plan" and r.plan == (("a",),) and r.robot_cost == 1


@pytest.mark.parametrize("problem", ["p1", "p2"])
def test_usar_fetch_domain(problem):
    """Smoke test on a real domain: OPT and JOINT agree with explicit search."""
    from pathlib import Path

    from mega_sat.ground.grounding import ground
    from mega_sat.model.task import TwoModelTask
    from mega_sat.pddl.reader import read_model
    from mega_sat.search.astar import astar

    d = Path(__file__).resolve().parent.parent / "domains" / "usar-fetch"
    pdir = d / problem
    if not (pdir / "robot-problem.pddl").exists():
        pytest.skip("domain not present")
    hp = pdir / "human-problem.pddl"
    robot = read_model(d / "robot-domain.pddl", pdir / "robot-problem.pddl")
    human = read_model(d / "human-domain.pddl", hp if hp.exists() else pdir / "robot-problem.pddl")
    fam = ground(TwoModelTask.from_models(robot, human))
    with SatOracles(fam) as orc:
        for sel in (frozenset(), fam.robot_selection):
            r = orc.opt(sel)
            a = astar(fam.specialize(sel), heuristic="lmcut")
            assert r.cost == a.cost and r.exact
            j = orc.joint(sel, None, r.cost)
            if j.status == "plan":
                assert plan_cost(fam.specialize(sel), j.plan) == j.human_cost == r.cost
        assert orc.stats.max_call_time_s < 0.5


@SETTINGS
@given(fam=families(max_atoms=3, max_actions=5, max_updates=4), data=st.data())
def test_joint_hints_and_lower_bounds_do_not_change_answers(fam: GroundFamily, data):
    """Hints (valid or not) and proven lower bounds only save SAT calls: same status, same
    minimal robot cost, a valid plan within the bounds."""
    robot = fam.specialize(fam.robot_selection)
    c_robot = dijkstra(robot)
    with SatOracles(fam) as orc:
        sel = data.draw(selections(fam.n_updates))
        hb = data.draw(st.integers(0, 7))
        rb = data.draw(st.one_of(st.none(), st.integers(0, 7)))
        c_star = dijkstra(fam.specialize(sel))
        best = joint_brute(fam, sel, rb, hb)
        bad = ((("no-such-action",),), (fam.actions[0].step,) * 3, ())
        good = orc.joint(sel, rb, hb)
        hints = [*bad, *([good.plan] if good.plan is not None else [])]
        r = orc.joint(sel, rb, hb, hints=hints, robot_lower_bound=c_robot, human_lower_bound=c_star)
        assert r.exact
        if best is None:
            assert r.status == "infeasible" and r.core is not None
            for other in agreeing(r.core, fam.n_updates):
                assert joint_brute(fam, other, rb, hb) is None
        else:
            assert r.status == "plan" and r.robot_cost == best == good.robot_cost
            assert plan_cost(robot, r.plan) == r.robot_cost
            assert plan_cost(fam.specialize(sel), r.plan) == r.human_cost <= hb


def test_bad_hint_is_ignored_and_good_hint_is_used():
    fam = _chain(4)
    with SatOracles(fam) as orc:
        plan = tuple(("step", str(i)) for i in range(4))
        r = orc.joint(frozenset(), None, 4, hints=[plan[:2], (("step", "9"),), plan[::-1]])
        assert r.status == "plan" and r.plan == plan and r.calls >= 1
        calls = orc.stats.solver_calls
        r = orc.joint(frozenset(), None, 4, hints=[plan], robot_lower_bound=4)
        assert r.status == "plan" and r.plan == plan and r.robot_cost == 4 and r.calls == 0
        assert orc.stats.solver_calls == calls  # the hint met the bound: no SAT call
        r = orc.joint(frozenset(), 3, 4, robot_lower_bound=4)
        assert r.status == "infeasible" and r.core == frozenset() and r.exact


def test_interrupt_and_deadline_leave_oracles_usable():
    import time

    from mega_sat.sat.oracles import OracleInterrupted

    fam = _chain(6)
    with SatOracles(fam) as orc:
        orc.deadline = Deadline(time.perf_counter())
        with pytest.raises(OracleInterrupted):
            orc.joint(frozenset(), None, 6)
        with pytest.raises(OracleInterrupted):  # still past the deadline
            orc.opt(frozenset())
        orc.deadline = None
        assert orc.joint(frozenset(), None, 6).robot_cost == 6
        orc.interrupt()
        with pytest.raises(OracleInterrupted):
            orc.joint(frozenset(), None, 6)
        # below the robot optimum at equal costs: answered without a SAT call
        assert orc.joint(frozenset(), None, 5).core == frozenset()
        assert orc.joint(frozenset(), None, 6).robot_cost == 6
        assert orc.opt(frozenset()).cost == 6
        orc.deadline = Deadline(time.perf_counter() + 60)  # a far deadline changes nothing
        assert orc.joint(frozenset(), None, 6).status == "plan"
        orc.deadline = None


def _add_pigeonhole(orc: SatOracles, n: int = 11, m: int = 10) -> int:
    """Add a pigeonhole formula (``n`` pigeons, ``m`` holes) to the JOINT solver behind a fresh
    guard literal, which is returned: assumed, it makes a solver call hard (9/8 was once
    refuted by CaDiCaL inside a 0.3 s deadline)."""
    top = orc.joint_enc.top
    v = [[top + i * m + j + 1 for j in range(m)] for i in range(n)]
    act = top + n * m + 1
    orc.joint_enc.top += n * m + 1
    s = orc.solving.joint_solver
    for i in range(n):
        s.add_clause([-act, *v[i]])
    for j in range(m):
        for a in range(n):
            for b in range(a + 1, n):
                s.add_clause([-act, -v[a][j], -v[b][j]])
    return act


@pytest.mark.parametrize("solver", ["glucose4", "cadical195"])
def test_deadline_interrupts_a_long_call(solver):
    """A call that would run long is stopped near the deadline (CaDiCaL: after a chunk)."""
    import time

    from mega_sat.sat.oracles import OracleInterrupted

    fam = _chain(3)
    with SatOracles(fam, solver=solver, options=Options(solve_chunk=50)) as orc:
        act = _add_pigeonhole(orc)
        s = orc.solving.joint_solver
        t0 = time.perf_counter()
        orc.deadline = Deadline(t0 + 0.3)
        with pytest.raises(OracleInterrupted):
            orc.solving.solve(s, [act])
        assert time.perf_counter() - t0 < 5
        orc.deadline = None
        # the oracle still answers after an interrupt (the pigeonhole switched off first: left
        # free, its guard may be decided true and the solver would grind on it)
        s.add_clause([-act])
        assert orc.joint(frozenset(), None, 3).robot_cost == 3


def test_cadical_chunks_follow_the_deadline_not_the_chunk_cap():
    """CaDiCaL holds the GIL, so the deadline only acts between conflict chunks; with no
    useful cap on the chunk (``solve_chunk`` huge) the chunks are sized by the measured
    seconds per conflict and the time left, and the call still stops near the deadline (a
    fixed chunk overran ``--timeout`` by 5 s on barman-bar Δ=20 p2)."""
    import time

    from mega_sat.sat.oracles import OracleInterrupted

    with SatOracles(_chain(3), solver="cadical195", options=Options(solve_chunk=10**9)) as orc:
        act = _add_pigeonhole(orc, 12, 11)
        t0 = time.perf_counter()
        orc.deadline = Deadline(t0 + 0.3)
        with pytest.raises(OracleInterrupted):
            orc.solving.solve(orc.solving.joint_solver, [act])
        assert time.perf_counter() - t0 < 1.5
        orc.deadline = None
        orc.solving.joint_solver.add_clause([-act])
        assert orc.joint(frozenset(), None, 3).robot_cost == 3


def test_chunk_sizes_do_not_follow_the_clock_without_a_deadline():
    """Chunk boundaries steer CaDiCaL's search, so without a deadline the chunks of a call
    follow a fixed schedule whatever the measured speed (clock-sized chunks made barman-bar/p3's
    loop take a different path through the models on every run); a near deadline cuts them."""
    import time

    with SatOracles(_chain(3), solver="cadical195") as orc:
        s = orc.solving.opt_solver
        sizes = [orc.solving.chunk(s, i) for i in range(8)]
        assert sizes == [1000, 2000, 3000, 4000, 5000, 5000, 5000, 5000]
        for rate in (1e-7, 1e-3):  # a fast and a slow machine
            orc.solving.rate[id(s)] = rate
            assert [orc.solving.chunk(s, i) for i in range(8)] == sizes
        orc.deadline = Deadline(time.perf_counter() + 0.5)
        assert orc.solving.chunk(s, 4) <= 500  # 1 ms per conflict: at most 0.5 s of work left
        orc.deadline = None


def _same_costs(fam: GroundFamily) -> GroundFamily:
    """``fam`` with every action's cost fixed to its first case (robot costs then dominate)."""
    from dataclasses import replace

    acts = tuple(replace(a, cost=(((), a.cost[0][1]),)) for a in fam.actions)
    return replace(fam, actions=acts)


@SETTINGS
@given(
    fam=families(max_atoms=3, max_actions=5, max_updates=4),
    data=st.data(),
    mode=st.sampled_from([(True, 3000), (True, 0), (False, 3000), (False, 0)]),
)
def test_joint_below_the_human_optimum_under_dominance_has_sound_cores(fam, data, mode):
    """When robot costs dominate and K < c*(E), JOINT is answered by shrinking the full
    assignment (a core, since K < c*(E) is proven): by OPT-style proofs on the human copy alone
    and operator counting, by operator counting alone (no conflicts to spend), or not at all;
    every core must still rule out every agreeing selection."""
    counting, budget = mode
    fam = _same_costs(fam)
    sel = data.draw(selections(fam.n_updates))
    c_star = dijkstra(fam.specialize(sel))
    c_robot = dijkstra(fam.specialize(fam.robot_selection))
    if c_star is None or c_robot is None or c_star <= c_robot:
        return
    rb = data.draw(st.integers(c_robot, c_star - 1))
    hb = data.draw(st.integers(c_star, c_star + 2))
    with SatOracles(
        fam, operator_counting=counting, options=Options(dominance_conflict_budget=budget)
    ) as orc:
        assert orc.joint_oracle.always_dominates
        r = orc.joint(sel, rb, hb, human_lower_bound=c_star)
        assert orc.stats.joint_by_dominance == 1
        assert r.status == "infeasible" and r.exact and joint_brute(fam, sel, rb, hb) is None
        if budget == 0 and not counting:  # no trials: the assignment, less its relaxing values
            full = [(i, i in sel) for i in range(fam.n_updates)]
            assert r.core == drop_relaxing(full, orc.restricting) and r.calls == 0
        for other in agreeing(r.core, fam.n_updates):
            assert joint_brute(fam, other, rb, hb) is None
        assert orc.joint_lits(r.core, rb, hb).status == "infeasible"
        # OPT of every agreeing selection may use the core's lower bound: still exact
        for o in agreeing(r.core, fam.n_updates):
            check_opt(fam, orc, o)
        # a later call whose selection agrees with the core reuses it without SAT
        other = data.draw(st.sampled_from(agreeing(r.core, fam.n_updates)))
        c_other = dijkstra(fam.specialize(other))
        if c_other is not None and c_other > rb:
            again = orc.joint(other, rb, c_other, human_lower_bound=c_other)
            assert again.status == "infeasible" and again.core == r.core and again.calls == 0
            assert orc.stats.joint_core_reused == 1


def test_dominance_core_without_trials_leaves_out_relaxing_values():
    """With no conflicts to spend and no counting, the core of
    "K < c*(E)" is the assignment less its literals at a relaxing value.  Update 1 adds a
    negative precondition to the only producer of the goal, so "update 1 off" relaxes and a
    core never needs it; update 0 (the goal atom initially true) has no direction, since a
    negative precondition tests that atom."""
    a0 = GroundAction("a0", ("o0",), None, (), ((0, (1, True)),), ((0, None),), (), (((), 1),))
    fam = GroundFamily((("p0",),), 2, (a0,), ((0, (0, True)),), ((0, None),))
    sel = frozenset()
    assert dijkstra(fam.specialize(sel)) == 1 and dijkstra(fam.specialize(fam.robot_selection)) == 0
    with SatOracles(
        fam, operator_counting=False, options=Options(dominance_conflict_budget=0)
    ) as orc:
        r = orc.joint(sel, 0, 1, human_lower_bound=1)
        assert r.status == "infeasible" and r.exact and r.calls == 0
        assert r.core == {(0, False)}
        for other in agreeing(r.core, fam.n_updates):
            assert joint_brute(fam, other, 0, 1) is None


@SETTINGS
@given(fam=families(max_atoms=3, max_actions=5, max_updates=4), data=st.data())
def test_plan_within_finds_a_plan_iff_one_exists_and_keeps_sound_cost_cores(fam, data):
    """``plan_within`` (no budget) returns a valid plan within the bound exactly when the
    model has one; a "none" it proves is kept as a cost core that every agreeing model obeys."""
    fam = _reachable_robot_goal(fam, data)
    sel = data.draw(selections(fam.n_updates))
    task = fam.specialize(sel)
    best = dijkstra(task)
    bound = data.draw(st.integers(0, 6))
    with SatOracles(fam) as orc:
        got = orc.plan_within(sel, bound, None)
        if best is None or best > bound:
            assert got is None
            assert len(orc.cost_cores) == 1 and orc.cost_cores[0][0] == bound
            for other in agreeing(orc.cost_cores[0][1], fam.n_updates):
                c = dijkstra(fam.specialize(other))
                assert c is None or c > bound
        else:
            plan, cost = got
            assert plan_cost(task, plan) == cost and best <= cost <= bound
            assert orc.cost_cores == []


def _cost_updates(fam: GroundFamily, data) -> GroundFamily:
    """``fam`` with some actions' costs under an update that makes them cheaper, dearer or
    no different for the human than for the robot (random cost cases rarely differ so)."""
    from dataclasses import replace

    if fam.n_updates == 0:
        return fam
    acts = []
    for a in fam.actions:
        if data.draw(st.booleans()):
            i = data.draw(st.integers(0, fam.n_updates - 1))
            base = data.draw(st.integers(1, 3))
            other = max(1, base + data.draw(st.integers(-1, 2)))
            robot_has = i in fam.robot_selection
            a = replace(a, cost=((((i, robot_has),), base), (((i, not robot_has),), other)))
        acts.append(a)
    return replace(fam, actions=tuple(acts))


def _reachable_robot_goal(fam: GroundFamily, data) -> GroundFamily:
    """``fam`` with an unguarded goal: the atoms of a state the robot model reaches, so that
    most drawn families have a robot plan (random goals mostly have none)."""
    from dataclasses import replace

    from helpers.sat_families import _succ

    task = fam.specialize(fam.robot_selection)
    seen, todo = {frozenset(task.init)}, [frozenset(task.init)]
    while todo:
        for _, s2 in _succ(task, todo.pop()):
            if s2 not in seen:
                seen.add(s2)
                todo.append(s2)
    others = sorted((s for s in seen if not s <= task.init), key=sorted)
    if not others:
        return fam
    target = data.draw(st.sampled_from(others))
    return replace(fam, goal=tuple((i, None) for i in sorted(target)))


@SETTINGS
@given(fam=families(max_atoms=3, max_actions=5, max_updates=4), data=st.data())
def test_joint_below_the_robot_optimum_under_human_dominance_has_sound_cores(fam, data):
    """A human bound below the robot optimum, where no action of the robot model costs the
    human less than the robot, is infeasible without SAT, with a core of cost literals under
    which that dominance holds in every agreeing selection (so none has a joint plan within
    the bound either); the shortcut is taken exactly when the selection has that dominance."""
    fam = _reachable_robot_goal(_cost_updates(fam, data), data)
    sel = data.draw(selections(fam.n_updates))
    c_robot = dijkstra(fam.specialize(fam.robot_selection))
    if c_robot is None or c_robot == 0:
        return
    hb = data.draw(st.integers(0, c_robot + 1))
    robot = fam.robot_selection
    robot_actions = [a for a in fam.actions if a.exists is None or holds(a.exists, robot)]

    def dominated_in(o: frozenset[int]) -> bool:
        return all(a.cost_in(o) >= a.cost_in(robot) for a in robot_actions)

    dominated = dominated_in(sel) and hb < c_robot
    with SatOracles(fam) as orc:
        r = orc.joint(sel, None, hb, robot_lower_bound=c_robot)
        assert (orc.stats.joint_by_human_dominance == 1) == dominated
        assert r.exact and (r.status == "infeasible") == (joint_brute(fam, sel, None, hb) is None)
        if dominated:
            assert r.status == "infeasible"
            assert r.calls == 0
            cost_updates = {i for a in fam.actions for g, _ in a.cost for i, _ in g}
            assert {i for i, _ in r.core} <= cost_updates
            assert all(dominated_in(o) for o in agreeing(r.core, fam.n_updates))
        if r.status == "infeasible":
            for other in agreeing(r.core, fam.n_updates):
                assert joint_brute(fam, other, None, hb) is None


def test_joint_by_dominance_on_barman():
    """barman-bar/p1: the human model restricts the robot's at equal costs; below the human
    optimum JOINT needs no robot copy, and its core alone is infeasible in the full JOINT."""
    from pathlib import Path

    from mega_sat.ground.grounding import ground
    from mega_sat.pddl.loading import load_task, resolve_task_dir

    d = Path(__file__).resolve().parent.parent / "domains" / "barman-bar" / "p1"
    fam = ground(load_task(**resolve_task_dir(d)))
    with SatOracles(fam) as orc:
        c = orc.opt(frozenset()).cost
        r = orc.joint(frozenset(), c - 1, c, human_lower_bound=c)
        assert r.status == "infeasible" and r.core and orc.stats.joint_by_dominance == 1
        assert orc.joint_lits(r.core, c - 1, c).status == "infeasible"
        assert orc.joint(frozenset(), c - 1, c).status == "infeasible"  # the two-copy answer


@pytest.mark.parametrize("partial_order", [False, True], ids=["lex", "lex+por"])
@SETTINGS
@given(fam=symmetric_families(max_atoms=3, max_actions=3, max_updates=3), data=st.data())
def test_symmetry_breaking_keeps_opt_and_joint_exact(partial_order, fam: GroundFamily, data):
    """Families with two interchangeable objects: the lex-leader clauses of the object swap
    (alone, and together with partial-order reduction) change no OPT cost, no JOINT answer,
    and cores stay sound."""
    from mega_sat.sat.symmetry import object_swaps

    assert [(s.a, s.b) for s in object_swaps(fam)] == [("oa", "ob")]
    with SatOracles(fam, options=Options(partial_order=partial_order)) as orc:
        assert orc.opt_enc.swaps
        sel = data.draw(selections(fam.n_updates))
        check_opt(fam, orc, sel)
        hb = data.draw(st.integers(0, 7))
        rb = data.draw(st.one_of(st.none(), st.integers(0, 7)))
        r = orc.joint(sel, rb, hb)
        best = joint_brute(fam, sel, rb, hb)
        if best is None:
            assert r.status == "infeasible"
            for other in agreeing(r.core, fam.n_updates):
                assert joint_brute(fam, other, rb, hb) is None
        else:
            assert r.status == "plan" and r.robot_cost == best


@SETTINGS
@given(fam=families(), data=st.data())
def test_opt_with_the_exact_extra_cost_horizon_stays_exact(fam: GroundFamily, data):
    """``opt_probe_budget=0`` sends every final proof through the explicit lower bound on the
    cost above ``N * c_min`` (a shorter horizon); costs must still be the optimum."""
    with SatOracles(fam, options=Options(opt_probe_budget=0)) as orc:
        for _ in range(3):
            r = check_opt(fam, orc, data.draw(selections(fam.n_updates)))
            if r.status == "optimal" and r.cost and fam.min_cost > 0:
                assert r.exact


def test_joint_by_dominance_cores_from_operator_counting_on_rover():
    """rover-martian/p3 with no conflicts to spend: the core below the human optimum is shrunk
    by operator counting alone, and every model agreeing with it has no plan within K."""
    from pathlib import Path

    from mega_sat.ground.grounding import ground
    from mega_sat.pddl.loading import load_task, resolve_task_dir
    from mega_sat.search.astar import astar

    d = Path(__file__).resolve().parent.parent / "domains" / "rover-martian" / "p3"
    fam = ground(load_task(**resolve_task_dir(d)))
    with SatOracles(fam, options=Options(dominance_conflict_budget=0)) as orc:
        c = orc.opt(frozenset()).cost
        r = orc.joint(frozenset(), c - 1, c, human_lower_bound=c)
        assert r.status == "infeasible" and r.exact and r.calls == 0
        assert len(r.core) < fam.n_updates and orc.stats.counting_calls > 1
        for other in agreeing(r.core, fam.n_updates):
            best = astar(fam.specialize(other), heuristic="blind")
            assert best.status == "optimal" and best.cost > c - 1


def test_lowered_cost_search_with_a_plan_runs_only_while_it_shortens_horizons():
    """barman-bar/p3's human model: the search lifts the extra cost from 2 to 7, so the proof
    runs 5 steps shorter and the steps are counted.  With a plan in hand, searches that
    removed fewer than two steps each stop; without one they go on (their plan is the
    first upper bound); mostly running out of expansions stops them either way."""
    from pathlib import Path

    from mega_sat.ground.grounding import ground
    from mega_sat.pddl.loading import load_task, resolve_task_dir

    d = Path(__file__).resolve().parent.parent / "domains" / "barman-bar" / "p3"
    fam = ground(load_task(**resolve_task_dir(d)))
    with SatOracles(fam) as orc:
        task = orc.task(frozenset())
        assert orc.opt_oracle.search_first(task, True) and orc.opt_oracle.search_first(task, False)
        r = orc.opt(frozenset())
        assert r.status == "optimal" and r.cost == 31 and r.exact
        assert orc.stats.search_hits == 1
        assert orc.stats.search_steps_saved == 5
        orc.opt_oracle.searches_hit, orc.opt_oracle.search_steps_saved = 6, 11
        assert not orc.opt_oracle.search_first(task, True) and orc.opt_oracle.search_first(
            task, False
        )
        orc.opt_oracle.search_steps_saved = 12
        assert orc.opt_oracle.search_first(task, True)
        orc.opt_oracle.searches_missed = 7
        assert not orc.opt_oracle.search_first(task, True) and not orc.opt_oracle.search_first(
            task, False
        )


@pytest.mark.parametrize("problem", ["rover-martian/p1", "barman-bar/p1"])
def test_step_queries_keep_opt_exact_on_shipped_problems(problem):
    """OPT with step queries (the default) against OPT without them on every model with
    |E| <= 3, and against A*/LM-cut on those with |E| <= 2: same answers.  Both new paths
    are taken: a step query that finds a shorter plan (rover-martian/p1 {0, 1, 4}), and a
    cost query that starts from a step bound proven by SAT (barman-bar/p1)."""
    import itertools
    from pathlib import Path

    from mega_sat.ground.grounding import ground
    from mega_sat.pddl.loading import load_task, resolve_task_dir
    from mega_sat.search.astar import astar

    d = Path(__file__).resolve().parent.parent / "domains" / problem
    fam = ground(load_task(**resolve_task_dir(d)))
    n = fam.n_updates
    sels = [frozenset(c) for r in range(4) for c in itertools.combinations(range(n), r)]
    found_shorter = cost_after_bound = 0
    with SatOracles(fam) as new, SatOracles(fam, options=Options(step_first=False)) as old:
        for sel in sels:
            queries = new.stats.step_queries or 0
            bounds = new.stats.step_bounds or 0
            r = new.opt(sel)
            queries = (new.stats.step_queries or 0) - queries
            bounds = (new.stats.step_bounds or 0) - bounds
            found_shorter += queries > bounds
            cost_after_bound += bounds > 0 and r.reason == "proven by SAT"
            o = old.opt(sel)
            assert (r.status, r.cost, r.exact) == (o.status, o.cost, o.exact), sorted(sel)
            if len(sel) <= 2:
                a = astar(fam.specialize(sel), heuristic="lmcut")
                assert r.cost == a.cost, sorted(sel)
        assert old.stats.step_queries is None
    assert found_shorter if problem.startswith("rover") else cost_after_bound


def test_observer_sees_every_call_with_its_costs_and_may_limit_it():
    """The observer hook: ``begin`` before and ``end`` after every OPT and JOINT call (also one
    that raises), with what was asked, the answer, conflicts, the largest horizon asked and the
    work seconds; a deadline returned by ``begin`` limits that call only."""
    import time

    from mega_sat.sat.observer import OracleCall
    from mega_sat.sat.oracles import OracleInterrupted

    class Recorder:
        def __init__(self):
            self.begun: list[str] = []
            self.ended: list[OracleCall] = []
            self.limit: Deadline | None = None

        def begin(self, call: OracleCall) -> Deadline | None:
            assert call.result is None and call.error is None
            self.begun.append(call.kind)
            return self.limit

        def end(self, call: OracleCall) -> None:
            self.ended.append(call)

    rec = Recorder()
    with SatOracles(_chain(3), observer=rec) as orc:
        first = orc.opt(frozenset())
        assert orc.opt(frozenset()) is first
        joint = orc.joint(frozenset(), None, 3)
        part = orc.joint_lits([], None, 3)
        assert rec.begun == ["opt", "opt", "joint", "joint"]
        o1, o2, j, p = rec.ended
        assert o1.result is first and not o1.cached and o2.cached and o2.result is first
        assert o1.selection == frozenset() and o1.seconds >= 0 and o1.error is None
        assert j.result is joint and (j.robot_bound, j.human_bound) == (None, 3)
        assert j.max_horizon_asked == joint.horizon == 3 and j.conflicts is not None
        assert p.selection is None and p.lits == () and p.result is part
        assert min(c.solve_s for c in rec.ended) >= 0 and j.grow_s >= 0
        # a per-call deadline already passed: the call raises, and end() still sees it
        rec.limit = Deadline(time.perf_counter())
        act = _add_pigeonhole(orc)
        with pytest.raises(OracleInterrupted):
            orc.joint_lits([], None, 3)  # any SAT call past the deadline raises
        assert isinstance(rec.ended[-1].error, OracleInterrupted)
        assert rec.ended[-1].result is None
        # the run's own deadline is untouched: without the per-call limit the oracles answer
        rec.limit = None
        assert orc.deadline.limited is False
        orc.solving.joint_solver.add_clause([-act])
        assert orc.joint(frozenset(), None, 3).robot_cost == 3


def test_stats_as_dict_reports_the_used_counters_only():
    """``OracleStats.as_dict`` gives the ``sat_*`` keys of the engine's JSON: the fixed
    counters always, the others once their work happened, in the order it first happened."""
    from mega_sat.sat.stats import OracleStats

    st = OracleStats()
    keys = list(st.as_dict())
    assert keys[:3] == ["sat_opt_calls", "sat_joint_calls", "sat_solver_calls"]
    assert "sat_step_queries" not in keys and keys[-1] == "sat_joint_horizon"
    st.joint_by_search = 1
    st.step_queries = 0
    st.joint_by_search = 2
    st.opt_calls = 3
    got = st.as_dict()
    assert list(got)[-2:] == ["sat_joint_by_search", "sat_step_queries"]
    assert got["sat_step_queries"] == 0 and got["sat_joint_by_search"] == 2
    assert got["sat_opt_calls"] == 3 and len(got) == len(keys) + 2


def test_dominance_cores_do_not_depend_on_the_clock(monkeypatch):
    """usar-fetch Delta10 p2 shrinks its dominance cores by SAT trials and operator counting,
    whichever has spent less *work* per settled trial: with every SAT trial made 50 ms
    slower, the loop shrinks the same cores (by seconds it tried counting 10 times, not 2)."""
    import time
    from pathlib import Path

    from mega_sat import api
    from mega_sat.pddl.loading import load_task_dir
    from mega_sat.sat.cores import CoreShrinker

    d = Path(__file__).resolve().parent.parent / "domains" / "usar-fetch" / "delta" / "10" / "p2"
    task = load_task_dir(d)
    keys = ("core_min_calls", "counting_calls", "learned_literals", "iterations")

    def run():
        fr = api.MegaSolver(task).frontier()
        stats = {k: v for k, v in fr.stats.items() if k.endswith(keys)}
        return [(p.explanation, p.plan) for p in fr.points], stats

    fast = run()
    real = CoreShrinker._trial

    def slow(self, *args, **kwargs):
        time.sleep(0.05)
        return real(self, *args, **kwargs)

    monkeypatch.setattr(CoreShrinker, "_trial", slow)
    slowed = run()
    assert slowed == fast
    assert fast[1]["sat_counting_calls"] >= 1 and fast[1]["sat_core_min_calls"] >= 1
