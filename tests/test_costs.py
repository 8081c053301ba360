"""Action costs of any size: costs up to 10^12 never hang, memory does not grow with them, and
the answers stay exact.

The SAT encoding counts costs in unary while they are small and in binary above
``UNARY_MAX_UNITS`` (``encodings/sequential.md``); these tests run the binary form against
explicit-state search on random families and the whole engine against the brute-force oracle.
Every test that could hang or run out of memory runs under a time and an address-space limit,
so a regression fails instead of taking the machine down (in-process, a C extension that runs
out of address space aborts the test run, which fails it as well).
"""

from __future__ import annotations

import contextlib
import heapq
import itertools
import json
import resource
import signal
import subprocess
import sys
import time
from dataclasses import replace

import pytest
from helpers.fuzzing import oracle_settings
from helpers.sat_families import check_bounded_answer, dijkstra, families, plan_cost, selections
from hypothesis import given
from hypothesis import strategies as st
from pysat.solvers import Solver
from test_sat_encoding import cheapest_within

from mega_sat.ground.family import GroundAction, GroundFamily
from mega_sat.sat.encoding import HUMAN, ROBOT, UNARY_MAX_UNITS, FamilyEncoding
from mega_sat.sat.oracles import SatOracles

SETTINGS = oracle_settings(60)
LARGE = [1000, 10**5, 10**12]
GIB = 1 << 30


@contextlib.contextmanager
def bounded(seconds: int, extra_bytes: int = 2 * GIB):
    """Fail (instead of hanging or swapping) past ``seconds`` or ``extra_bytes`` of address
    space beyond what the test process already has."""

    def alarm(*_):
        raise TimeoutError(f"took more than {seconds} s")

    with open("/proc/self/statm") as f:
        in_use = int(f.read().split()[0]) * resource.getpagesize()
    soft, hard = resource.getrlimit(resource.RLIMIT_AS)
    limit = in_use + extra_bytes
    resource.setrlimit(resource.RLIMIT_AS, (limit if hard < 0 else min(limit, hard), hard))
    old = signal.signal(signal.SIGALRM, alarm)
    signal.alarm(seconds)
    try:
        yield
    finally:
        signal.alarm(0)
        signal.signal(signal.SIGALRM, old)
        resource.setrlimit(resource.RLIMIT_AS, (soft, hard))


@st.composite
def large_cost_families(draw, **kw) -> GroundFamily:
    """A random family (``sat_families.families``) with every cost case redrawn: small values,
    values near a large scale, and anything in between, so that sums carry across bits."""
    fam = draw(families(**kw))
    scale = draw(st.sampled_from(LARGE))
    value = st.one_of(
        st.integers(1, 3), st.integers(scale - 3, scale + 3), st.integers(1, 2 * scale)
    )
    acts = tuple(
        replace(a, cost=tuple((guards, draw(value)) for guards, _ in a.cost)) for a in fam.actions
    )
    return replace(fam, actions=acts)


def joint_pareto(
    fam: GroundFamily, sel: frozenset[int], robot_bound: int | None, human_bound: int
) -> int | None:
    """Minimum robot cost of a plan valid in the robot model and in ``human + sel`` within both
    bounds (None: none), by search over paired states with a Pareto set of (robot cost, human
    cost) labels each: unlike ``sat_families.joint_brute`` its states do not carry the human
    cost, so large bounds do not blow it up.  Positive costs: the first goal label popped is
    the answer."""
    rt, ht = fam.specialize(fam.robot_selection), fam.specialize(sel)
    r_by = {a.index: a for a in rt.actions}
    h_by = {a.index: a for a in ht.actions}
    common = sorted(set(r_by) & set(h_by))
    start = (frozenset(rt.init), frozenset(ht.init))
    labels: dict[tuple, list[tuple[int, int]]] = {start: [(0, 0)]}
    heap = [(0, 0, 0, start)]
    tie = itertools.count()
    while heap:
        rc, hc, _, node = heapq.heappop(heap)
        if (rc, hc) not in labels[node]:
            continue  # dominated since it was pushed
        rs, hs = node
        if rt.goal <= rs and ht.goal <= hs:
            return rc
        for j in common:
            ra, ha = r_by[j], h_by[j]
            if not (ra.pre <= rs and not ra.negpre & rs and ha.pre <= hs and not ha.negpre & hs):
                continue
            rc2, hc2 = rc + ra.cost, hc + ha.cost
            if hc2 > human_bound or (robot_bound is not None and rc2 > robot_bound):
                continue
            n2 = ((rs - ra.delete) | ra.add, (hs - ha.delete) | ha.add)
            old = labels.setdefault(n2, [])
            if any(r <= rc2 and h <= hc2 for r, h in old):
                continue
            old[:] = [(r, h) for r, h in old if not (rc2 <= r and hc2 <= h)] + [(rc2, hc2)]
            heapq.heappush(heap, (rc2, hc2, next(tie), n2))
    return None


# ------------------------------------------------------------------------ the encoding alone
def _family(costs: list[int], jump: int | None = None) -> GroundFamily:
    """p0 -> p1 -> ... -> pn, one action per step with the given costs, and a shortcut
    p0 -> pn costing ``jump`` (default: the sum plus one)."""
    n = len(costs)
    jump = sum(costs) + 1 if jump is None else jump
    acts = [
        GroundAction(f"step{i}", (), None, ((i, None),), (), ((i + 1, None),), ((i, None),),
                     (((), c),))
        for i, c in enumerate(costs)
    ]  # fmt: skip
    acts.append(
        GroundAction("jump", (), None, ((0, None),), (), ((n, None),), ((0, None),),
                     (((), jump),))
    )  # fmt: skip
    return GroundFamily(
        tuple((f"p{i}",) for i in range(n + 1)), 0, tuple(acts), ((0, None),), ((n, None),)
    )


def test_threshold_chooses_unary_or_binary():
    small = _family([1, UNARY_MAX_UNITS - 2])  # the shortcut costs UNARY_MAX_UNITS units
    enc = FamilyEncoding(small, lambda c: None)
    assert not enc.binary and enc.cost_bits == 0 and enc.max_units == UNARY_MAX_UNITS
    big = _family([1, UNARY_MAX_UNITS - 1])
    enc = FamilyEncoding(big, lambda c: None)
    assert enc.binary and enc.cost_bits == (UNARY_MAX_UNITS + 1).bit_length()
    forced = FamilyEncoding(small, lambda c: None, unary_max_units=0)
    assert forced.binary


def test_encoding_size_does_not_grow_with_the_cost_values():
    """Same steps and bounds, costs 10^3 and 10^12 times larger: the formula grows with the
    bit length only (40 bits against 10), not with the values."""
    sizes = []
    with bounded(60):
        for scale in (1000, 10**12):
            fam = _family([scale, 3 * scale + 1, 7])
            clauses: list[list[int]] = []
            enc = FamilyEncoding(fam, clauses.append)
            for bound in (scale, 2 * scale, 4 * scale + 7):
                enc.cost_assumptions(HUMAN, bound, 3)
            enc.extend(10)
            sizes.append((enc.size().variables, len(clauses)))
    (v1, c1), (v2, c2) = sizes
    assert v2 < 6 * v1 and c2 < 6 * c1 and c2 < 20_000


@pytest.mark.parametrize("scale", LARGE)
def test_cost_bounds_are_exact_at_every_value(scale):
    """Every bound from just below to just above the cheapest plan's cost, in both copies."""
    costs = [scale + 1, 2 * scale - 1, 3]
    fam = _family(costs)
    total = sum(costs)
    with bounded(60), Solver(name="cadical195") as s:
        enc = FamilyEncoding(fam, s.add_clause, copies=(HUMAN, ROBOT))
        for h in (1, 3, 4):
            best = cheapest_within(fam.specialize(frozenset()), h)
            assert best == (total if h >= 3 else total + 1)
            for bound in (best - 2, best - 1, best, best + 1, 3 * best):
                for copy in (HUMAN, ROBOT):
                    lits = enc.goal_assumptions(h) + enc.cost_assumptions(copy, bound, h)
                    assert s.solve(assumptions=lits) == (bound >= best), (h, bound, copy)


@SETTINGS
@given(fam=large_cost_families(min_cost=1), data=st.data())
def test_binary_bounds_match_bounded_search(fam: GroundFamily, data):
    """SAT at horizon h with cost <= B iff a plan of <= h steps and cost <= B exists."""
    with bounded(60), Solver(name="cadical195") as solver:
        enc = FamilyEncoding(fam, solver.add_clause)
        for _ in range(3):
            sel = data.draw(selections(fam.n_updates))
            task = fam.specialize(sel)
            h = data.draw(st.integers(0, 4))
            best = cheapest_within(task, h)
            near = [] if best is None else [b for b in (best - 1, best, best + 1) if b >= 0]
            bound = data.draw(st.sampled_from([None, 0, *near, 10**13]))
            lits = enc.selection_assumptions(sel) + enc.goal_assumptions(h)
            lits += enc.cost_assumptions(HUMAN, bound, h)
            check_bounded_answer(solver, enc, task, lits, h, best, bound)


# -------------------------------------------------------------------------------- oracles
@SETTINGS
@given(fam=large_cost_families(min_cost=1), data=st.data())
def test_opt_with_large_costs_matches_astar(fam: GroundFamily, data):
    from mega_sat.search.astar import astar

    with bounded(120), SatOracles(fam) as orc:
        for _ in range(3):
            sel = data.draw(selections(fam.n_updates))
            task = fam.specialize(sel)
            r = orc.opt(sel)
            a = astar(task, heuristic="hmax")
            assert r.exact, r.reason
            assert r.cost == a.cost == dijkstra(task)
            assert (r.status == "unsolvable") == (a.status == "unsolvable")
            if r.plan is not None:
                assert plan_cost(task, r.plan) == r.cost


def _there_and_back(n: int, jump: int) -> GroundFamily:
    """Walk p0 -> ... -> pn (marking ``seen`` on arrival) and back to p0, 2n steps of cost 1,
    or mark ``seen`` from p0 in one step costing ``jump``.  The delete relaxation sees only
    the way there, so LM-cut is about n: the known plans do not settle the optimum."""
    seen = n + 1
    acts = []
    for i in range(n):
        add = ((i + 1, None), (seen, None)) if i == n - 1 else ((i + 1, None),)
        acts.append(
            GroundAction(f"fwd{i}", (), None, ((i, None),), (), add, ((i, None),), (((), 1),))
        )
        acts.append(
            GroundAction(f"back{i}", (), None, ((i + 1, None),), (), ((i, None),),
                         ((i + 1, None),), (((), 1),))
        )  # fmt: skip
    acts.append(
        GroundAction("jump", (), None, ((0, None),), (), ((seen, None),), (), (((), jump),))
    )
    atoms = tuple((f"p{i}",) for i in range(n + 1)) + (("seen",),)
    return GroundFamily(atoms, 0, tuple(acts), ((0, None),), ((0, None), (seen, None)))


def test_opt_and_joint_past_the_horizon_cap_are_answered_by_search():
    """Optimum 202 (101 steps there and back) against one step costing 10^12: proving "no plan
    of cost <= 201" would take 201 steps, above the cap of 200, and JOINT's human bound of
    10^12 would take 10^12.  Both are answered by explicit search, exactly, and say so."""
    fam = _there_and_back(101, 10**12)
    with bounded(120), SatOracles(fam, operator_counting=False) as orc:
        r = orc.opt(frozenset())
        assert r.status == "optimal" and r.cost == 202 and r.exact, r.reason
        assert "horizon cap" in r.reason and "explicit-state search" in r.reason
        assert orc.stats.opt_by_search == 1
        j = orc.joint(frozenset(), None, 10**12)
        assert j.exact and j.status == "plan" and j.robot_cost == 202
        assert "horizon cap" in j.reason and orc.stats.joint_by_search == 1


def test_joint_past_the_horizon_cap_leaves_a_sized_call_to_its_caller():
    """A JOINT call given ``max_action_steps`` comes from a caller with its own explicit
    search and Fast Downward hand-over (the sat engine's loop): past the cap it is left
    undecided, as past the size limit, instead of searching in the oracle without FD."""
    fam = _there_and_back(101, 10**12)
    with bounded(120), SatOracles(fam, operator_counting=False) as orc:
        j = orc.joint(frozenset(), None, 10**12, max_action_steps=12_000)
        assert j.status == "limit" and not j.exact and not j.status.decided
        assert "horizon cap" in j.reason and not orc.stats.joint_by_search
        assert orc.stats.solver_calls == 0  # no SAT call at the capped horizon either


@SETTINGS
@given(fam=large_cost_families(max_atoms=3, max_actions=5, max_updates=4), data=st.data())
def test_joint_with_large_costs_matches_paired_search(fam: GroundFamily, data):
    robot = fam.specialize(fam.robot_selection)
    with bounded(120), SatOracles(fam) as orc:
        for _ in range(2):
            sel = data.draw(selections(fam.n_updates))
            opt = orc.opt(sel)
            hb = opt.cost if opt.cost is not None else data.draw(st.integers(0, 10**12))
            rb = data.draw(st.one_of(st.none(), st.integers(0, 4 * 10**12)))
            r = orc.joint(sel, rb, hb, hints=(opt.plan,) if opt.plan else ())
            best = joint_pareto(fam, sel, rb, hb)
            assert r.exact, r.reason
            if best is None:
                assert r.status == "infeasible"
            else:
                assert r.status == "plan" and r.robot_cost == best
                assert plan_cost(robot, r.plan) == r.robot_cost
                assert plan_cost(fam.specialize(sel), r.plan) == r.human_cost <= hb


@SETTINGS
@given(fam=families(max_atoms=3, max_actions=5, max_updates=4), data=st.data())
def test_ground_truth_pareto_search_agrees_with_joint_brute(fam: GroundFamily, data):
    """The ground truth of the JOINT test against ``sat_families.joint_brute`` where both are
    cheap (a check of the test's own oracle: it passes on any version of the solver)."""
    from helpers.sat_families import joint_brute

    sel = data.draw(selections(fam.n_updates))
    hb = data.draw(st.integers(0, 7))
    rb = data.draw(st.one_of(st.none(), st.integers(0, 7)))
    assert joint_pareto(fam, sel, rb, hb) == joint_brute(fam, sel, rb, hb)


@pytest.mark.parametrize("scale", LARGE)
def test_wcnf_export_weighs_binary_cost_bits(scale, tmp_path):
    """The exported MaxSAT formula's optimum is the optimal cost, with soft clauses weighted
    by the bits they stand for, and the horizon is capped and reported as such."""
    from pysat.examples.rc2 import RC2
    from pysat.formula import WCNF

    from mega_sat.sat.cnf_export import export_opt

    costs = [scale + 1, 2 * scale - 1, 3]
    fam = _family(costs)  # optimum: the chain, sum(costs); the jump costs one more
    with bounded(60):
        paths = export_opt(fam, frozenset(), sum(costs) + 5, tmp_path)
        with RC2(WCNF(from_file=str(paths["wcnf"]))) as rc2:
            assert rc2.compute() is not None and rc2.cost == sum(costs)
    meta = json.loads(paths["vars"].read_text())
    assert meta["cost_bits"] > 0 and meta["horizon"] == 200 and not meta["exact"]
    assert "w[human][0][0]" in meta["variables"].values()


def test_operator_counting_bound_stays_below_costs_beyond_the_lp_file_precision():
    """PuLP hands CBC the costs with 13 significant digits: 10^13 + 3 and 10^13 + 1 both
    become 10^13, CBC may count the dearer action, and its cost is then a "bound" above the
    optimum.  Scaled costs keep the bound below it."""
    from mega_sat.analysis.operator_counting import operator_counting_bound
    from mega_sat.ground.family import GroundTask, StripsAction

    for costs in ([10**13 + 3, 10**13 + 1], [10**15 + 7, 10**15 + 1, 10**15 + 4]):
        acts = tuple(
            StripsAction(i, f"a{i}", (), frozenset(), frozenset(), frozenset({0}), frozenset(), c)
            for i, c in enumerate(costs)
        )
        task = GroundTask((("g",),), acts, frozenset(), frozenset({0}))
        bound = operator_counting_bound(task)
        assert bound is not None and bound <= min(costs)


# ---------------------------------------------------------------------------- the engine
DOMAIN = """(define (domain usar-fetch)
  (:requirements :strips :typing :action-costs)
  (:types waypoint)
  (:predicates (robot_at ?l - waypoint) (clear_path ?from - waypoint ?to - waypoint)
               (clearable ?from - waypoint ?to - waypoint) (picture_taken ?l - waypoint))
  (:functions (total-cost) - number)
  (:action move
    :parameters (?from - waypoint ?to - waypoint)
    :precondition (and (robot_at ?from) (clear_path ?from ?to))
    :effect (and (not (robot_at ?from)) (robot_at ?to) (increase (total-cost) MOVE)))
  (:action clear_passage
    :parameters (?from - waypoint ?to - waypoint)
    :precondition (and (robot_at ?from) (clearable ?from ?to))
    :effect (and (not (clearable ?from ?to)) (clear_path ?from ?to)
                 (increase (total-cost) CLEAR)))
  (:action take_picture
    :parameters (?loc - waypoint)
    :precondition (and (robot_at ?loc))
    :effect (and (picture_taken ?loc) (increase (total-cost) PICTURE))))
"""
PROBLEM = """(define (problem usar-p1) (:domain usar-fetch)
  (:objects p1 p2 p3 p4 p5 p6 p7 p8 - waypoint)
  (:init (= (total-cost) 0) (robot_at p1)
    (clear_path p1 p2) (clear_path p2 p1) (clearable p2 p3) (clear_path p3 p4) (clear_path p4 p3)
    (clear_path p4 p5) (clear_path p5 p4) (clear_path p1 p6) (clear_path p6 p1)
    (clear_path p8 p5) (clear_path p5 p8) MAP)
  (:goal (and (picture_taken p5)))
  (:metric minimize (total-cost)))
"""
ROBOT_MAP = "(clear_path p6 p7) (clear_path p7 p5)"  # walls collapsed; rubble on p1 -> p8
HUMAN_MAP = "(clear_path p1 p8)"  # the human's outdated map


def _domain(move: int, clear: int, picture: int) -> str:
    return (
        DOMAIN.replace("MOVE", str(move))
        .replace("CLEAR", str(clear))
        .replace("PICTURE", str(picture))
    )


def usar_texts(scale: int, variant: str) -> dict[str, str]:
    """The paper's USAR example (``domains/usar-fetch/p1``) with large costs.

    ``robot``: clearing debris costs the robot ``scale`` (the human still thinks 3), so the
    cost is one more update to explain.  ``both``: every cost large and different in both
    models (move ``scale``, clear ``3 * scale + 1``, picture 1: gcd 1, the cheapest action
    costs 1, so ``floor(c / c_min)`` is far above the horizon cap)."""
    if variant == "robot":
        robot, human = _domain(1, scale, 1), _domain(1, 3, 1)
    else:
        robot = human = _domain(scale, 3 * scale + 1, 1)
    return {
        "robot-domain.pddl": robot,
        "human-domain.pddl": human,
        "robot-problem.pddl": PROBLEM.replace("MAP", ROBOT_MAP),
        "human-problem.pddl": PROBLEM.replace("MAP", HUMAN_MAP),
    }


def _limit_memory() -> None:
    resource.setrlimit(resource.RLIMIT_AS, (2 * GIB, 2 * GIB))


@pytest.mark.parametrize("variant", ["robot", "both"])
@pytest.mark.parametrize("scale", LARGE)
def test_frontier_with_large_costs_in_bounded_time_and_memory(scale, variant, tmp_path):
    """``mega-sat frontier`` in a subprocess limited to 2 GB of address space and 60 s: the
    frontier is complete, exact, and that of the brute-force oracle and of the astar engine."""
    from helpers.bruteforce import brute_force_frontier

    from mega_sat.api import frontier
    from mega_sat.ground.grounding import ground
    from mega_sat.pddl.loading import load_task_from_strings

    texts = usar_texts(scale, variant)
    for name, text in texts.items():
        (tmp_path / name).write_text(text)
    cli = "import sys; sys.argv[0] = 'mega-sat'; from mega_sat.cli.commands import main; main()"
    t0 = time.perf_counter()
    res = subprocess.run(
        [sys.executable, "-c", cli, "frontier", "--task", str(tmp_path), "--json"],
        capture_output=True,
        text=True,
        timeout=60,
        preexec_fn=_limit_memory,
    )
    took = time.perf_counter() - t0
    assert res.returncode == 0, res.stderr[-2000:]
    got = json.loads(res.stdout)
    assert got["exact"] and got["complete"], got["notes"]
    pairs = [(len(p["explanation"]), p["robot_cost"]) for p in got["frontier"]]

    task = load_task_from_strings(
        texts["robot-domain.pddl"],
        texts["robot-problem.pddl"],
        texts["human-domain.pddl"],
        texts["human-problem.pddl"],
    )
    c_robot, points, _ = brute_force_frontier(task, ground(task))
    assert got["robot_optimal_cost"] == c_robot
    assert pairs == [(p.size, p.robot_cost) for p in points]
    astar = frontier(task, engine="astar")
    assert astar.robot_optimal_cost == c_robot
    assert [(p.size, p.robot_cost) for p in astar.points] == pairs
    assert took < 60
