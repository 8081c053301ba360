"""Ground atom ids looked up for every grounding of a schema at once (numpy).

Grounding spends its time turning each lifted atom of each ground action into an atom id.  A
schema with many typed parameters has tens of thousands of groundings, so this module does the
lookup per lifted atom over all groundings at once: objects become integers, every predicate
gets a dense array from argument indices to atom ids (-1: not an atom of the family yet), and
one fancy-indexing call grounds a lifted atom for a whole block of actions.

The result is the same as grounding action by action (:func:`mega_sat.ground.grounding._entries`):
the same ids, fresh ids for unknown preconditions given in the same order, the same merged
entries.  Where the dense array would be too large (a predicate of high arity over many
objects) or an atom has an argument that is not an object, the caller falls back to the
per-action path.
"""

from __future__ import annotations

import operator
from collections.abc import Sequence
from itertools import chain, compress

import numpy as np

from mega_sat.ground.family import Entry, Guard
from mega_sat.model.lifted import Atom

MAX_TABLE_CELLS = 4_000_000
"""Largest dense id array of one predicate (objects ** arity cells, 4 bytes each)."""

LiftedPart = tuple[tuple[Atom, Guard], ...]
"""The guarded lifted atoms of one schema component (preconditions, adds, ...)."""


def object_indices(
    rows: Sequence[tuple[str, ...]], index: dict[str, int], width: int | None = None
) -> np.ndarray | None:
    """``rows`` of object names as a matrix of object indices (None if a name is no object)."""
    width = len(rows[0]) if width is None else width
    try:
        flat = np.fromiter(
            map(index.__getitem__, chain.from_iterable(rows)),
            dtype=np.int64,
            count=len(rows) * width,
        )
    except KeyError:
        return None
    return flat.reshape(len(rows), width)


class AtomTable:
    """Atom ids by predicate and object indices; shares and extends the caller's id dict.

    Every atom over objects also has a *key*, an integer unique to it (the predicate's offset
    plus the flat index of its arguments), so unknown atoms can be numbered in bulk.
    """

    def __init__(self, ids: dict[Atom, int], objects: Sequence[str]):
        self.ids = ids
        self.objects = list(objects)
        self.index = {o: k for k, o in enumerate(objects)}
        self.n = len(objects)
        self._tables: dict[tuple[str, int], np.ndarray | None] = {}
        self._offsets: dict[tuple[str, int], int] = {}
        self._by_offset: list[tuple[int, str, int]] = []
        self._next_offset = 0

    def forget(self) -> None:
        """Drop the id arrays (after ``ids`` grew elsewhere); they are rebuilt on next use."""
        self._tables.clear()

    def _table(self, pred: str, arity: int) -> np.ndarray | None:
        key = (pred, arity)
        if key not in self._tables:
            if self.n**arity > MAX_TABLE_CELLS:
                self._tables[key] = None
            else:
                t = np.full((self.n,) * arity, -1, dtype=np.int64)
                for atom, i in self.ids.items():
                    if atom[0] == pred and len(atom) == arity + 1:
                        idx = [self.index.get(x) for x in atom[1:]]
                        if None not in idx:
                            t[tuple(idx)] = i
                self._tables[key] = t
            if key not in self._offsets:
                self._offsets[key] = self._next_offset
                self._by_offset.append((self._next_offset, pred, arity))
                self._next_offset += self.n**arity
        return self._tables[key]

    def _atom(self, key: int) -> Atom:
        """The atom of a key (inverse of the keys :meth:`lookup` gives)."""
        offset, pred, arity = max(o for o in self._by_offset if o[0] <= key)
        idx = np.unravel_index(key - offset, (self.n,) * arity) if arity else ()
        return (pred, *(self.objects[int(k)] for k in idx))

    def _fresh(self, atom: Atom) -> int:
        """The id of ``atom``, giving it the next free id if the family has none for it yet."""
        i = self.ids.get(atom)
        if i is None:
            i = self.ids[atom] = len(self.ids)
            t = self._tables.get((atom[0], len(atom) - 1))
            if t is not None:
                t[tuple(self.index[x] for x in atom[1:])] = i
        return i

    def lookup(
        self, lifted: LiftedPart, params: tuple[str, ...], args: np.ndarray
    ) -> tuple[np.ndarray, np.ndarray] | None:
        """Atom ids and keys of every lifted atom (columns) for every grounding (rows of
        ``args``, object indices per parameter); id -1 where the family has no such atom yet.
        None: not vectorisable (an argument that is no object, or a table too large)."""
        pos = {p: k for k, p in enumerate(params)}
        ids = np.empty((args.shape[0], len(lifted)), dtype=np.int64)
        keys = np.empty_like(ids)
        for j, (atom, _) in enumerate(lifted):
            arity = len(atom) - 1
            table = self._table(atom[0], arity)
            if table is None:
                return None
            cols = []
            for x in atom[1:]:
                if x in pos:
                    cols.append(args[:, pos[x]])
                elif x in self.index:
                    cols.append(np.full(args.shape[0], self.index[x], dtype=np.int64))
                else:
                    return None
            offset = self._offsets[(atom[0], arity)]
            if cols:
                ids[:, j] = table[tuple(cols)]
                keys[:, j] = offset + np.ravel_multi_index(cols, (self.n,) * arity)
            else:
                ids[:, j] = table[()]
                keys[:, j] = offset
        return ids, keys

    def ground_block(
        self,
        parts: tuple[LiftedPart, LiftedPart, LiftedPart, LiftedPart],
        params: tuple[str, ...],
        arg_rows: Sequence[tuple[str, ...]],
    ) -> list[tuple[tuple[Entry, ...], ...]] | None:
        """Entries ``(pre, negpre, add, delete)`` of each grounding in ``arg_rows`` (in order).

        Unknown atoms get fresh ids when they are preconditions or adds (in the order of the
        per-action path: action by action, preconditions before adds) and are dropped from
        negative preconditions and deletes.  None when some part is not vectorisable.
        """
        if not arg_rows:
            return []
        args = object_indices(arg_rows, self.index, len(params))
        if args is None:
            return None
        found = []
        for part in parts:
            r = self.lookup(part, params, args)
            if r is None:
                return None
            found.append(r)
        (pre, pre_k), (negpre, negpre_k), (add, add_k), (delete, delete_k) = found
        n_pre = pre.shape[1]
        # fresh ids, in the per-action order: action by action, preconditions (phase 0) before
        # negative preconditions (1), adds (2) and deletes (3)
        kept, kept_k = np.hstack([pre, add]), np.hstack([pre_k, add_k])
        rows, cols = np.nonzero(kept < 0)  # row-major: the per-action order
        if len(rows):
            keys = kept_k[rows, cols]
            uniq, first = np.unique(keys, return_index=True)
            new_ids = np.empty(len(uniq), dtype=np.int64)
            for u in np.argsort(first, kind="stable").tolist():
                new_ids[u] = self._fresh(self._atom(int(uniq[u])))
            kept[rows, cols] = new_ids[np.searchsorted(uniq, keys)]
            pre, add = kept[:, :n_pre], kept[:, n_pre:]
            # where it came first: 4 * action + phase
            first_at = 4 * rows[first] + np.where(cols[first] < n_pre, 0, 2)
            # a negative precondition or delete of an atom numbered earlier in that order keeps
            # it, as in the per-action path
            for m, mk, phase in ((negpre, negpre_k, 1), (delete, delete_k, 3)):
                r2, c2 = np.nonzero(m < 0)
                if not len(r2):
                    continue
                k2 = mk[r2, c2]
                at = np.minimum(np.searchsorted(uniq, k2), len(uniq) - 1)
                hit = (uniq[at] == k2) & (first_at[at] < 4 * r2 + phase)
                m[r2[hit], c2[hit]] = new_ids[at[hit]]
        per_part = [
            _component_entries(m, part, drop)
            for m, part, drop in zip((pre, negpre, add, delete), parts, DROPS, strict=True)
        ]
        return list(zip(*per_part, strict=True))


DROPS = (False, True, False, True)
"""Per component (pre, negpre, add, delete): whether atoms unknown to the family are dropped."""

_PLAIN, _DROP, _MERGE = 0, 1, 2
"""How a row's entries are built: every lifted atom one entry; some entries dropped (unknown
atoms, or repeats of an equal entry); merged by :func:`_builder` (a repeat with another guard)."""


def _component_entries(
    m: np.ndarray, part: LiftedPart, drop_unknown: bool
) -> list[tuple[Entry, ...]]:
    """Entries of one component for every row of atom ids in ``m``.

    Two lifted atoms of one predicate may ground to the same atom.  With equal guards the
    later entry is a repeat and is dropped; with different guards the row is merged entry by
    entry (:func:`_builder`), as the per-action path does.  Unknown atoms (-1) are dropped
    where ``drop_unknown``."""
    guards = [g for _, g in part]
    keep = np.ones(m.shape, dtype=bool)
    merge = np.zeros(m.shape[0], dtype=bool)
    for a in range(len(part)):
        for b in range(a + 1, len(part)):
            if part[a][0][0] == part[b][0][0] and len(part[a][0]) == len(part[b][0]):
                same = m[:, a] == m[:, b]
                if part[a][1] == part[b][1]:
                    keep[:, b] &= ~same
                else:
                    merge |= same
    if drop_unknown:
        keep &= m >= 0
    rows = m.tolist()
    # one shared entry object per (column, atom): no tuple is built per action, and the
    # family holds each distinct entry once
    getters = [
        {i: (i, g) for i in np.unique(m[:, j]).tolist()}.__getitem__ for j, g in enumerate(guards)
    ]
    if not merge.any() and keep.all():
        return [tuple(map(_call, getters, r)) for r in rows]
    kind = np.where(merge, _MERGE, np.where(keep.all(axis=1), _PLAIN, _DROP)).tolist()
    merged = _builder(part)
    out: list[tuple[Entry, ...]] = []
    for r, kd, kp in zip(rows, kind, keep.tolist(), strict=True):
        if kd == _PLAIN:
            out.append(tuple(map(_call, getters, r)))
        elif kd == _DROP:
            out.append(tuple(compress(map(_call, getters, r), kp)))
        else:
            out.append(merged(r))
    return out


def _call_py(f, x):
    return f(x)


_call = getattr(operator, "call", _call_py)  # operator.call is C-level (Python >= 3.11)


def _builder(part: LiftedPart):
    """Entries of one component from one row of atom ids, merged like the per-action path."""
    guards = [g for _, g in part]

    from mega_sat.ground.grounding import merge_guards

    def merged(row: list[int]) -> tuple[Entry, ...]:
        out: dict[int, list[Guard]] = {}
        for i, g in zip(row, guards, strict=True):
            if i >= 0:
                out.setdefault(i, []).append(g)
        return merge_guards(out)

    return merged
