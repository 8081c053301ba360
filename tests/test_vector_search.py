"""The numpy uniform-cost search is the pure-Python one, only faster: same states, same order,
same counts yielded, same answer (plan included), on random tasks with zero-cost actions,
negative preconditions, atoms no action changes, node limits and states wider than a word."""

from __future__ import annotations

import numpy as np
import pytest
from helpers.fuzzing import oracle_settings
from hypothesis import given
from hypothesis import strategies as st

from mega_sat.ground.family import GroundTask, StripsAction
from mega_sat.ground.relevance import relevant_part
from mega_sat.search import astar as astar_mod
from mega_sat.search.astar import _python_uniform_cost_steps, _successor_groups
from mega_sat.search.vector_search import (
    _GROUP_ROWS,
    Reachability,
    _Closed,
    goal_reachable,
    successors,
    vector_uniform_cost_steps,
)
from mega_sat.status import Status


def _run(steps):
    yielded = []
    try:
        while True:
            yielded.append(next(steps))
    except StopIteration as done:
        return done.value, yielded


@st.composite
def strips_tasks(draw) -> GroundTask:
    """Random STRIPS tasks: a few 'mobile' atoms that actions toggle (so the state space is
    rich), optionally padded past 64 atoms so states take two words."""
    n = draw(st.integers(3, 9))
    pad = draw(st.sampled_from([0, 0, 70]))
    n_atoms = n + pad
    atom_ids = st.integers(0, n - 1)
    sets = st.frozensets(atom_ids, max_size=3)
    acts = []
    for i in range(draw(st.integers(1, 12))):
        pre = draw(sets)
        acts.append(
            StripsAction(
                i, f"a{i}", (), pre | draw(st.frozensets(st.integers(0, n_atoms - 1), max_size=1)),
                draw(sets) - pre, draw(sets), draw(sets), draw(st.sampled_from([0, 1, 1, 2, 5])),
            )
        )  # fmt: skip
    if pad:  # two actions that change all the padding atoms: states take two words
        far = frozenset(range(n, n_atoms))
        acts.append(StripsAction(len(acts), "out", (), frozenset({0}), frozenset(), far,
                                 frozenset({0}), 1))  # fmt: skip
        acts.append(StripsAction(len(acts), "back", (), frozenset({n_atoms - 1}), frozenset(),
                                 frozenset({0}), far, 0))  # fmt: skip
    init = draw(st.frozensets(st.integers(0, n_atoms - 1), max_size=n_atoms // 2 + 1))
    goal = draw(st.frozensets(st.integers(0, n_atoms - 1), min_size=1, max_size=3))
    atoms = tuple((f"p{i}",) for i in range(n_atoms))
    return GroundTask(atoms, tuple(acts), init, goal)


@oracle_settings(300, suppress_health_check=())
@given(strips_tasks(), st.sampled_from([None, None, 0, 1, 3, 7]))
def test_vector_search_is_the_python_search(task, node_limit):
    init = sum(1 << p for p in task.init)
    goal = sum(1 << p for p in task.goal)
    order = [act[0] for _, acts in _successor_groups(task) for act in acts]
    (py, py_counts) = _run(_python_uniform_cost_steps(task, init, goal, node_limit))
    (vec, vec_counts) = _run(
        vector_uniform_cost_steps(task, init, goal, node_limit, order=order, check_every=32)
    )
    assert vec == py
    assert vec_counts == py_counts


def _grid(width: int, zero_every: int) -> GroundTask:
    """A width x width grid walk (one position atom per cell) plus 'coins' picked up on the
    way, which multiplies the states; every ``zero_every``-th move costs nothing."""
    cells = [(x, y) for x in range(width) for y in range(width)]
    at = {c: i for i, c in enumerate(cells)}
    coins = {c: len(cells) + k for k, c in enumerate(cells[1::3])}
    acts = []
    for (x, y), i in at.items():
        for dx, dy in ((1, 0), (0, 1), (-1, 0), (0, -1)):
            if (x + dx, y + dy) in at:
                j = at[(x + dx, y + dy)]
                cost = 0 if len(acts) % zero_every == 0 else 1 + len(acts) % 3
                acts.append(StripsAction(len(acts), "move", (str(i), str(j)), frozenset({i}),
                                         frozenset(), frozenset({j}), frozenset({i}), cost))  # fmt: skip
        if (x, y) in coins:
            k = coins[(x, y)]
            acts.append(StripsAction(len(acts), "pick", (str(i),), frozenset({i}),
                                     frozenset({k}), frozenset({k}), frozenset(), 1))  # fmt: skip
    atoms = tuple((f"p{i}",) for i in range(len(cells) + len(coins)))
    goal = frozenset({at[cells[-1]], *list(coins.values())[-3:]})
    return GroundTask(atoms, tuple(acts), frozenset({0}), goal)


def test_large_searches_agree_with_the_python_search_and_switch_over():
    """Searches past ``VECTOR_AFTER`` expansions, through the public generator (which moves to
    numpy midway): the answer and every count yielded are the pure-Python search's."""
    for width, zero_every in ((5, 4), (6, 7)):
        task = _grid(width, zero_every)
        init = sum(1 << p for p in task.init)
        goal = sum(1 << p for p in task.goal)
        py, py_counts = _run(_python_uniform_cost_steps(task, init, goal))
        mixed, mixed_counts = _run(astar_mod.uniform_cost_steps(task, init, goal))
        assert py[0] == Status.OPTIMAL and py[3] > astar_mod.VECTOR_AFTER
        assert mixed == py and mixed_counts == py_counts
        # unsolvable: the goal needs a coin that does not exist, after exhausting the space
        dead = GroundTask(task.atoms + (("never",),), task.actions, task.init,
                          task.goal | {len(task.atoms)})  # fmt: skip
        py, py_counts = _run(_python_uniform_cost_steps(dead, init, goal | 1 << len(task.atoms)))
        mixed, mixed_counts = _run(
            astar_mod.uniform_cost_steps(dead, init, goal | 1 << len(task.atoms))
        )
        assert py[0] == Status.UNSOLVABLE and mixed == py and mixed_counts == py_counts


@oracle_settings(300, suppress_health_check=())
@given(strips_tasks(), st.sampled_from([None, None, 1, 4, 20]))
def test_goal_reachable_agrees_with_search(task, node_limit):
    """Reachability proves unsolvable exactly the tasks the search exhausts, within the same
    number of expansions (both on the relevant part of the task), and finds the goal exactly
    where there is a plan."""
    part = relevant_part(task)
    init = sum(1 << p for p in part.init)
    goal = sum(1 << p for p in part.goal)
    full, _ = _run(_python_uniform_cost_steps(part, init, goal))
    whole, _ = _run(
        _python_uniform_cost_steps(
            task, sum(1 << p for p in task.init), sum(1 << p for p in task.goal)
        )
    )
    assert (full[0] == Status.OPTIMAL) == (whole[0] == Status.OPTIMAL)
    verdict, expanded = goal_reachable(task, node_limit=node_limit)
    if verdict == Status.UNSOLVABLE:
        assert expanded == full[3]  # every reachable state, once
    if full[0] == Status.OPTIMAL:
        assert verdict in ((Status.PLAN, Status.LIMIT) if node_limit else (Status.PLAN,))
    else:
        exhausted = node_limit is None or full[3] <= node_limit
        assert verdict == (Status.UNSOLVABLE if exhausted else Status.LIMIT)
    if node_limit is None:
        assert verdict == (Status.PLAN if full[0] == Status.OPTIMAL else Status.UNSOLVABLE)


@oracle_settings(200, suppress_health_check=())
@given(strips_tasks(), st.lists(st.integers(0, 30), min_size=1, max_size=5))
def test_reachability_resumed_in_steps_is_one_run(task, limits):
    """Resumed with growing state limits, the check ends with the verdict and the count of a
    single run, and each intermediate LIMIT stays within its limit."""
    one, expanded = goal_reachable(task)
    reach = Reachability(task)
    for limit in sorted(limits):
        verdict = reach.run(limit)
        assert reach.expanded <= limit or verdict != Status.LIMIT
        if verdict != Status.LIMIT:
            assert verdict == one
    assert reach.run() == one and reach.expanded == expanded
    assert reach.run(0) == one  # decided: asked again, the same answer


def _step(i: int, name: str, pre: int, add: int) -> StripsAction:
    """An action that moves a token from atom ``pre`` to atom ``add``."""
    return StripsAction(i, name, (), frozenset({pre}), frozenset(), frozenset({add}),
                        frozenset({pre}), 1)  # fmt: skip


def _token(n: int, goal) -> GroundTask:
    """A token moved forward along ``n`` atoms from the sixth: each atom is a precondition,
    so states past 64 atoms take two words."""
    acts = tuple(_step(i, f"step{i}", i, i + 1) for i in range(n - 1))
    return GroundTask(tuple((f"p{i}",) for i in range(n)), acts, frozenset({5}), frozenset(goal))


@pytest.mark.parametrize("goal", [{69}, {3, 69}], ids=["end", "behind-and-end"])
def test_reachability_on_states_of_two_words(goal):
    """The token reaches the end, never two places at once, and never goes back: the second
    goal is proven unsolvable after the 65 states from the sixth atom on, as the search
    proves it."""
    n = 70
    task = _token(n, goal)
    verdict, expanded = goal_reachable(task)
    if goal == {69}:
        assert verdict == Status.PLAN
    else:
        init = sum(1 << p for p in task.init)
        full, _ = _run(_python_uniform_cost_steps(task, init, sum(1 << p for p in goal)))
        assert verdict == Status.UNSOLVABLE and expanded == full[3] == n - 5


@st.composite
def wide_tasks(draw) -> GroundTask:
    """Random STRIPS tasks over 65-90 atoms that every action may change, so that the
    relevant part's states take two words."""
    n = draw(st.integers(65, 90))
    atom = st.integers(0, n - 1)
    sets = st.frozensets(atom, max_size=3)
    acts = []
    for i in range(draw(st.integers(n // 2, n + 20))):
        pre = draw(st.frozensets(atom, min_size=1, max_size=2))
        acts.append(
            StripsAction(i, f"a{i}", (), pre, frozenset(), draw(sets), draw(sets), 1)
        )  # fmt: skip
    init = draw(st.frozensets(atom, min_size=1, max_size=n // 2))
    goal = draw(st.frozensets(atom, min_size=1, max_size=3))
    return GroundTask(tuple((f"p{i}",) for i in range(n)), tuple(acts), init, goal)


@oracle_settings(100, suppress_health_check=())
@given(wide_tasks(), st.lists(st.sampled_from([20, 200, 2000]), min_size=1, max_size=2))
def test_hashed_states_give_the_exact_verdict_and_count(task, limits):
    """States of two words are keyed by a 64-bit hash: the same verdicts and counts as keying
    them by their bytes (resumed with growing limits), and as the search once decided."""
    hashed = Reachability(task)
    exact = Reachability(task, hashed=False)
    for limit in sorted(limits):
        assert hashed.run(limit) == exact.run(limit)
        assert hashed.expanded == exact.expanded
    if hashed.verdict is not None:  # decided within the limit: a small search decides too
        part = relevant_part(task)
        init = sum(1 << p for p in part.init)
        goal = sum(1 << p for p in part.goal)
        full, _ = _run(_python_uniform_cost_steps(part, init, goal))
        assert (hashed.verdict == Status.PLAN) == (full[0] == Status.OPTIMAL)
        if hashed.verdict == Status.UNSOLVABLE:
            assert hashed.expanded == full[3]


@pytest.mark.parametrize("weak", [lambda s: s[:, 0] % np.uint64(3), lambda s: s[:, 1] * 0])
def test_colliding_hashes_fall_back_to_exact_keys(monkeypatch, weak):
    """With a hash that maps many states to one key, the search notices the first collision
    and starts again with exact keys: the verdict and count stay those of the exact search."""
    from mega_sat.search import vector_search

    n = 70
    task = _token(n, {3, n - 1})
    exact = Reachability(task, hashed=False)
    monkeypatch.setattr(vector_search, "row_hashes", weak)
    reach = Reachability(task)
    assert reach.run(10) == exact.run(10) == Status.LIMIT and reach.expanded == exact.expanded
    assert reach.run() == exact.run() == Status.UNSOLVABLE
    assert reach.expanded == exact.expanded == n - 5


def test_two_new_states_with_one_key_are_both_kept(monkeypatch):
    """The two successors of the initial state share a key under a weak hash, and only the
    second leads to the goal: the collision inside the layer is noticed (no closed state has
    that key), so the goal is still found."""
    from mega_sat.search import vector_search

    n = 70
    # p1 is a dead end (d also needs p2), but a relevant one: both successors are states
    both = StripsAction(3, "d", (), frozenset({1, 2}), frozenset(), frozenset({3}),
                        frozenset(), 1)  # fmt: skip
    acts = [_step(0, "a", 0, 1), _step(1, "b", 0, 2), _step(2, "c", 2, n - 1), both]
    acts += [_step(len(acts) + k - 3, f"step{k}", k, k + 1) for k in range(3, n - 1)]
    task = GroundTask(tuple((f"p{i}",) for i in range(n)), tuple(acts), frozenset({0}),
                      frozenset({n - 1}))  # fmt: skip

    def weak(states):
        keys = states[:, 0] ^ (states[:, 1] << np.uint64(32))
        keys[(states[:, 0] & np.uint64(6)) != 0] = 6  # p1 and p2 (bits 1 and 2 of word 0)
        return keys

    monkeypatch.setattr(vector_search, "row_hashes", weak)
    assert vector_search._Layout(relevant_part(task), list(range(len(acts)))).n_words == 2
    assert goal_reachable(task)[0] == Status.PLAN


def _successors_row_by_row(states, pre, neg, keep, add):
    """The definition of :func:`successors`, one state and one row at a time."""
    out = []
    for r, s in enumerate(states):
        for a in range(len(pre)):
            if ((s & (pre[a] | neg[a])) == pre[a]).all() and not (pre[a] & neg[a]).any():
                out.append((r, a, tuple(int(x) for x in (s & keep[a]) | add[a])))
    return out


def _listed(rows, acts, succ):
    return [(int(r), int(a), tuple(int(x) for x in s))
            for r, a, s in zip(rows, acts, succ, strict=True)]  # fmt: skip


@st.composite
def action_tables(draw):
    """States and action rows over a few atoms, the rows in runs of equal conditions (as
    the variants of one action) long and short, so that both ways of testing them run."""
    words = draw(st.integers(1, 2))
    word = st.lists(st.integers(0, 63), min_size=words, max_size=words)
    states = draw(st.lists(word, max_size=40))
    runs = draw(st.lists(st.tuples(word, word, st.integers(1, 8)), min_size=1, max_size=24))
    pre, neg = [], []
    for p, n, length in runs:
        pre += [p] * length
        neg += [n] * length
    rows = len(pre)
    keep = draw(st.lists(word, min_size=rows, max_size=rows))
    add = draw(st.lists(word, min_size=rows, max_size=rows))
    return tuple(np.array(x, dtype=np.uint64).reshape(-1, words)
                 for x in (states, pre, neg, keep, add))  # fmt: skip


@oracle_settings(150)
@given(action_tables())
def test_successors_with_runs_of_equal_conditions_are_row_by_row(table):
    """Grouped (runs tested once) or not, the successors are the row-by-row ones, in
    order; tables below the grouping size are grouped too when the size is lowered."""
    from mega_sat.search import vector_search

    want = _successors_row_by_row(*table)
    for group in (_GROUP_ROWS, 1):
        vector_search._GROUP_ROWS = group
        try:
            rows, acts, succ = successors(*table)
        finally:
            vector_search._GROUP_ROWS = _GROUP_ROWS
        assert _listed(rows, acts, succ) == want


def test_a_grouped_table_tests_each_run_once(monkeypatch):
    """A table of long runs is tested on its runs only: a count of the rows the mask test
    sees (through ``np.flatnonzero``'s input) shows the grouping happened."""
    from mega_sat.search import vector_search

    rng = np.random.default_rng(7)
    states = rng.integers(0, 1 << 12, size=(50, 1), dtype=np.uint64)
    pre = np.repeat(np.arange(10, dtype=np.uint64).reshape(-1, 1), 4, 0)  # 10 runs of 4
    neg = np.zeros_like(pre)
    keep = rng.integers(0, 1 << 12, size=(40, 1), dtype=np.uint64)
    add = rng.integers(0, 1 << 12, size=(40, 1), dtype=np.uint64)
    seen = []
    real = np.flatnonzero
    monkeypatch.setattr(vector_search.np, "flatnonzero", lambda a: seen.append(a.shape) or real(a))
    rows, acts, succ = successors(states, pre, neg, keep, add)
    monkeypatch.undo()
    assert seen[-1] == (50, 10)
    assert _listed(rows, acts, succ) == _successors_row_by_row(states, pre, neg, keep, add)


@pytest.mark.parametrize("with_rows", [False, True])
def test_a_compacted_closed_list_is_the_same_set(with_rows):
    """``_Closed.compact`` merges the sorted arrays into one: membership and the rows kept
    behind the keys stay as they were."""
    rng = np.random.default_rng(3)
    closed = _Closed()
    # keys are added once each, as the searches add only keys not seen before
    keys = rng.permutation(500).astype(np.uint64)
    batches = [np.sort(keys[lo:hi]) for lo, hi in ((0, 40), (40, 47), (47, 137), (137, 140))]
    for batch in batches:
        closed.add(batch, batch * np.uint64(2) if with_rows else None)
    assert len(closed.levels) > 1
    probe = np.arange(500, dtype=np.uint64)
    before = closed.contains(probe)
    closed.compact()
    assert len(closed.levels) == 1 and (np.diff(closed.levels[0].astype(np.int64)) > 0).all()
    assert (closed.contains(probe) == before).all()
    assert (before == np.isin(probe, keys[:140])).all()
    if with_rows:
        assert (closed.rows[0] == closed.levels[0] * np.uint64(2)).all()
