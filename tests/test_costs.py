"""Action costs of any size: costs up to 10^12 never hang, memory does not grow with them, and
the answers stay exact.

The SAT encoding counts costs in unary while they are small and in binary above
``UNARY_MAX_UNITS`` (``encodings/sequential.md``); these tests run the binary form against
explicit-state search on random families.
Every test that could hang or run out of memory runs under a time and an address-space limit,
so a regression fails instead of taking the machine down (in-process, a C extension that runs
out of address space aborts the test run, which fails it as well).
"""

from __future__ import annotations

import contextlib
import json
import resource
import signal
from dataclasses import replace

import pytest
from hypothesis import HealthCheck, given, settings
from hypothesis import strategies as st
from pysat.solvers import Solver
from sat_families import dijkstra, families, plan_cost, selections
from test_sat_encoding import cheapest_within

from mega_sat.family import GroundAction, GroundFamily
from mega_sat.oracles import SatOracles
from mega_sat.sat_encoding import HUMAN, ROBOT, UNARY_MAX_UNITS, FamilyEncoding

SETTINGS = settings(
    max_examples=60, deadline=None, derandomize=True, suppress_health_check=list(HealthCheck)
)
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
            expect = best is not None and (bound is None or best <= bound)
            assert solver.solve(assumptions=lits) == expect
            if expect:
                plan = enc.decode_plan(solver.get_model(), h)
                cost = plan_cost(task, plan)
                assert cost is not None and len(plan) <= h
                assert bound is None or cost <= bound


# -------------------------------------------------------------------------------- oracles
@SETTINGS
@given(fam=large_cost_families(min_cost=1), data=st.data())
def test_opt_with_large_costs_matches_astar(fam: GroundFamily, data):
    from mega_sat.search import astar

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


@pytest.mark.parametrize("scale", LARGE)
def test_wcnf_export_weighs_binary_cost_bits(scale, tmp_path):
    """The exported MaxSAT formula's optimum is the optimal cost, with soft clauses weighted
    by the bits they stand for, and the horizon is capped and reported as such."""
    from pysat.examples.rc2 import RC2
    from pysat.formula import WCNF

    from mega_sat.cnf_export import export_opt

    costs = [scale + 1, 2 * scale - 1, 3]
    fam = _family(costs)  # optimum: the chain, sum(costs); the jump costs one more
    with bounded(60):
        paths = export_opt(fam, frozenset(), sum(costs) + 5, tmp_path)
        with RC2(WCNF(from_file=str(paths["wcnf"]))) as rc2:
            assert rc2.compute() is not None and rc2.cost == sum(costs)
    meta = json.loads(paths["vars"].read_text())
    assert meta["cost_bits"] > 0 and meta["horizon"] == 200 and not meta["exact"]
    assert "w[human][0][0]" in meta["variables"].values()
