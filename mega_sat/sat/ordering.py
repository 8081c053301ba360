"""Symmetry breaking between steps: lex-leader constraints over object swaps, and the
partial order of independent actions (encodings/sequential.md).  A part of
:class:`~mega_sat.sat.encoding.FamilyEncoding`, kept apart because it only prunes models."""

from __future__ import annotations

from mega_sat.sat.symmetry import Swap


class StepOrdering:
    """The ordering clauses of :class:`~mega_sat.sat.encoding.FamilyEncoding`."""

    def _lex_step(self, sw: Swap, lex: list[int], a_base: int) -> None:
        """Lex-leader clauses of one step: while every earlier action was fixed by the swap,
        the step's action must not be the larger of a swapped pair."""
        cur = lex[-1]
        nxt = self._alloc(1) + 1
        lex.append(nxt)
        moved = sw.moved
        self._emit([-nxt, cur])
        for j in moved:
            self._emit([-nxt, -(a_base + j + 1)])
            if sw.action_perm[j] < j:
                self._emit([-cur, -(a_base + j + 1)])
        self._emit([-cur, nxt, *(a_base + j + 1 for j in moved)])

    def _ordering(self, t: int) -> None:
        """Partial-order reduction: of two adjacent *independent* actions, the one with the
        smaller index comes first.

        Role variables ``R[t][(kind, p)]`` say exactly "the action at step t reads (``pre``),
        modifies (``mod``), adds (``add``) or deletes (``del``) atom p" over the union of all
        guarded components (independence must hold in every model of the family).  Action
        ``k`` at step ``t`` then needs an action of index ``<= k`` at ``t-1`` or one that
        interferes with it.  Linear size; sound because bubble-sorting any plan by swapping
        adjacent independent inversions keeps it valid, with the same final state and cost,
        in every model (``encodings/sequential.md``).
        """
        roles: dict[tuple[str, int], int] = {}
        base = self._alloc(len(self._role_members))
        for off, (key, members) in enumerate(self._role_members.items()):
            v = base + off + 1
            roles[key] = v
            for j in members:
                self._emit([-self.a(t, j), v])
            self._emit([-v, *(self.a(t, j) for j in members)])
        self.roles.append(roles)
        if t == 0:
            return
        prev, pre_s = self.roles[t - 1], self.prefix[t - 1]
        for k in range(self.n_actions - 1):  # the last index is never an inversion
            clause = [-self.a(t, k), pre_s[k]]
            clause.extend(prev[key] for key in self._interferes[k] if key in prev)
            self._emit(clause)

    def _prepare_ordering(self) -> None:
        """Static interference data for :meth:`_ordering` (guards ignored: conservative)."""
        members: dict[tuple[str, int], set[int]] = {}
        for j, act in enumerate(self.family.actions):
            for p, _ in act.pre + act.negpre:
                members.setdefault(("pre", p), set()).add(j)
            for p, _ in act.add + act.delete:
                members.setdefault(("mod", p), set()).add(j)
            for p, _ in act.add:
                members.setdefault(("add", p), set()).add(j)
            for p, _ in act.delete:
                members.setdefault(("del", p), set()).add(j)
        self._interferes: list[list[tuple[str, int]]] = []
        needed: set[tuple[str, int]] = set()
        for act in self.family.actions:
            keys = {("mod", p) for p, _ in act.pre + act.negpre}
            keys |= {("pre", p) for p, _ in act.add + act.delete}
            keys |= {("del", p) for p, _ in act.add}
            keys |= {("add", p) for p, _ in act.delete}
            keys &= members.keys()
            self._interferes.append(sorted(keys))
            needed |= keys
        self._role_members = {k: sorted(members[k]) for k in sorted(needed)}
