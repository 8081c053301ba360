"""One STRIPS task that over-approximates every model agreeing with a selection on some updates.

Learned clauses generalise a failure of the candidate ``human + E`` to every selection ``E'``
that agrees with ``E`` on a set ``fixed`` of updates.  To *prove* that a failure generalises,
we search once in a single task whose behaviours include those of every such ``E'``:

* each atom ``p`` becomes two facts, ``T_p`` ("p may be true", id ``p``) and ``F_p`` ("p may be
  false", id ``n + p``); a concrete state ``s`` is the fact set ``{T_p : p in s} ∪ {F_p : p not
  in s}``;
* a component whose update is fixed is present or absent exactly as in ``human + E``; one whose
  update is free is present or absent, whichever lets more happen: a free precondition or goal
  is dropped, a free add effect or initial atom may happen (its fact is added), a free delete
  may happen (``F_p`` is added) but need not (``T_p`` is kept), a free action may exist, and an
  action costs the least of its possible cost cases;
* preconditions ``p`` / ``not p`` become positive conditions on ``T_p`` / ``F_p``.

The result has no negative preconditions, and each of its states contains the fact set of the
corresponding concrete state of every agreeing model (induction over a plan: every applicable
concrete action is applicable abstractly, and the abstract successor contains the concrete
one).  So a plan of any agreeing model at cost ``c`` is an abstract plan at cost ``<= c``; "no
abstract plan (within a bound)" is a proof for all of them.  With ``fixed`` = every update the
abstraction is ``human + E`` itself, in the two-fact form.
"""

from __future__ import annotations

from collections.abc import Iterable

from mega_sat.ground.family import GroundFamily, GroundTask, Guard, StripsAction


def abstract_task(
    family: GroundFamily, selection: frozenset[int], fixed: Iterable[int]
) -> GroundTask:
    """The two-fact over-approximation of every ``human + E'`` with ``E'`` agreeing with
    ``selection`` on ``fixed`` (see the module docstring)."""
    sel = frozenset(selection)
    fix = frozenset(fixed)
    n = len(family.atoms)

    def must(g: Guard) -> bool:
        return g is None or (g[0] in fix and (g[0] in sel) == g[1])

    def may(g: Guard) -> bool:
        return g is None or g[0] not in fix or (g[0] in sel) == g[1]

    init: set[int] = set()
    init_must: set[int] = set()
    for p, g in family.init:
        if may(g):
            init.add(p)
        if must(g):
            init_must.add(p)
    init.update(n + p for p in range(n) if p not in init_must)

    actions = []
    for j, a in enumerate(family.actions):
        if not may(a.exists):
            continue
        pre = {p for p, g in a.pre if must(g)} | {n + p for p, g in a.negpre if must(g)}
        add_may = {p for p, g in a.add if may(g)}
        add_must = {p for p, g in a.add if must(g)}
        del_may = {p for p, g in a.delete if may(g)}
        del_must = {p for p, g in a.delete if must(g)}
        adds = set(add_may)
        adds.update(n + p for p in del_may - add_must)
        dels = {p for p in del_must if p not in add_may}
        dels.update(n + p for p in add_must)
        cost = min(v for guards, v in a.cost if all(may(g) for g in guards))
        actions.append(
            StripsAction(
                j, a.name, a.args, frozenset(pre), frozenset(), frozenset(adds), frozenset(dels),
                cost,
            )
        )  # fmt: skip
    goal = frozenset(p for p, g in family.goal if must(g))
    atoms = tuple(family.atoms) + tuple(("not", *atom) for atom in family.atoms)
    return GroundTask(atoms, tuple(actions), frozenset(init), goal)
