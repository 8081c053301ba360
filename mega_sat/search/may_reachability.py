"""The states some model agreeing with a selection can reach, grown one freed update at a time.

An unsolvable candidate ``human + E`` is excluded by a clause over a set ``fixed`` of updates,
which must hold a proof that every selection agreeing with ``E`` on ``fixed`` is unsolvable.
The *may semantics* over-approximates all of them at once, on concrete states: an update
outside ``fixed`` is *free*, and

* an action whose existence guard is free may exist; a free precondition or goal atom is
  dropped (whichever way it goes, dropping it allows at least as much);
* a free add or delete effect may or may not happen, so an action has one *variant* per
  combination of its free effects, and each variant is a plain STRIPS transition;
* a free initial atom may or may not hold: there is one initial state per combination.

Every transition of every agreeing model is a transition here, so the set ``R`` of states
reachable here contains the reachable states of every agreeing model; if no state of ``R``
satisfies the (smallest possible) goal, none of them has a plan.  This is finer than the
two-fact abstraction of :mod:`mega_sat.analysis.abstraction` (a state here is one concrete
state, not a superposition of many), and it is monotone: freeing one more update only adds
transitions, initial states and goal states.  So :class:`MayReachability` keeps ``R`` for the
free set proven so far and, to test one more update, explores only from what that update adds
(the successors of ``R`` under the actions it guards, and the new initial states); the rest of
``R`` is closed already.  The argument is written out in ``encodings/hitting-set.md``
("Unsolvable models").
"""

from __future__ import annotations

import itertools
from collections.abc import Iterable

import numpy as np

from mega_sat.deadline import NO_DEADLINE, Deadline
from mega_sat.ground.family import Entry, GroundAction, GroundFamily, Guard
from mega_sat.ground.relevance import may_relevant_atoms
from mega_sat.search.vector_search import (
    _CHUNK,
    _Closed,
    _words,
    key_rows,
    state_keys,
    successors,
    unique_keys,
)
from mega_sat.status import Status

_PRESENT, _FREE, _ABSENT = 0, 1, 2

MAX_FREE_COMBINATIONS = 64
"""Most variants of one action (or initial states) a free set may create; past that the
update is not freed (the clause keeps it), which is sound, only less general."""


class _Blowup(Exception):
    """Too many variants: the trial proves nothing."""


class MayReachability:
    """``R`` for a growing free set, for one unsolvable ``human + selection``.

    ``ok`` is False when ``R`` for the empty free set (the model's own reachable states) could
    not be exhausted within ``node_limit`` states; then nothing can be freed by this method.
    ``work_limit`` bounds the new states all trials together may visit (the successors of
    ``R`` under the actions a trial changes are computed for every state of ``R``, at most
    ``node_limit`` per trial, and not counted), so that the effort, and with it the answer,
    does not depend on the machine's speed.  ``trial_limit``: one trial may add at most
    ``max(trial_growth * |R|, trial_limit)`` states (past that its update stays in the clause,
    which is sound, only less general): an update whose freedom multiplies
    ``R`` makes every later trial scan all of it, and one whose may-states reach the goal only
    deep down costs as much before it fails.
    """

    def __init__(
        self,
        family: GroundFamily,
        selection: Iterable[int],
        *,
        node_limit: int,
        work_limit: int | None = None,
        trial_limit: int | None = None,
        trial_growth: int = 0,
        deadline: Deadline | None = None,
    ):
        self.family = family
        self.sel = frozenset(selection)
        self.node_limit = node_limit
        self.work_limit = work_limit
        self.trial_limit = trial_limit
        self.trial_growth = trial_growth
        self.work = 0
        self.deadline = deadline if deadline is not None else NO_DEADLINE
        self.free: frozenset[int] = frozenset()
        # states are projected onto the atoms that can matter for any free set
        # (ground/relevance.py): the rest never decide a condition or the goal, and would
        # only multiply R
        self.relevant = may_relevant_atoms(family, self.sel)
        self.active = {
            j
            for j, a in enumerate(family.actions)
            if any(p in self.relevant for p, _ in (*a.add, *a.delete))
        }
        mutable = {p for a in family.actions for p, _ in (*a.add, *a.delete)}
        mutable.update(p for p, g in family.init if g is not None)
        # atoms no action changes and no update puts in the initial state: constant
        self.constant_true = {p for p, g in family.init if g is None and p not in mutable}
        self.pos = {p: i for i, p in enumerate(sorted(mutable & self.relevant))}
        self.n_words = max(1, -(-len(self.pos) // 64))
        self.mentions: dict[int, list[int]] = {}
        for j in sorted(self.active):
            for u in _condition_guards(family.actions[j], self.relevant):
                self.mentions.setdefault(u, []).append(j)
        self.rows: dict[int, tuple[np.ndarray, ...]] = {}
        self.closed = _Closed()
        self.states = np.zeros((0, self.n_words), dtype=np.uint64)
        self.ok = False
        try:
            for j in range(len(family.actions)):
                self.rows[j] = self._variants(j, self.free)
            starts = self._initial_states(self.free)
        except _Blowup:
            return
        # R's own states are not work: they are the model's reachable states, which the proof
        # that it has no plan has just exhausted
        verdict, new_closed, new_states = self._explore(starts, self.rows, self.free, count=False)
        if verdict == Status.UNSOLVABLE:
            self._commit(self.free, self.rows, new_closed, new_states)
            self.ok = True

    # ---------------------------------------------------------------- the may semantics
    def _status(self, g: Guard, free: frozenset[int]) -> int:
        if g is None:
            return _PRESENT
        if g[0] in free:
            return _FREE
        return _PRESENT if (g[0] in self.sel) == g[1] else _ABSENT

    def _mask(self, atoms) -> list[int]:
        return _words(atoms, self.pos, self.n_words)

    def _variants(self, j: int, free: frozenset[int]) -> tuple[np.ndarray, ...]:
        """``(pre, neg, keep, add)`` word arrays, one row per variant of action ``j`` under
        ``free`` (no rows when it cannot be applicable or changes no relevant atom); effects
        on irrelevant atoms are left out."""
        empty = tuple(np.zeros((0, self.n_words), dtype=np.uint64) for _ in range(4))
        a = self.family.actions[j]
        if j not in self.active or self._status(a.exists, free) == _ABSENT:
            return empty
        pre, neg = [], []
        for entries, out, positive in ((a.pre, pre, True), (a.negpre, neg, False)):
            for p, g in entries:
                if self._status(g, free) != _PRESENT:
                    continue  # free conditions are dropped; absent ones do not exist
                if p in self.pos:
                    out.append(p)
                elif (p in self.constant_true) != positive:
                    return empty  # a constant atom the condition can never see
        add = tuple(e for e in a.add if e[0] in self.pos)
        delete = tuple(e for e in a.delete if e[0] in self.pos)
        must_add, must_del, maybe = _effects(add, delete, lambda g: self._status(g, free))
        if 2 ** len(maybe) > MAX_FREE_COMBINATIONS:
            raise _Blowup
        pre_w, neg_w = self._mask(pre), self._mask(neg)
        rows = set()
        for pick in itertools.product((False, True), repeat=len(maybe)):
            adds = set(must_add) | {p for (p, is_add), on in zip(maybe, pick, strict=True)
                                    if on and is_add}  # fmt: skip
            dels = set(must_del) | {p for (p, is_add), on in zip(maybe, pick, strict=True)
                                    if on and not is_add}  # fmt: skip
            keep = [w ^ ((1 << 64) - 1) for w in self._mask(dels)]
            rows.add((*pre_w, *neg_w, *keep, *self._mask(adds)))
        w = self.n_words
        arr = np.array(sorted(rows), dtype=np.uint64).reshape(-1, 4 * w)
        return tuple(np.ascontiguousarray(arr[:, k * w : (k + 1) * w]) for k in range(4))

    def _initial_states(self, free: frozenset[int]) -> np.ndarray:
        sure, maybe = set(), []
        for p, g in self.family.init:
            if p not in self.pos:
                continue
            s = self._status(g, free)
            if s == _PRESENT:
                sure.add(p)
            elif s == _FREE:
                maybe.append(p)
        maybe = sorted(set(maybe) - sure)
        if 2 ** len(maybe) > MAX_FREE_COMBINATIONS:
            raise _Blowup
        states = [
            self._mask(sure | {p for p, on in zip(maybe, pick, strict=True) if on})
            for pick in itertools.product((False, True), repeat=len(maybe))
        ]
        return np.array(states, dtype=np.uint64).reshape(-1, self.n_words)

    def _goal(self, free: frozenset[int]) -> np.ndarray | None:
        """The goal's word mask under ``free`` (its smallest form); ``None`` if a goal atom
        is constant and false, so that no state satisfies it."""
        need = []
        for p, g in self.family.goal:
            if self._status(g, free) != _PRESENT:
                continue
            if p in self.pos:
                need.append(p)
            elif p not in self.constant_true:
                return None
        return np.array(self._mask(need), dtype=np.uint64)

    # ---------------------------------------------------------------- exploration
    @staticmethod
    def _stack(rows: dict[int, tuple[np.ndarray, ...]], which: Iterable[int]):
        parts = [rows[j] for j in which]
        if not parts:
            return None
        return tuple(np.concatenate([p[k] for p in parts]) for k in range(4))

    def _explore(
        self,
        starts: np.ndarray,
        rows,
        free: frozenset[int],
        most: int | None = None,
        count: bool = True,
    ):
        """Exhaust what ``starts`` reach beyond ``R`` under ``free``: ``(verdict, closed,
        states)`` of the new states, ``UNSOLVABLE`` when none satisfies the goal; ``LIMIT``
        past ``most`` new states (or the node or work limit; ``count``: whether they are
        work)."""
        goal = self._goal(free)
        table = self._stack(rows, rows.keys())
        closed = _Closed()
        found: list[np.ndarray] = []
        n_new = 0
        layer = starts
        while len(layer):
            layer = self._unseen(layer, closed)
            keys = state_keys(layer)
            if not len(layer):
                break
            if goal is not None and _at_goal(layer, goal).any():
                return Status.PLAN, None, None
            n_new += len(layer)
            if (
                len(self.states) + n_new > self.node_limit
                or (most is not None and n_new > most)
                or (count and self._spend(len(layer)))
            ):
                return Status.LIMIT, None, None
            closed.add(keys)
            found.append(layer)
            nxt = []
            for succ in _successors_by_chunk(layer, table):
                nxt.append(succ)
                if self.deadline.expired():
                    return Status.TIMEOUT, None, None
            layer = np.concatenate(nxt) if nxt else layer[:0]
        new_states = np.concatenate(found) if found else self.states[:0]
        return Status.UNSOLVABLE, closed, new_states

    def _unseen(self, states: np.ndarray, closed: _Closed | None = None) -> np.ndarray:
        """The distinct rows of ``states`` in neither ``R`` nor ``closed``, in key order (a
        layer's order plays no part in what it reaches; sorted keys keep the closed lists'
        searches cache-friendly)."""
        keys = unique_keys(state_keys(states))
        seen = self.closed.contains(keys)
        if closed is not None:
            seen |= closed.contains(keys)
        return key_rows(keys[~seen], self.n_words)

    def _spend(self, states: int) -> bool:
        """Count ``states`` as visited; whether that passes ``work_limit``."""
        self.work += states
        return self.work_limit is not None and self.work > self.work_limit

    def _commit(self, free, rows, closed: _Closed, new_states: np.ndarray) -> None:
        self.free, self.rows = free, rows
        for level in closed.levels:
            self.closed.add(level)
        # R is searched by every trial's scan and grows only here: one array to search
        self.closed.compact()
        self.states = np.concatenate((self.states, new_states))

    def reached(self) -> set[frozenset[int]]:
        """``R`` as atom sets (on the relevant atoms, constant ones included), for tests and
        debugging."""
        atoms = sorted(self.pos, key=self.pos.__getitem__)
        out = set()
        for row in self.states:
            bits = 0
            for w, word in enumerate(row):
                bits |= int(word) << (64 * w)
            out.add(frozenset(self.constant_true | {p for p in atoms if bits >> self.pos[p] & 1}))
        return out

    def try_free(self, updates: Iterable[int]) -> Status:
        """Free ``updates`` as well, if ``R`` stays goal-free: ``UNSOLVABLE`` (and ``R``
        grows) when it does; ``PLAN`` when some state would satisfy the goal, ``LIMIT`` when
        ``R`` would outgrow ``node_limit``, the trial ``trial_limit``, the work ``work_limit``
        or a variant count its cap, ``TIMEOUT`` at the deadline; then nothing changes."""
        assert self.ok
        free = self.free | frozenset(updates)
        changed = sorted({j for u in free - self.free for j in self.mentions.get(u, ())})
        try:
            rows = dict(self.rows)
            for j in changed:
                rows[j] = self._variants(j, free)
            initial = self._initial_states(free)
        except _Blowup:
            return Status.LIMIT
        goal = self._goal(free)
        if goal is not None and _at_goal(self.states, goal).any():
            return Status.PLAN
        # R is closed under the variants it was grown with: only a variant new to an action
        # can lead out of it
        fresh = {j: _new_rows(self.rows[j], rows[j]) for j in changed}
        table = self._stack(fresh, changed)
        room = self.node_limit - len(self.states)
        most = None
        if self.trial_limit is not None:
            most = max(self.trial_growth * len(self.states), self.trial_limit)
            room = min(room, most)
        if self.work_limit is not None:
            # starts that cannot all be explored within the work left are not explored (nor
            # counted); once the work is spent, the first new state settles a trial, without
            # the successors of the rest of R
            room = min(room, max(self.work_limit - self.work, 0))
        seen, starts = _Closed(), []
        n_starts = 0
        for states in itertools.chain([initial], _successors_by_chunk(self.states, table)):
            new = self._unseen(states, seen)
            if goal is not None and _at_goal(new, goal).any():
                return Status.PLAN
            seen.add(state_keys(new))
            starts.append(new)
            n_starts += len(new)
            if n_starts > room:  # past a limit already: no need to look further
                return Status.LIMIT
        verdict, closed, new_states = self._explore(np.concatenate(starts), rows, free, most)
        if verdict == Status.UNSOLVABLE:
            self._commit(free, rows, closed, new_states)
        return verdict


def _successors_by_chunk(states: np.ndarray, table):
    """The successors of ``states`` under the action rows ``table`` (``None``: no rows), a
    chunk of states at a time."""
    if table is None:
        return
    for lo in range(0, len(states), _CHUNK):
        yield successors(states[lo : lo + _CHUNK], *table)[2]


def _at_goal(states: np.ndarray, goal: np.ndarray) -> np.ndarray:
    return ((states & goal) == goal).all(axis=1)


def _new_rows(old: tuple[np.ndarray, ...], new: tuple[np.ndarray, ...]) -> tuple[np.ndarray, ...]:
    """The variants in ``new`` (an action's ``(pre, neg, keep, add)`` rows) not in ``old``."""
    had = {tuple(r) for r in np.hstack(old).tolist()}
    keep = [i for i, r in enumerate(np.hstack(new).tolist()) if tuple(r) not in had]
    return tuple(part[keep] for part in new)


def _condition_guards(a: GroundAction, relevant: frozenset[int]) -> set[int]:
    """Updates whose freedom changes ``a``'s transitions on the ``relevant`` atoms (its cost
    plays no part here)."""
    out = {a.exists[0]} if a.exists else set()
    for entries in (a.pre, a.negpre):
        out.update(g[0] for _, g in entries if g)
    for entries in (a.add, a.delete):
        out.update(g[0] for p, g in entries if g and p in relevant)
    return out


def _effects(add: tuple[Entry, ...], delete: tuple[Entry, ...], status):
    """``(must_add, must_delete, maybe)``: the effects present for sure, and the free ones as
    ``(atom, is_add)`` pairs."""
    must_add, must_del, maybe = set(), set(), []
    for entries, must, is_add in ((add, must_add, True), (delete, must_del, False)):
        for p, g in entries:
            s = status(g)
            if s == _PRESENT:
                must.add(p)
            elif s == _FREE:
                maybe.append((p, is_add))
    # a free effect the action has for sure anyway changes nothing
    maybe = [(p, is_add) for p, is_add in maybe if p not in (must_add if is_add else must_del)]
    return must_add, must_del, sorted(set(maybe))
