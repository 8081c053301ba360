"""Which way each update moves the human model: toward fewer plans, or toward more.

Model ``M'`` is a *sub-model* of ``M`` (same atoms and family actions) when every plan of
``M'`` is a plan of ``M`` that costs no more there.  That holds when ``M'`` has no more
initial atoms, add effects or actions, no fewer preconditions, delete effects or goals, no
lower costs, and the same initial and effect entries on atoms some negative precondition
tests: by induction over a plan, each state of ``M'`` agrees with the state ``M`` reaches on
those atoms and is a subset of it on the rest (argument in ``encodings/hitting-set.md``,
"Monotone updates").

An update ``i`` is *monotone* when one of its values, ``w``, makes the model a sub-model of the
one with ``not w`` whatever the other updates are; ``w`` is its *restricting* value.  Claims of
the form "no plan (of the robot model, also valid) in ``human + E`` within these cost bounds"
survive moving ``E`` to a sub-model, and claims "this plan runs in ``human + E`` within this
cost" survive moving it to a super-model.  So a core of the first kind never needs a literal
at the relaxing value, and a plan's support never needs one at the restricting value.
"""

from __future__ import annotations

from collections.abc import Iterable

from mega_sat.ground.family import GroundFamily, GuardLit


def restricting_values(family: GroundFamily) -> dict[int, bool]:
    """``{i: w}`` for every monotone update ``i`` with restricting value ``w``."""
    # a present precondition, delete effect or goal restricts; a present initial atom, add
    # effect or action relaxes; but an atom some negative precondition tests may disable an
    # action when it is true, so its initial and effect entries have no direction
    negative = {p for a in family.actions for p, _ in a.negpre}
    direction: dict[int, set[bool]] = {}  # update -> restricting values seen

    def see(guard, present_restricts: bool | None) -> None:
        if guard is None:
            return
        i, v = guard
        if present_restricts is None:
            direction.setdefault(i, set()).update((True, False))
        else:
            direction.setdefault(i, set()).add(v if present_restricts else not v)

    for p, g in family.init:
        see(g, None if p in negative else False)
    for _, g in family.goal:
        see(g, True)
    for a in family.actions:
        see(a.exists, False)
        for _, g in a.pre:
            see(g, True)
        for _, g in a.negpre:
            see(g, True)
        for p, g in a.add:
            see(g, None if p in negative else False)
        for p, g in a.delete:
            see(g, None if p in negative else True)
        _see_costs(a.cost, direction)
    return {i: next(iter(ws)) for i, ws in direction.items() if len(ws) == 1}


def _see_costs(cases, direction: dict[int, set[bool]]) -> None:
    """For each update in a cost guard, the value that never costs less, if one does: two
    cases that differ in ``i`` and may both apply with the other updates equal must order
    their values the same way for every such pair."""
    for guards, value in cases:
        for i, v in guards:
            rest = {j: u for j, u in guards if j != i}
            for guards2, value2 in cases:
                if (i, not v) not in guards2:
                    continue
                if any(rest.get(j, u) != u for j, u in guards2 if j != i):
                    continue  # never both apply with only i flipped
                if value > value2:
                    direction.setdefault(i, set()).add(v)
                elif value < value2:
                    direction.setdefault(i, set()).add(not v)


def split_relaxing(
    lits: Iterable[GuardLit], restricting: dict[int, bool]
) -> tuple[list[GuardLit], list[GuardLit]]:
    """``lits`` in their order, split into those a core of "no plan within bounds" may need
    and those at a relaxing value, which it never needs (see :func:`drop_relaxing`)."""
    need, relaxing = [], []
    for i, v in lits:
        (need if restricting.get(i, v) == v else relaxing).append((i, v))
    return need, relaxing


def drop_relaxing(core: Iterable[GuardLit], restricting: dict[int, bool]) -> frozenset[GuardLit]:
    """The literals of a core of "no plan within bounds" that a proof needs: those at a
    relaxing value may flip to the restricting one, which only removes plans."""
    return frozenset((i, v) for i, v in core if restricting.get(i, v) == v)


def drop_restricting(
    support: Iterable[GuardLit], restricting: dict[int, bool]
) -> frozenset[GuardLit]:
    """The literals of a plan's support that keep it valid within its cost: those at the
    restricting value may flip to the relaxing one, which only adds plans and lowers costs."""
    return frozenset((i, v) for i, v in support if restricting.get(i, not v) != v)
