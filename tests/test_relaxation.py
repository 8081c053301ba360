"""h^max and LM-cut against a plain reference: every precondition counted one by one, the queue
of pairs (value, atom).  The A* of the OPT portfolio expands states by these values, so the
fast path (static atoms merged in, not counted) must give the same values, the same choice
function and the same cuts, not just admissible ones."""

from __future__ import annotations

import heapq
import math

from helpers.fuzzing import oracle_settings
from hypothesis import given
from hypothesis import strategies as st

from mega_sat.analysis.relaxation import RelaxedTask
from mega_sat.ground.family import GroundTask, StripsAction


def reference_hmax(r: RelaxedTask, state, costs):
    """h^max and the choice function of ``r`` (the precondition popped last)."""
    h = [math.inf] * r.n_atoms
    done = [False] * r.n_atoms
    left = [len(p) for p in r.pres]
    pcf = [-1] * len(r.pres)
    heap = [(0, p) for p in state if r.needed[p]] + [(0, r.true_atom)]
    for _, p in heap:
        h[p] = 0
    heapq.heapify(heap)
    while heap:
        d, p = heapq.heappop(heap)
        if done[p]:
            continue
        done[p] = True
        for j, pre in enumerate(r.pres):
            if p not in pre:
                continue
            left[j] -= 1
            if left[j] == 0:
                pcf[j] = p
                for q in r.adds[j]:
                    if d + costs[j] < h[q]:
                        h[q] = d + costs[j]
                        heapq.heappush(heap, (h[q], q))
    return h, pcf


def reference_lmcut(r: RelaxedTask, state):
    """LM-cut's value and its cuts (each in the order the forward walk meets them)."""
    costs, total, cuts = list(r.costs), 0, []
    while True:
        h, pcf = reference_hmax(r, state, costs)
        if h[r.goal_atom] in (0, math.inf):
            return (total if h[r.goal_atom] == 0 else math.inf), cuts
        zone, stack = {r.goal_atom}, [r.goal_atom]
        while stack:
            q = stack.pop()
            for j, adds in enumerate(r.adds):
                if q in adds and pcf[j] >= 0 and costs[j] == 0 and pcf[j] not in zone:
                    zone.add(pcf[j])
                    stack.append(pcf[j])
        stack = [r.true_atom, *state]
        reached, cut = set(stack), []
        while stack:
            p = stack.pop()
            for j in range(len(r.pres)):
                if pcf[j] != p:
                    continue
                for q in r.adds[j]:
                    if q not in zone and q not in reached:
                        reached.add(q)
                        stack.append(q)
                if any(q in zone for q in r.adds[j]):
                    cut.append(j)
        m = min(costs[j] for j in cut)
        cuts.append([j for j in cut if j != len(r.pres) - 1])
        total += m
        for j in cut:
            costs[j] -= m


@st.composite
def tasks_and_states(draw):
    """Random ground tasks where many preconditions are static (initially true, never
    deleted), with zero costs, and states that hold every static atom or miss some."""
    n = draw(st.integers(2, 10))
    n_static = draw(st.integers(0, n - 1))
    atoms = tuple(("p", str(i)) for i in range(n))
    subsets = st.frozensets(st.integers(0, n - 1), max_size=4)
    acts = []
    for i in range(draw(st.integers(1, 12))):
        pre, add = draw(subsets), draw(subsets)
        delete = draw(subsets).difference(range(n_static)) - add
        cost = draw(st.integers(0, 3))
        acts.append(StripsAction(i, "a", (str(i),), pre, frozenset(), add, delete, cost))
    init = frozenset(range(n_static)) | draw(subsets)
    task = GroundTask(atoms, tuple(acts), init, draw(subsets))
    holds_statics = draw(st.booleans())
    state = sorted(init | draw(subsets)) if holds_statics else sorted(draw(subsets))
    return task, state


@oracle_settings(300, suppress_health_check=())
@given(tasks_and_states(), st.booleans())
def test_hmax_and_lmcut_equal_the_reference(case, unit):
    task, state = case
    r = RelaxedTask(task)
    costs = [1] * len(r.costs) if unit else r.costs
    assert r.hmax(state, costs) == reference_hmax(r, state, costs)
    assert r.h_max(state) == reference_hmax(r, state, r.costs)[0][r.goal_atom]
    cuts: list[list[int]] = []
    value = r.lmcut(state, cuts)
    assert (value, cuts) == reference_lmcut(r, state)


def test_static_atoms_are_merged_in_their_order():
    """Atom 0 is static, 1 is reached at 0 through a zero-cost action of static 0, 2 is a
    later static; action 3 needs 1 and 2: the queue pops 0, 1, 2, so its choice is 2."""
    acts = (
        StripsAction(0, "a", (), frozenset({0}), frozenset(), frozenset({1}), frozenset(), 0),
        StripsAction(1, "b", (), frozenset({1, 2}), frozenset(), frozenset({3}), frozenset(), 2),
    )
    task = GroundTask(tuple(("p", str(i)) for i in range(4)), acts, frozenset({0, 2}), {3})
    r = RelaxedTask(task)
    h, pcf = r.hmax([0, 2], r.costs)
    assert (h[1], h[3], pcf[0], pcf[1]) == (0, 2, 0, 2)
    assert (h, pcf) == reference_hmax(r, [0, 2], r.costs)
