"""The delete relaxation of a ground task: h^max and LM-cut (Helmert & Domshlak 2009).

States are ``int`` bitmasks over atom ids; :func:`bits` lists the atoms of one.  The built-in
planner, the operator-counting bounds and the relaxed proofs of the oracles all evaluate the
same :class:`RelaxedTask`.
"""

from __future__ import annotations

import heapq
from collections.abc import Iterable, Sequence

from mega_sat.ground.family import GroundTask

_INF = float("inf")


def bits(s: int) -> list[int]:
    out = []
    while s:
        low = s & -s
        out.append(low.bit_length() - 1)
        s ^= low
    return out


class RelaxedTask:
    """The delete-relaxation of a ground task with the usual LM-cut normalisation: an
    artificial atom ``true`` (precondition of actions without preconditions) and an
    artificial goal action (precondition = goal, adds ``goal``, cost 0).

    Add effects on atoms that are neither a precondition nor a goal are dropped: they cannot
    change h^max of the goal or any LM-cut landmark, and skipping them makes every evaluation
    cheaper (half the facts of a two-fact abstraction are such atoms).

    Static atoms (initially true, deleted by no action, needed) are most preconditions of
    typical ground tasks. In a state that holds them all, h^max visits them without counting
    them one precondition at a time, with the same values and the same choice function
    (see :meth:`hmax`)."""

    def __init__(self, task: GroundTask):
        n = len(task.atoms)
        self.true_atom, self.goal_atom = n, n + 1
        self.n_atoms = n + 2
        needed = set(task.goal).union(*(a.pre for a in task.actions))
        self.needed = [p in needed for p in range(n)] + [True, True]
        pres: list[tuple[int, ...]] = []
        adds: list[tuple[int, ...]] = []
        costs: list[int] = []
        for a in task.actions:
            pres.append(tuple(sorted(a.pre)) or (self.true_atom,))
            adds.append(tuple(sorted(q for q in a.add if q in needed)))
            costs.append(a.cost)
        pres.append(tuple(sorted(task.goal)) or (self.true_atom,))
        adds.append((self.goal_atom,))
        costs.append(0)
        self.pres, self.adds, self.costs = pres, adds, costs
        self.n_pre = [len(p) for p in pres]
        self.pre_of: list[list[int]] = [[] for _ in range(self.n_atoms)]
        self.achievers: list[list[int]] = [[] for _ in range(self.n_atoms)]
        for j, (p, ad) in enumerate(zip(pres, adds, strict=True)):
            for q in p:
                self.pre_of[q].append(j)
            for q in ad:
                self.achievers[q].append(j)
        # heap entries are ints (h << shift) | atom: ordered as the pairs (h, atom)
        self._shift = max(1, self.n_atoms.bit_length())
        deleted = set().union(*(a.delete for a in task.actions))
        static = sorted(p for p in task.init if p not in deleted and p in needed)
        self._static, self._static_set = static, frozenset(static)
        self._general = _Counting(self, ())
        self._with_static = _Counting(self, static)

    def _counting(self, state: list[int]) -> _Counting:
        return self._with_static if self._static_set.issubset(state) else self._general

    def hmax(
        self, state: list[int], costs: list[int], *, stop_at_goal: bool = False
    ) -> tuple[list[float], list[int]]:
        """h^max of every atom from ``state`` and the precondition choice function (the
        precondition popped last from the queue of pairs (h^max, atom), i.e. one with maximal
        h^max; -1 if unreachable).

        ``stop_at_goal`` stops once the goal's value is final: enough for the value, but the
        choice function is then partial, and LM-cut needs it for *every* reachable action (an
        action left out of the justification graph would be missing from its cut, which would
        then not be a landmark and the heuristic not admissible)."""
        return self._hmax(state, costs, stop_at_goal, self._counting(state))

    def _hmax(
        self, state: list[int], costs: list[int], stop_at_goal: bool, counting: _Counting
    ) -> tuple[list[float], list[int]]:
        # Static atoms stay out of the queue: all start at 0, so the queue would pop them in
        # ascending order, each before any pair greater than it. They are merged in that order
        # instead, and an action counts its static preconditions as one, the greatest (the
        # last of them popped); the pops, the values and the choice function stay the same.
        shift = self._shift
        mask = (1 << shift) - 1
        h: list[float] = [_INF] * self.n_atoms
        left = counting.left[:]
        pcf = [-1] * len(self.pres)
        static = counting.static
        is_static, needed = counting.is_static, self.needed
        heap = [p for p in state if needed[p] and not is_static[p]]
        heap.append(self.true_atom)
        for p in heap:
            h[p] = 0
        for p in static:
            h[p] = 0
        heapq.heapify(heap)
        pre_of, adds = counting.pre_of, self.adds
        goal = self.goal_atom
        pop, push = heapq.heappop, heapq.heappush
        i, n_static = 0, len(static)
        while heap or i < n_static:
            if i < n_static and (not heap or static[i] < heap[0]):
                p, d = static[i], 0
                i += 1
            else:
                x = pop(heap)
                p, d = x & mask, x >> shift
                if d != h[p]:  # a stale pair: p was popped at a lower value
                    continue
                if p == goal and stop_at_goal:
                    break
            for j in pre_of[p]:
                k = left[j] - 1
                left[j] = k
                if k == 0:
                    pcf[j] = p
                    c = d + costs[j]
                    for q in adds[j]:
                        if c < h[q]:
                            h[q] = c
                            push(heap, (c << shift) | q)
        return h, pcf

    def h_max(self, state: list[int]) -> float:
        return self.hmax(state, self.costs, stop_at_goal=True)[0][self.goal_atom]

    def h_add(self, state: Iterable[int]) -> float:
        """h_add of the goal from ``state``: as h^max, but an action's precondition costs the
        sum of its atoms' values, so the goal costs the sum over the goal atoms (infinite when
        one is unreachable).  Not admissible: a guide for greedy search
        (:mod:`mega_sat.search.greedy`)."""
        shift = self._shift
        mask = (1 << shift) - 1
        h: list[float] = [_INF] * self.n_atoms
        counting = self._general
        left, pre_of = counting.left[:], counting.pre_of
        spent = [0] * len(self.pres)
        heap = [p for p in state if self.needed[p]]
        heap.append(self.true_atom)
        for p in heap:
            h[p] = 0
        heapq.heapify(heap)
        adds, costs = self.adds, self.costs
        while heap:
            x = heapq.heappop(heap)
            p, d = x & mask, x >> shift
            if d != h[p]:  # a stale pair: p was popped at a lower value
                continue
            for j in pre_of[p]:
                spent[j] += d
                left[j] -= 1
                if left[j] == 0:
                    c = spent[j] + costs[j]
                    for q in adds[j]:
                        if c < h[q]:
                            h[q] = c
                            heapq.heappush(heap, (c << shift) | q)
        return h[self.goal_atom]

    def lmcut(self, state: list[int], cuts: list[list[int]] | None = None) -> float:
        """LM-cut: repeatedly find a cut between the initial atoms and the zero-cost goal zone
        of the justification graph, add its minimum cost and reduce it to zero.

        Each cut is a disjunctive action landmark (every plan from ``state`` uses one of its
        actions); with ``cuts`` given they are appended to it, as lists of action indices
        (the artificial goal action left out)."""
        counting = self._counting(state)
        costs = self.costs[:]
        total = 0
        goal, n = self.goal_atom, self.n_atoms
        adds, achievers = self.adds, self.achievers
        # the actions whose choice can be p: those p is counted for (ascending, as pre_of)
        justified = counting.pre_of
        while True:
            h, pcf = self._hmax(state, costs, False, counting)
            if h[goal] == _INF:
                return _INF
            if h[goal] == 0:
                return total
            zone = [False] * n
            zone[goal] = True
            stack = [goal]
            while stack:
                q = stack.pop()
                for j in achievers[q]:
                    p = pcf[j]
                    if p >= 0 and costs[j] == 0 and not zone[p]:
                        zone[p] = True
                        stack.append(p)
            reached = [False] * n
            stack = [self.true_atom, *state]
            for p in stack:
                reached[p] = True
            cut: list[int] = []
            while stack:
                p = stack.pop()
                for j in justified[p]:
                    if pcf[j] != p:
                        continue
                    in_cut = False
                    for q in adds[j]:
                        if zone[q]:
                            in_cut = True
                        elif not reached[q]:
                            reached[q] = True
                            stack.append(q)
                    if in_cut:
                        cut.append(j)
            m = min(costs[j] for j in cut)
            assert m > 0, "LM-cut found a zero-cost cut"
            if cuts is not None:
                cuts.append([j for j in cut if j != len(self.pres) - 1])
            total += m
            for j in cut:
                costs[j] -= m


class _Counting:
    """How h^max counts the preconditions of ``relaxed``'s actions when the atoms
    ``static`` (ascending) hold in the state: each action counts its other preconditions
    and, if it has any in ``static``, one more for the greatest of them.  ``pre_of[p]``
    lists, ascending, the actions ``p`` is counted for."""

    def __init__(self, relaxed: RelaxedTask, static: Sequence[int]):
        n = relaxed.n_atoms
        self.static = list(static)
        self.is_static = [False] * n
        for p in static:
            self.is_static[p] = True
        pre_of: list[list[int]] = [[] for _ in range(n)]
        self.left: list[int] = []
        for j, pre in enumerate(relaxed.pres):
            own = [q for q in pre if not self.is_static[q]]
            given = [q for q in pre if self.is_static[q]]
            for q in own:
                pre_of[q].append(j)
            if given:
                pre_of[max(given)].append(j)
            self.left.append(len(own) + (1 if given else 0))
        self.pre_of = [tuple(js) for js in pre_of]
