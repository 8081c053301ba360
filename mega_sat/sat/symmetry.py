"""Object symmetries of a whole model family, for lex-leader symmetry breaking in SAT.

Two objects are interchangeable when swapping them maps the family onto itself: every ground
action onto a ground action with the same guards, costs and (swapped) components, and the
initial state and goal onto themselves (barman's two hands, for instance).  Then swapping them
in any plan gives a plan of every model with the same costs, and an UNSAT proof would otherwise
have to refute each plan and its mirror image separately.  Each swap ``sigma`` found here lets
the encoding keep only plans ``pi`` with ``pi <=lex sigma(pi)`` (``encodings/sequential.md``).
"""

from __future__ import annotations

from collections import Counter
from dataclasses import dataclass

from mega_sat.ground.family import GroundAction, GroundFamily


@dataclass(frozen=True)
class Swap:
    """The swap of objects ``a`` and ``b`` as a permutation of the family's action indices."""

    a: str
    b: str
    action_perm: tuple[int, ...]

    @property
    def moved(self) -> tuple[int, ...]:
        """Actions the swap does not fix."""
        return tuple(j for j, k in enumerate(self.action_perm) if k != j)


def _swap_atom(atom: tuple[str, ...], a: str, b: str) -> tuple[str, ...]:
    return (atom[0], *(b if x == a else a if x == b else x for x in atom[1:]))


MAX_ACTIONS = 20_000
"""Families with more ground actions are not searched for swaps: each candidate pair costs a
pass over every action, which on such families takes longer than the proofs it shortens.
Symmetry breaking only prunes mirror-image plans, so skipping it changes no answer."""


def object_swaps(
    family: GroundFamily, limit: int = 64, max_actions: int = MAX_ACTIONS
) -> list[Swap]:
    """Every pair of interchangeable objects (at most ``limit`` swaps; none for a family of
    more than ``max_actions`` ground actions)."""
    if len(family.actions) > max_actions:
        return []
    objects = sorted(
        {x for atom in family.atoms for x in atom[1:]} | {x for a in family.actions for x in a.args}
    )
    atom_index = family.atom_index
    action_index = family.action_index
    signature = _signatures(family)
    out: list[Swap] = []
    for i, a in enumerate(objects):
        for b in objects[i + 1 :]:
            if signature[a] != signature[b]:
                continue  # the swap maps some atom, entry or action outside the family
            swap = _check(family, a, b, atom_index, action_index)
            if swap is not None:
                out.append(swap)
                if len(out) >= limit:
                    return out
    return out


def _signatures(family: GroundFamily) -> dict[str, Counter]:
    """Per object, how often it occurs at each argument position of each predicate (in the
    atoms, and in the initial and goal entries with their guards) and of each action name.
    Swapping ``a`` and ``b`` moves ``a``'s occurrences to ``b`` at the same places, so a swap
    that maps the family onto itself needs equal signatures: a check in one pass that spares
    :func:`_check`'s pass over every atom and action for most pairs."""
    sig: dict[str, Counter] = {}

    def count(args, key) -> None:
        for k, x in enumerate(args):
            sig.setdefault(x, Counter())[(*key, k)] += 1

    for atom in family.atoms:
        count(atom[1:], ("atom", atom[0]))
    for part, entries in (("init", family.init), ("goal", family.goal)):
        for p, g in entries:
            atom = family.atoms[p]
            count(atom[1:], (part, atom[0], g))
    for act in family.actions:
        count(act.args, ("action", act.name))
    return sig


def _check(family: GroundFamily, a: str, b: str, atom_index, action_index) -> Swap | None:
    atom_map: list[int] = []
    for atom in family.atoms:
        k = atom_index.get(_swap_atom(atom, a, b))
        if k is None:
            return None
        atom_map.append(k)

    def image(entries) -> frozenset:
        return frozenset((atom_map[p], g) for p, g in entries)

    if image(family.init) != frozenset(family.init) or image(family.goal) != frozenset(family.goal):
        return None
    perm: list[int] = []
    for act in family.actions:
        args = tuple(b if x == a else a if x == b else x for x in act.args)
        k = action_index.get((act.name, *args))
        if k is None or not _same(family.actions[k], act, image):
            return None
        perm.append(k)
    if all(k == j for j, k in enumerate(perm)):
        return None  # the two objects occur in nothing that matters
    return Swap(a, b, tuple(perm))


def _same(img: GroundAction, act: GroundAction, image) -> bool:
    return (
        img.exists == act.exists
        and frozenset(img.cost) == frozenset(act.cost)
        and frozenset(img.pre) == image(act.pre)
        and frozenset(img.negpre) == image(act.negpre)
        and frozenset(img.add) == image(act.add)
        and frozenset(img.delete) == image(act.delete)
    )
