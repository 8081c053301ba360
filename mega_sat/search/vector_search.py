"""Uniform-cost search over numpy arrays of bit-packed states.

:func:`mega_sat.search.astar.uniform_cost_steps` pops one state at a time in pure Python, about
a hundred thousand states a second.  An unsolvable model must be searched to exhaustion, and
the human models of a large model difference often are unsolvable with state spaces of a
million states; so this search expands whole layers at once: a layer of states is a
``(n, words)`` array of ``uint64``, applicability of every action is two mask tests over the
whole layer, and the closed list is a few sorted arrays searched with ``searchsorted``.

It is the same search in the same order: states of one path cost ``g`` in the order they were
first generated, the successors of a state in the order of its actions, zero-cost successors
after the states of the same ``g`` that were there before them.  So it expands the same states,
returns the same plan, yields the same counts at the same points (every ``_CHECK_EVERY``
expansions) and returns the same answer as the pure-Python search, only faster on large
layers.  ``tests/test_vector_search.py`` checks that on random tasks.

Only the atoms some action adds or deletes are stored (the others keep their initial value),
so most tasks here fit one 64-bit word per state.
"""

from __future__ import annotations

import heapq
from collections.abc import Callable

import numpy as np

from mega_sat.deadline import NO_DEADLINE, Deadline
from mega_sat.ground.family import GroundTask
from mega_sat.ground.relevance import relevant_part
from mega_sat.model.lifted import PlanStep
from mega_sat.status import Status

_WORD = 64
_ALL = (1 << _WORD) - 1
_GROUP_ROWS = 32
"""Action tables from this size on, with three rows or more per run of equal conditions on
average, have each run tested once; smaller or less repetitive tables are tested row by row,
which is then as fast or faster."""
_CHUNK = 4096
"""States expanded per numpy pass: large enough that numpy's per-call cost is small, small
enough that the applicability matrix (states x actions) stays a few megabytes."""


def _words(atoms, pos: dict[int, int], n_words: int) -> list[int]:
    mask = 0
    for p in atoms:
        mask |= 1 << pos[p]
    return [(mask >> (_WORD * w)) & _ALL for w in range(n_words)]


class _Closed:
    """A set of state keys as a few sorted arrays of doubling size (a log-structured merge):
    membership is one ``searchsorted`` per array, insertion amortises the sorting.  Keys added
    with their ``rows`` keep them, in the same order, in ``rows``."""

    def __init__(self) -> None:
        self.levels: list[np.ndarray] = []
        self.rows: list[np.ndarray | None] = []

    def contains(self, keys: np.ndarray) -> np.ndarray:
        found = np.zeros(len(keys), dtype=bool)
        for hit, _, _ in self.lookup(keys):
            found |= hit
        return found

    def lookup(self, keys: np.ndarray):
        """Per sorted array: which ``keys`` it holds, where each would stand in it, and the
        rows kept behind its keys (``None`` if none were given)."""
        for level, rows in zip(self.levels, self.rows, strict=True):
            at = np.minimum(np.searchsorted(level, keys), len(level) - 1)
            yield level[at] == keys, at, rows

    def add(self, keys: np.ndarray, rows: np.ndarray | None = None) -> None:
        if not len(keys):
            return
        self.levels.append(keys)
        self.rows.append(rows)
        self._sort_top()
        while len(self.levels) > 1 and len(self.levels[-2]) <= 2 * len(self.levels[-1]):
            top, top_rows = self.levels.pop(), self.rows.pop()
            self.levels[-1] = np.concatenate((self.levels[-1], top))
            if top_rows is not None:
                self.rows[-1] = np.concatenate((self.rows[-1], top_rows))
            self._sort_top()

    def compact(self) -> None:
        """Merge every array into one: for a set searched far more often than it grows, one
        ``searchsorted`` per lookup instead of one per array.  The arrays are sorted runs, which
        a stable sort merges in linear time."""
        if len(self.levels) < 2:
            return
        rows = None if self.rows[0] is None else np.concatenate(self.rows)
        self.levels, self.rows = [np.concatenate(self.levels)], [rows]
        self._sort_top(kind="stable")

    def _sort_top(self, kind: str | None = None) -> None:
        if self.rows[-1] is None:
            self.levels[-1] = np.sort(self.levels[-1], kind=kind)
        else:
            order = np.argsort(self.levels[-1], kind=kind)
            self.levels[-1], self.rows[-1] = self.levels[-1][order], self.rows[-1][order]


def mutable_atoms(task: GroundTask) -> list[int]:
    """The atoms some action adds or deletes, sorted: the ones a state stores."""
    return sorted({p for a in task.actions for p in (*a.add, *a.delete)})


def state_words(n_atoms: int) -> int:
    """The 64-bit words of a state that stores ``n_atoms`` atoms (at least one)."""
    return max(1, -(-n_atoms // _WORD))


class _Layout:
    """The search's view of ``task``: actions in generation order as word arrays."""

    def __init__(self, task: GroundTask, order: list[int]):
        mutable = mutable_atoms(task)
        pos = {p: i for i, p in enumerate(mutable)}
        self.n_words = w = state_words(len(mutable))
        init = set(task.init)
        rows, pre, neg, keep, add = [], [], [], [], []
        for j in order:
            a = task.actions[j]
            fixed_pre = [p for p in a.pre if p not in pos]
            fixed_neg = [p for p in a.negpre if p not in pos]
            # an atom no action changes keeps its initial value in every reachable state
            if any(p not in init for p in fixed_pre) or any(p in init for p in fixed_neg):
                continue
            rows.append(j)
            pre.append(_words([p for p in a.pre if p in pos], pos, w))
            neg.append(_words([p for p in a.negpre if p in pos], pos, w))
            keep.append([x ^ _ALL for x in _words(a.delete, pos, w)])
            add.append(_words(a.add, pos, w))
        self.action = np.array(rows, dtype=np.int64)
        self.cost = np.array([task.actions[j].cost for j in rows], dtype=np.int64)
        self.pre, self.neg, self.keep, self.add = (
            np.array(x, dtype=np.uint64).reshape(-1, w) for x in (pre, neg, keep, add)
        )
        self.pos = pos
        self.init_set = init

    def state(self, atoms) -> np.ndarray:
        return np.array([_words([p for p in atoms if p in self.pos], self.pos, self.n_words)],
                        dtype=np.uint64)  # fmt: skip

    def goal_rows(self, goal_atoms) -> Callable[[np.ndarray], np.ndarray]:
        """A test giving the rows of a layer that satisfy the goal (none ever, when a goal
        atom no action changes is false initially)."""
        if not all(p in self.pos or p in self.init_set for p in goal_atoms):
            return lambda states: np.empty(0, dtype=np.int64)
        goal = self.state(goal_atoms)[0]
        return lambda states: np.flatnonzero(((states & goal) == goal).all(axis=1))

    def keys(self, states: np.ndarray) -> np.ndarray:
        return state_keys(states)

    def successors(self, states: np.ndarray) -> tuple[np.ndarray, np.ndarray, np.ndarray]:
        """``(row, action row, successor)`` for every applicable action of every state, in
        generation order (by state, then action)."""
        return successors(states, self.pre, self.neg, self.keep, self.add)


def state_keys(states: np.ndarray) -> np.ndarray:
    """Exact sortable keys of bit-packed states: the word itself, or the row's bytes for
    wider states."""
    if states.shape[1] == 1:
        return states[:, 0]
    return np.ascontiguousarray(states).view(np.dtype((np.void, 8 * states.shape[1]))).ravel()


def key_rows(keys: np.ndarray, n_words: int) -> np.ndarray:
    """Bit-packed states back from their keys (:func:`state_keys`)."""
    return np.ascontiguousarray(keys).view(np.uint64).reshape(-1, n_words)


def unique_keys(keys: np.ndarray) -> np.ndarray:
    """The distinct keys, sorted: one sort and one comparison of neighbours (``np.unique``
    hashes before it sorts, which costs more on arrays of this size)."""
    keys = np.sort(keys)
    first = np.ones(len(keys), dtype=bool)
    if len(keys) > 1:
        first[1:] = keys[1:] != keys[:-1]  # (no ufunc loop writes the void keys of wide states)
    return keys[first]


def successors(
    states: np.ndarray, pre: np.ndarray, neg: np.ndarray, keep: np.ndarray, add: np.ndarray
) -> tuple[np.ndarray, np.ndarray, np.ndarray]:
    """``(row, action row, successor)`` for every action row (word arrays ``pre``, ``neg``,
    ``keep``, ``add``) applicable in every state, by state, then action.

    Neighbouring rows with the same conditions (the variants of one action in
    :mod:`mega_sat.search.may_reachability`, which differ only in their effects) are tested
    once, and each applicable run is spread back over its rows in order."""
    runs = None
    if len(pre) >= _GROUP_ROWS:
        differs = (pre[1:] != pre[:-1]).any(axis=1) | (neg[1:] != neg[:-1]).any(axis=1)
        if 3 * (differs.sum() + 1) <= len(pre):
            runs = np.concatenate(([0], np.flatnonzero(differs) + 1))
            pre, neg = pre[runs], neg[runs]
    # one mask test per word: the atoms a row tests, against the ones it needs true
    both = pre | neg
    ok = (states[:, :1] & both[:, 0]) == pre[:, 0]
    for w in range(1, states.shape[1]):
        ok &= (states[:, w : w + 1] & both[:, w]) == pre[:, w]
    clash = ((pre & neg) != 0).any(axis=1)  # a row needing an atom both true and false
    if clash.any():
        ok &= ~clash
    # the flat indices split by hand: the same (row-major) pairs as np.nonzero, several times
    # faster than its two-dimensional form
    rows, acts = np.divmod(np.flatnonzero(ok), ok.shape[1])
    if runs is not None:
        # run k covers rows runs[k] .. runs[k+1]-1: repeat each (state, run) pair once per
        # row of its run, counting up from the run's first row
        sizes = np.diff(runs, append=len(keep))[acts]
        ends = np.cumsum(sizes)
        rows = np.repeat(rows, sizes)
        acts = np.repeat(runs[acts] - ends + sizes, sizes) + np.arange(len(rows))
    return rows, acts, (states[rows] & keep[acts]) | add[acts]


def _first_new(keys: np.ndarray, closed: _Closed) -> np.ndarray:
    """Indices of the first occurrence of each key not in ``closed``, in order of occurrence
    (the closed list is searched with the sorted unique keys, which is cache-friendly)."""
    unique, first = np.unique(keys, return_index=True)
    first = first[~closed.contains(unique)]
    first.sort()
    return first


def vector_uniform_cost_steps(
    task: GroundTask,
    init: int,
    goal: int,
    node_limit: int | None = None,
    *,
    order: list[int] | None = None,
    check_every: int = 32,
):
    """:func:`mega_sat.search.astar.uniform_cost_steps` on numpy layers: the same generator
    protocol (it yields the expansions so far every ``check_every`` expansions and returns
    ``(status, plan, cost, expanded)``), the same states in the same order.  ``order``: the
    actions' generation order (default: their index order)."""
    if order is None:
        order = list(range(len(task.actions)))
    lay = _Layout(task, order)
    at_goal = lay.goal_rows([p for p in range(len(task.atoms)) if goal >> p & 1])
    closed = _Closed()
    # what the plan is read back from: per closed state id, its parent's id and action
    parents: list[np.ndarray] = []
    actions: list[np.ndarray] = []
    n_closed = 0
    start = lay.state([p for p in range(len(task.atoms)) if init >> p & 1])
    buckets: dict[int, list[tuple[np.ndarray, np.ndarray, np.ndarray]]] = {
        0: [(start, np.array([-1]), np.array([-1]))]
    }
    pending = [0]
    expanded = 0

    def trace(parent: int, act: int) -> tuple[PlanStep, ...]:
        steps: list[PlanStep] = []
        if act < 0:  # the initial state
            return ()
        up, how = np.concatenate(parents), np.concatenate(actions)
        while act >= 0:
            steps.append(task.actions[int(act)].step)
            parent, act = int(up[parent]), int(how[parent])
        return tuple(reversed(steps))

    while pending:
        g = heapq.heappop(pending)
        parts = buckets.pop(g)
        layer = tuple(np.concatenate(x) for x in zip(*parts, strict=True))
        while len(layer[0]):
            states, up, how = layer
            keys = lay.keys(states)
            fresh = _first_new(keys, closed)
            states, up, how, keys = states[fresh], up[fresh], how[fresh], keys[fresh]
            if not len(states):
                break
            n = len(states)
            reached = at_goal(states)
            stop = int(reached[0]) if len(reached) else n
            room = n if node_limit is None else max(node_limit - expanded, 0)
            # pop by pop, the pure-Python search tests the goal, then the node limit, then
            # yields every check_every pops: k pops pass both tests here
            k = min(stop, room, n)
            yield from range(-(-expanded // check_every) * check_every, expanded + k, check_every)
            if k < n:
                expanded += k
                if k == stop:
                    return Status.OPTIMAL, trace(int(up[k]), int(how[k])), g, expanded
                return Status.LIMIT, None, None, expanded
            closed.add(keys)
            ids = np.arange(n_closed, n_closed + n)
            n_closed += n
            parents.append(up)
            actions.append(how)
            zero: list[tuple[np.ndarray, np.ndarray, np.ndarray]] = []
            for lo in range(0, n, _CHUNK):
                rows, acts, succ = lay.successors(states[lo : lo + _CHUNK])
                g2 = g + lay.cost[acts]
                parent_ids, act_ids = ids[lo + rows], lay.action[acts]
                same = g2 == g
                if same.any():
                    zero.append((succ[same], parent_ids[same], act_ids[same]))
                for c in np.unique(g2[~same]):
                    pick = g2 == c
                    c = int(c)
                    if c not in buckets:
                        buckets[c] = []
                        heapq.heappush(pending, c)
                    buckets[c].append((succ[pick], parent_ids[pick], act_ids[pick]))
            expanded += n
            if not zero:
                break
            layer = tuple(np.concatenate(x) for x in zip(*zero, strict=True))
    return Status.UNSOLVABLE, None, None, expanded


def goal_reachable(
    task: GroundTask, *, node_limit: int | None = None, deadline: Deadline | None = None
) -> tuple[Status, int]:
    """Whether any state of ``task`` satisfies its goal, and the states expanded to find out:
    :meth:`Reachability.run` from scratch."""
    reach = Reachability(task)
    return reach.run(node_limit, deadline), reach.expanded


class _Collision(Exception):
    """Two different states with the same 64-bit key in one :class:`_StateSet`."""


def _mix(x: np.ndarray) -> np.ndarray:
    """SplitMix64's finaliser, a bijection of 64-bit words that spreads every bit over all.
    Array arithmetic on ``uint64`` wraps around silently."""
    x = (x ^ (x >> np.uint64(30))) * np.uint64(0xBF58476D1CE4E5B9)
    x = (x ^ (x >> np.uint64(27))) * np.uint64(0x94D049BB133111EB)
    return x ^ (x >> np.uint64(31))


def row_hashes(states: np.ndarray) -> np.ndarray:
    """A 64-bit key per row of a multi-word state array: its words mixed in one at a time.
    Not injective: :class:`_StateSet` checks every key it relies on against the rows."""
    h = _mix(states[:, 0])
    for w in range(1, states.shape[1]):
        h = _mix(h ^ states[:, w] ^ np.uint64(w))
    return h


class _StateSet:
    """Exact sets of bit-packed states for a breadth-first search, keyed for sorting and
    lookup.  A state of one word is its own key.  Wider states would need their bytes as keys,
    and numpy sorts and searches those an order of magnitude more slowly than integers; so
    they get a 64-bit hash as their key (:func:`row_hashes`), and every use of a key compares
    the rows behind it.  Two different states with the same key raise :class:`_Collision`;
    ``hashed=False`` keys wide states by their bytes instead, always exact."""

    def __init__(self, n_words: int, *, hashed: bool = True):
        self.n_words = n_words
        self.hashed = hashed and n_words > 1
        self.closed = _Closed()  # hashed: with the states behind its keys

    def distinct(self, states: np.ndarray) -> tuple[np.ndarray, np.ndarray]:
        """The distinct rows of ``states`` and their keys, in key order."""
        if not self.hashed:
            keys = unique_keys(state_keys(states))
            return key_rows(keys, self.n_words), keys
        h = row_hashes(states)
        order = np.argsort(h)
        h, states = h[order], states[order]
        same = h[1:] == h[:-1]
        if (same & (states[1:] != states[:-1]).any(axis=1)).any():
            raise _Collision
        first = np.ones(len(h), dtype=bool)
        first[1:] = ~same
        return states[first], h[first]

    def unseen(self, states: np.ndarray, keys: np.ndarray) -> np.ndarray:
        """Which of the distinct ``states`` (keys ``keys``) are not in the set."""
        if not self.hashed:
            return ~self.closed.contains(keys)
        seen = np.zeros(len(keys), dtype=bool)
        for hit, at, rows in self.closed.lookup(keys):
            if hit.any():
                if (rows[at[hit]] != states[hit]).any():
                    raise _Collision
                seen |= hit
        return ~seen

    def add(self, states: np.ndarray, keys: np.ndarray) -> None:
        """Add distinct ``states`` (keys ``keys``) that :meth:`unseen` found new."""
        self.closed.add(keys, states if self.hashed else None)


class Reachability:
    """Breadth-first reachability of ``task`` on numpy layers, costs ignored, that can be
    resumed with a larger state limit: the exhaustive searches that prove a model unsolvable
    need no order, so no costs either, and a layer is a set, kept in key order
    (:class:`_StateSet`).  It runs on the relevant part of ``task`` (the same verdict, often
    on far fewer states)."""

    def __init__(self, task: GroundTask, *, hashed: bool = True):
        task = relevant_part(task)
        self._lay = _Layout(task, list(range(len(task.actions))))
        self._at_goal = self._lay.goal_rows(task.goal)
        self._init = task.init
        self._start(hashed)
        self.verdict: Status | None = None  # once decided

    def _start(self, hashed: bool) -> None:
        self._seen = _StateSet(self._lay.n_words, hashed=hashed)
        self._layer = self._lay.state(self._init)
        self._keys = None  # the keys of _layer once it holds only states not seen before
        self.expanded = 0

    def run(self, node_limit: int | None = None, deadline: Deadline | None = None) -> Status:
        """``PLAN`` once a reached state satisfies the goal, ``UNSOLVABLE`` once every
        reachable state is expanded (a proof that ``task`` has no plan), ``LIMIT`` when that
        would take more than ``node_limit`` expansions in all, ``TIMEOUT`` once ``deadline``
        passes.  After ``LIMIT`` or ``TIMEOUT`` a later call goes on where this one stopped.
        Two states with the same hash key start the search again with exact keys: the
        verdict and the count are those of the search that never hashed."""
        if self.verdict is not None:
            return self.verdict
        try:
            return self._run(node_limit, deadline)
        except _Collision:
            self._start(hashed=False)
            return self._run(node_limit, deadline)

    def _run(self, node_limit: int | None, deadline: Deadline | None) -> Status:
        deadline = deadline if deadline is not None else NO_DEADLINE
        lay, seen = self._lay, self._seen
        while True:
            if self._keys is None:  # a new layer: keep its states not seen before
                states, keys = seen.distinct(self._layer)
                new = seen.unseen(states, keys)
                self._layer, self._keys = states[new], keys[new]
                if not len(self._layer):
                    break
                if len(self._at_goal(self._layer)):
                    self.verdict = Status.PLAN
                    return self.verdict
            layer = self._layer
            if node_limit is not None and self.expanded + len(layer) > node_limit:
                return Status.LIMIT
            successors = []
            for lo in range(0, len(layer), _CHUNK):
                if deadline.expired():
                    return Status.TIMEOUT  # the layer is expanded again on the next call
                successors.append(seen.distinct(lay.successors(layer[lo : lo + _CHUNK])[2])[0])
            seen.add(layer, self._keys)
            self.expanded += len(layer)
            self._layer = np.concatenate(successors) if successors else layer[:0]
            self._keys = None
        self.verdict = Status.UNSOLVABLE
        return self.verdict
