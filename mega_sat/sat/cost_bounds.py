"""Bounds in the SAT encoding: binary adders and unary totalizers over the step costs, and the
assumptions that ask for the goal at a horizon and bound a copy's plan cost
(encodings/sequential.md).  A part of :class:`~mega_sat.sat.encoding.FamilyEncoding`."""

from __future__ import annotations

import time

from pysat.card import ITotalizer

from mega_sat.analysis.invariants import NEVER


class CostBounds:
    """The cost arithmetic of :class:`~mega_sat.sat.encoding.FamilyEncoding`."""

    def _add_binary(self, xs: list[int], ys: list[int], width: int) -> list[int]:
        """Bits of ``xs + ys`` (least significant first) by a ripple-carry adder, exact both
        ways, truncated to ``width`` bits with every bit above forced false.

        Forcing the overflow false removes no model in which the step costs are exact (their
        sum is below ``2**width``), and in every other model the truncated bits are the true
        sum of the per-step upper bounds, so the sum never wraps around below a plan's cost."""
        out: list[int] = []
        carry: list[int] = []
        for i in range(max(len(xs), len(ys)) + 1):
            ins = [bits[i] for bits in (xs, ys) if i < len(bits)] + carry
            if not ins:
                break
            carry = []
            if len(ins) == 1:
                bit = ins[0]
            else:
                bit = self._alloc(1) + 1
                cout = self._alloc(1) + 1
                carry = [cout]
                a, b = ins[0], ins[1]
                if len(ins) == 2:  # half adder: bit = a xor b, cout = a and b
                    for clause in (
                        [-a, -b, -bit], [a, b, -bit], [-a, b, bit], [a, -b, bit],
                        [-cout, a], [-cout, b], [-a, -b, cout],
                    ):  # fmt: skip
                        self._emit(clause)
                else:  # full adder: bit = a xor b xor d, cout = majority(a, b, d)
                    d = ins[2]
                    for sa in (1, -1):
                        for sb in (1, -1):
                            for sd in (1, -1):
                                odd = ((sa > 0) + (sb > 0) + (sd > 0)) % 2 == 1
                                self._emit([-sa * a, -sb * b, -sd * d, bit if odd else -bit])
                    for clause in (
                        [-a, -b, cout], [-a, -d, cout], [-b, -d, cout],
                        [a, b, -cout], [a, d, -cout], [b, d, -cout],
                    ):  # fmt: skip
                        self._emit(clause)
            if i < width:
                out.append(bit)
            else:
                self._emit([-bit])
        for c in carry:
            self._emit([-c])
        return out

    def _at_most(self, bits: list[int], bound: int) -> int:
        """A fresh literal that implies "the binary number ``bits`` is at most ``bound``":
        for every 0-bit ``i`` of ``bound``, not (bit ``i`` and every higher bit that is 1 in
        ``bound``); the highest bit where the number and ``bound`` differ is such a clause."""
        g = self._alloc(1) + 1
        for i, bit in enumerate(bits):
            if not bound >> i & 1:
                higher = [-bits[j] for j in range(i + 1, len(bits)) if bound >> j & 1]
                self._emit([-g, -bit, *higher])
        return g

    def _take_totalizer_clauses(self, tot: ITotalizer, count: int) -> None:
        if count:
            for clause in tot.cnf.clauses[-count:]:
                self._emit(list(clause))
        self.top = max(self.top, tot.top_id)

    # ------------------------------------------------------------ assumptions
    def goal_assumptions(self, h: int) -> list[int]:
        """Assumptions "every copy reaches its goal after exactly ``h`` steps".

        With symmetry breaking also ``-act[h]`` (no action from step h on), so the solver need
        not consider the steps beyond ``h`` that a longer encoding has.
        """
        if h < 0:
            raise ValueError("negative horizon")
        self.extend(h)
        g = self.goal_act.get(h)
        if g is None:
            t0 = time.perf_counter()
            g = self._alloc(1) + 1
            self.goal_act[h] = g
            # no action is needed fewer steps before the goal than its backward layer
            for j, k in enumerate(self._to_goal):
                for t in range(max(0, h - k + 1), h) if k < NEVER else ():
                    self._emit([-g, -self.a(t, j)])
            for c in self.copies:
                for p, guard in self.family.goal:
                    gv = self._guard(c, guard)
                    if gv is False:
                        continue
                    lits = [-g, self.x(c, h, p)]
                    if gv is not True:
                        lits.insert(1, -self._resolve(gv, None))
                    self._emit(lits)
            self.grow_s += time.perf_counter() - t0
        out = [g]
        if self.horizon > h and self.symmetry_breaking:
            out.append(-self.act[h])
        elif self.horizon > h:
            out.extend(-self.a(t, j) for t in range(h, self.horizon) for j in range(self.n_actions))
        return out

    def cost_assumptions(self, copy: str, bound: int | None, horizon: int = 0) -> list[int] | None:
        """Assumptions "total cost of ``copy`` over all steps <= ``bound``".

        The encoding is first extended to ``horizon`` steps: growing it later replaces the
        totalizer outputs, so literals returned before an extension must not be used after it.
        ``horizon`` must be the one given to :meth:`goal_assumptions` in the same call (the
        steps after it are idle, which lets unit-cost bounds be dropped entirely).
        ``[]`` when the bound cannot bite; ``None`` when it is unsatisfiable (bound < 0).
        """
        self.extend(horizon)
        if bound is None:
            return []
        if bound < 0:
            return None
        b = bound // self.cost_unit
        if b >= horizon * self.max_units:
            return []  # cannot bite (goal_assumptions(horizon) idles the later steps)
        if self.binary:
            # the sum of steps 0..horizon-1: the later steps are idle, and the literal stays
            # valid when the encoding grows
            key = (copy, horizon, b)
            g = self._cmp.get(key)
            if g is None:
                t0 = time.perf_counter()
                g = self._cmp[key] = self._at_most(self.sum_bits[copy][horizon], b)
                self.grow_s += time.perf_counter() - t0
            return [g]
        units = [
            self.u(copy, t, k) for t in range(self.horizon) for k in range(1, self.max_units + 1)
        ]
        if b >= len(units):
            return []
        tot = self._tot[copy]
        t0 = time.perf_counter()
        if tot is None:
            tot = ITotalizer(lits=units, ubound=b + 1, top_id=self.top)
            self._tot[copy] = tot
            self._take_totalizer_clauses(tot, len(tot.cnf.clauses))
        elif tot.ubound < b + 1:
            tot.increase(ubound=b + 1, top_id=self.top)
            self._take_totalizer_clauses(tot, tot.nof_new)
        self.grow_s += time.perf_counter() - t0
        return [-tot.rhs[b]]
