"""State invariants and reachability layers that hold in a set of family members.

SAT planners prove "no plan within the bounds" much faster when the formula also states what
every reachable state satisfies (Rintanen's invariants): without them the solver must rediscover,
by conflicts, that a hand holds one thing at a time or a robot is at one place.  Both facts here
are computed on the two-fact abstraction (:mod:`mega_sat.analysis.abstraction`), whose states contain
those of every model it over-approximates, so they hold in *every* state reachable in any such
model and adding them as clauses removes no plan of any of them:

* **mutex pairs** (h^2, :mod:`mega_sat.analysis.pair_reachability`): two abstract facts never true
  together.  With ``T_p`` read as ``x_p`` and ``F_p`` as ``not x_p`` each gives a binary clause
  (``not p or not q``, ``p -> q`` or ``p or q``);
* **layers** (h^1 with unit costs): the first step at which an abstract fact can hold; before it
  ``x_p`` is false (``T_p``) or true (``F_p``), and an action whose certain preconditions are not
  all reached yet cannot run.

For the human copy of an encoding (which must serve every selection, since UNSAT cores over
selectors are read off it) the abstraction leaves every update free; for the robot copy it fixes
every update (the robot model itself).
"""

from __future__ import annotations

from collections.abc import Iterable
from dataclasses import dataclass, field
from functools import cached_property

from mega_sat.analysis.abstraction import abstract_task
from mega_sat.analysis.pair_reachability import pair_masks
from mega_sat.ground.family import GroundFamily, GroundTask

NEVER = 1 << 30


@dataclass(frozen=True)
class Invariants:
    """Clauses valid in every reachable state of the members covered.

    ``binary``: pairs of state literals ``(±(p+1), ±(q+1))`` (atom ids shifted by one, sign =
    truth), each a clause ``l1 or l2`` over the same step; ``true_from[p]`` / ``false_from[p]``:
    first step at which ``p`` may be true / false (``NEVER``: at no step); ``action_from[j]``:
    first step at which family action ``j`` may run.
    """

    binary: tuple[tuple[int, int], ...]
    true_from: tuple[int, ...]
    false_from: tuple[int, ...]
    action_from: tuple[int, ...]

    def fixed_at(self, t: int) -> Iterable[int]:
        """State literals forced at step ``t`` by the layers (``p+1``: true, ``-(p+1)``: false)."""
        for p, (tf, ff) in enumerate(zip(self.true_from, self.false_from, strict=True)):
            if tf > t:
                yield -(p + 1)
            elif ff > t:
                yield p + 1


def family_invariants(
    family: GroundFamily,
    selection: frozenset[int] = frozenset(),
    fixed: Iterable[int] = (),
    *,
    task: GroundTask | None = None,
    seed: list[int] | None = None,
) -> Invariants:
    """Invariants of every ``human + E'`` with ``E'`` agreeing with ``selection`` on ``fixed``
    (default: every model of the family); ``task``: that abstraction, if already built;
    ``seed``: pair masks of a task it relaxes (:func:`pair_masks`), to reach the same
    fixpoint in fewer rounds."""
    if task is None:
        task = abstract_task(family, frozenset(selection), fixed)
    n = len(family.atoms)
    masks = pair_masks(task, seed)
    layer = _unit_layers(task)
    # atoms whose value can never change need no mutex clauses: frame axioms carry them
    changing = [False] * n
    for a in family.actions:
        for p, _ in a.add + a.delete:
            changing[p] = True
    reach = [bool((masks[f] >> f) & 1) for f in range(2 * n)]

    def lit(f: int) -> int:
        return f + 1 if f < n else -(f - n + 1)

    binary: list[tuple[int, int]] = []
    usable = 0  # reachable facts of atoms that can change
    for f in range(2 * n):
        if reach[f] and changing[f % n]:
            usable |= 1 << f
    for f in range(2 * n):
        if not (usable >> f) & 1:
            continue
        # partners g > f, not the same atom, never reachable together with f
        other = usable & ~masks[f] & ~((1 << (f + 1)) - 1) & ~(1 << ((f + n) % (2 * n)))
        while other:
            low = other & -other
            g = low.bit_length() - 1
            binary.append((-lit(f), -lit(g)))
            other ^= low
    true_from = tuple(layer[p] if reach[p] else NEVER for p in range(n))
    false_from = tuple(layer[n + p] if reach[n + p] else NEVER for p in range(n))
    action_from = [NEVER] * len(family.actions)
    for a in task.actions:
        if all(reach[p] for p in a.pre) and not any(
            not (masks[p] >> q) & 1 for p in a.pre for q in a.pre
        ):
            action_from[a.index] = max((layer[p] for p in a.pre), default=0)
    return Invariants(tuple(binary), true_from, false_from, tuple(action_from))


def _unit_layers(task) -> list[int]:
    """First step at which each fact of ``task`` is relaxed-reachable (unit costs)."""
    layer = [NEVER] * len(task.atoms)
    frontier = list(task.init)
    for p in frontier:
        layer[p] = 0
    t = 0
    pending = list(task.actions)
    while frontier:
        t += 1
        new: list[int] = []
        rest = []
        for a in pending:
            if all(layer[p] < t for p in a.pre):
                for q in a.add:
                    if layer[q] == NEVER:
                        layer[q] = t
                        new.append(q)
            else:
                rest.append(a)
        pending = rest
        frontier = new
    return layer


def steps_to_goal(family: GroundFamily) -> tuple[int, ...]:
    """``k[j]``: the fewest steps, counting its own, from action ``j`` to the end of a plan in
    which ``j`` is needed (``NEVER``: no plan needs ``j``, it is *irrelevant*).

    Backward layers over the union of every guarded component: the last action of a plan must
    add a goal atom; an action ``k`` steps from the end must add a kept atom (goal, or
    precondition of an action ``< k`` steps from the end) or delete an avoided one (negative
    precondition of such an action).  Removing from a plan, one at a time, every action whose
    removal leaves it valid in every model it was valid in keeps it valid, no costlier and no
    longer; in the result each action is needed by a later one or by the goal, so it is within
    these layers (induction from the end).  So "action ``j`` at step ``t`` of a plan whose goal
    holds after ``h`` steps" only when ``h - t >= k[j]``.
    """
    n_act = len(family.actions)
    k = [NEVER] * n_act
    keep = {p for p, _ in family.goal}
    avoid: set[int] = set()
    layer = 0
    while True:
        layer += 1
        new = [
            j
            for j, a in enumerate(family.actions)
            if k[j] == NEVER
            and (any(p in keep for p, _ in a.add) or any(p in avoid for p, _ in a.delete))
        ]
        if not new:
            return tuple(k)
        for j in new:
            k[j] = layer
            keep.update(p for p, _ in family.actions[j].pre)
            avoid.update(p for p, _ in family.actions[j].negpre)


GuardedPair = tuple[int, int, int]
"""``(guard, l1, l2)``: the clause ``-guard or l1 or l2``, ``guard`` a selector literal
(``i+1`` for "update i selected", ``-(i+1)`` for "not selected")."""


def guarded_mutexes(
    family: GroundFamily, base: Invariants, max_updates: int = 64
) -> tuple[GuardedPair, ...]:
    """Mutexes that hold in every model with one update fixed (``i`` selected or not) and are
    not already in ``base``, as clauses guarded by that selector literal.  Valid for every
    selection (the guard is false in the others), so UNSAT cores over selectors stay sound.
    Skipped above ``max_updates`` updates (up to two h^2 computations per update)."""
    if family.n_updates > max_updates:
        return ()
    have = set(base.binary)
    out: list[GuardedPair] = []
    # fixing an update to the value its free abstraction already takes (a precondition
    # absent, an action present) gives the same task, hence the same mutexes as ``base``:
    # one of the two values on every update of barman-bar/p3 and rover-martian/p3
    free = abstract_task(family, frozenset(), ())
    # fixing one update relaxes the model that fixes every update to the same value (each
    # other update becomes free), so that model's pairs start the fixpoint: no update
    # selected for the value False, every update selected (the robot model) for True
    everything = range(family.n_updates)
    seeds: dict[bool, list[int]] = {}
    for i in everything:
        for v in (False, True):
            sel = frozenset([i]) if v else frozenset()
            task = abstract_task(family, sel, [i])
            if task == free:
                continue
            if v not in seeds:
                seeds[v] = pair_masks(
                    abstract_task(family, frozenset(everything) if v else frozenset(), everything)
                )
            inv = family_invariants(family, sel, [i], task=task, seed=seeds[v])
            guard = i + 1 if v else -(i + 1)
            out.extend((guard, l1, l2) for l1, l2 in inv.binary if (l1, l2) not in have)
    return tuple(out)


@dataclass(frozen=True)
class EncodingFacts:
    """Everything the encoding adds beyond the plain clause schemas, computed once per family
    (both oracle encodings share it): invariants per state copy, guarded mutexes of the human
    copy, and the backward layers.

    The guarded mutexes cost up to two h^2 computations per update, more than the rest
    together on large model differences, so they are computed on first use
    (:attr:`guarded`); the encoding asks for them only once it has more than a few steps."""

    human: Invariants
    robot: Invariants
    to_goal: tuple[int, ...]
    family: GroundFamily = field(repr=False, compare=False)

    @cached_property
    def guarded(self) -> tuple[GuardedPair, ...]:
        return guarded_mutexes(self.family, self.human)


def encoding_facts(family: GroundFamily) -> EncodingFacts:
    human = family_invariants(family)
    robot = family_invariants(family, family.robot_selection, range(family.n_updates))
    return EncodingFacts(human, robot, steps_to_goal(family), family)
