"""Backward relevance: the part of a ground task that can matter for reaching its goal.

An atom is *relevant* if it is a goal or a (positive or negative) precondition of a relevant
action; an action is relevant if it adds or deletes a relevant atom and its preconditions do
not contradict each other.  Everything else is dropped: irrelevant actions, and every
irrelevant atom from the initial state and the effects.

Why this is exact: an irrelevant action touches no relevant atom, so deleting it from a plan
leaves every relevant atom's history, hence every remaining precondition and the goal, as it
was, and costs are never negative; and a relevant action reads only relevant atoms.  So the
reduced task has a plan exactly when the task has one, with the same optimal cost, and each
of its plans runs unchanged in the task.  Atom ids are kept, so states and plans need no
translation.  Irrelevant atoms multiply the states of an explicit search without changing
its answer (a picture taken of a place no goal mentions, a flag nothing reads): searches that
prove a model unsolvable, or find its optimum, explore the reduced task instead.
"""

from __future__ import annotations

from collections.abc import Iterable

from mega_sat.ground.family import GroundFamily, GroundTask, StripsAction, holds


def _closure(goals: Iterable[int], changers: dict[int, list[int]], conditions) -> frozenset[int]:
    """The fixpoint: ``goals``, plus ``conditions(j)`` of every action ``j`` in
    ``changers[p]`` (the actions that add or delete ``p``) of each atom ``p`` in it."""
    relevant = set(goals)
    todo = list(relevant)
    used: set[int] = set()
    while todo:
        for j in changers.get(todo.pop(), ()):
            if j in used:
                continue
            used.add(j)
            for q in conditions(j):
                if q not in relevant:
                    relevant.add(q)
                    todo.append(q)
    return frozenset(relevant)


def relevant_atoms(task: GroundTask) -> frozenset[int]:
    """The relevant atoms of ``task`` (the fixpoint in the module docstring)."""
    live = [a for a in task.actions if not (a.pre & a.negpre)]
    changers: dict[int, list[int]] = {}
    for j, a in enumerate(live):
        for p in a.add | a.delete:
            changers.setdefault(p, []).append(j)
    return _closure(task.goal, changers, lambda j: live[j].pre | live[j].negpre)


def relevant_part(task: GroundTask) -> GroundTask:
    """``task`` without its irrelevant actions and atoms (same atom ids, same action order);
    ``task`` itself when everything is relevant."""
    keep = relevant_atoms(task)
    acts = []
    changed = False
    for a in task.actions:
        if (a.pre & a.negpre) or not ((a.add | a.delete) & keep):
            changed = True
            continue
        add, delete = a.add & keep, a.delete & keep
        if add != a.add or delete != a.delete:
            changed = True
            a = StripsAction(a.index, a.name, a.args, a.pre, a.negpre, add, delete, a.cost)
        acts.append(a)
    init = task.init & keep
    if not changed and init == task.init:
        return task
    return GroundTask(task.atoms, tuple(acts), init, task.goal)


def may_relevant_atoms(family: GroundFamily, selection: frozenset[int]) -> frozenset[int]:
    """Atoms that can matter in the may semantics of :mod:`mega_sat.search.may_reachability`
    around ``human + selection``, for every free set: the fixpoint above, where a goal or a
    condition counts only if present in ``human + selection`` and an effect (or action) counts
    under any guard.  Freeing an update only drops goals and conditions (a free one is
    dropped) and only adds effects and actions (a free one may happen), so each free set's
    relevant atoms lie inside this set, and projecting its states onto the set keeps every
    verdict."""
    changers: dict[int, list[int]] = {}
    for j, a in enumerate(family.actions):
        for p, _ in (*a.add, *a.delete):
            changers.setdefault(p, []).append(j)

    def conditions(j: int) -> list[int]:
        a = family.actions[j]
        return [q for q, g in (*a.pre, *a.negpre) if holds(g, selection)]

    goals = [p for p, g in family.goal if holds(g, selection)]
    return _closure(goals, changers, conditions)
