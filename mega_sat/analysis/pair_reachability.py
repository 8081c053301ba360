"""h^2 reachability: which pairs of facts can ever hold together (Haslum & Geffner 2000).

Relaxed reachability (h^1) ignores deletes, so it cannot see that a goal needs two facts that
no state ever has at once (the robot in two places, a hand holding two things).  h^2 keeps
deletes for pairs: a pair ``{p, q}`` becomes reachable when an action adds both, or adds ``p``
while ``q`` survives it (not deleted, and reachable together with each precondition).  Every
pair true in some reachable state is marked, so a goal pair left unmarked proves the task
unsolvable.  Used on abstractions (:mod:`mega_sat.analysis.abstraction`: no negative preconditions, and
a proof there holds for every model they over-approximate).
"""

from __future__ import annotations

from collections import OrderedDict

from mega_sat.ground.family import GroundTask

KEEP_FIXPOINTS = 32
"""How many pair fixpoints :func:`pair_masks` keeps (the most recently asked for)."""
KEEP_BITS = 1 << 27
"""At most this many mask bits (16 MiB) kept in all: a fixpoint of ``n`` facts is ``n * n``
bits, so on large tasks fewer are kept, and one larger than this none."""


class _Kept:
    """The fixpoints :func:`pair_masks` keeps, least recently asked for first, within
    :data:`KEEP_FIXPOINTS` and :data:`KEEP_BITS`."""

    def __init__(self) -> None:
        self.masks: OrderedDict[tuple, tuple[int, ...]] = OrderedDict()
        self.bits = 0

    @staticmethod
    def size(key: tuple) -> int:
        return key[0] * key[0]

    def get(self, key: tuple) -> tuple[int, ...] | None:
        got = self.masks.get(key)
        if got is not None:
            self.masks.move_to_end(key)
        return got

    def put(self, key: tuple, masks: tuple[int, ...]) -> None:
        if self.size(key) > KEEP_BITS:
            return
        self.masks[key] = masks
        self.bits += self.size(key)
        while len(self.masks) > KEEP_FIXPOINTS or self.bits > KEEP_BITS:
            old, _ = self.masks.popitem(last=False)
            self.bits -= self.size(old)


_kept = _Kept()


def _mask(ids) -> int:
    m = 0
    for i in ids:
        m |= 1 << i
    return m


def pair_masks(task: GroundTask, seed: list[int] | None = None) -> list[int]:
    """``m[p]``: bitmask of the facts ``q`` with ``{p, q}`` h^2-reachable (bit ``p`` itself set
    iff ``p`` is reachable).  ``task`` must have no negative preconditions.

    ``seed``: pairs known to be reachable here, such as the masks of a task this one relaxes
    (fewer preconditions and deletes, more adds and initial facts); the fixpoint reached from
    them is the same, in fewer rounds.

    The loop asks for the same fixpoint again and again (the same abstraction or product for
    several candidates), so the last few are kept (:data:`KEEP_FIXPOINTS`, :data:`KEEP_BITS`),
    keyed by everything they depend on; not by the seed, which does not change them."""
    if any(a.negpre for a in task.actions):
        raise ValueError("pair reachability needs a task without negative preconditions")
    n = len(task.atoms)
    actions = tuple((a.pre, a.add, a.delete) for a in task.actions)
    key = (n, task.init, actions)
    got = _kept.get(key)
    if got is None:
        got = _fixpoint(n, task.init, actions, seed)
        _kept.put(key, got)
    return list(got)


def _fixpoint(
    n: int,
    init_facts: frozenset[int],
    actions: tuple[tuple[frozenset[int], frozenset[int], frozenset[int]], ...],
    seed: list[int] | None,
) -> tuple[int, ...]:
    init = _mask(init_facts)
    m = [init if (init >> p) & 1 else 0 for p in range(n)]
    if seed is not None:
        m = [a | b for a, b in zip(m, seed, strict=True)]
    acts = [
        (sorted(pre), _mask(pre), sorted(add), _mask(add), _mask(delete))
        for pre, add, delete in actions
    ]
    changed = True
    while changed:
        changed = False
        for pre, pre_m, add, add_m, del_m in acts:
            ok = True
            together = ~0
            for r in pre:
                mr = m[r]
                if mr & pre_m != pre_m:
                    ok = False
                    break
                together &= mr
            if not ok:
                continue
            if not pre:
                together = 0
                for p in range(n):
                    if (m[p] >> p) & 1:
                        together |= 1 << p
            # facts that can hold with every precondition and survive the action
            survive = together & ~del_m & ~add_m
            gain = survive | add_m
            for p in add:
                new = gain & ~m[p]
                if not new:
                    continue
                changed = True
                m[p] |= new
                q_bits = new & ~(1 << p)
                while q_bits:
                    low = q_bits & -q_bits
                    m[low.bit_length() - 1] |= 1 << p
                    q_bits ^= low
    return tuple(m)


def goal_pair_unreachable(task: GroundTask) -> bool:
    """True when some goal fact or pair of goal facts is not h^2-reachable: no plan exists."""
    return not goal_pairs_reached(pair_masks(task), task)


def goal_pairs_reached(m: list[int], task: GroundTask) -> bool:
    """Whether the pair masks ``m`` of ``task`` hold every goal fact and pair of goal facts."""
    goal = _mask(task.goal)
    return all(m[p] & goal == goal for p in task.goal)
