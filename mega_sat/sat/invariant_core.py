"""The updates an inductive invariant depends on: an unsolvable core from an IC3 proof.

IC3 (:mod:`mega_sat.search.pdr`) proves ``human + E`` unsolvable with an invariant ``I`` (a set
of clauses over atoms) that holds initially, holds after every step from a state where it
holds, and excludes the goal.  The same ``I`` often proves more models unsolvable: every
``E'`` for which the three checks still pass.  :func:`invariant_core` finds a set ``S`` of
updates such that they pass for every ``E'`` agreeing with ``E`` on ``S``, so the loop can
exclude all of those models with one clause instead of ``E`` alone.

The checks are three SAT queries on one step of the *family* (every guarded component of the
family with one selector variable per update, ``encodings/hitting-set.md``): a free selector
ranges over both values, so an UNSAT answer covers every agreeing ``E'`` at once.  Variables:
the state before (``x``) and after (``y``) the step, one variable per family action (at most
one is taken; none leaves the state as it is), and the selectors.  The queries, under the
selectors of ``S`` fixed as in ``E``:

1. some initial state of an agreeing model violates ``I``;
2. some state satisfies ``I`` and an agreeing model's goal;
3. some step of an agreeing model leads from a state satisfying ``I`` to one violating it.

All three UNSAT: no agreeing model has a plan.  ``S`` is found by deletion from all updates,
each query's core first dropping what it does not need.
"""

from __future__ import annotations

from collections.abc import Sequence

from pysat.card import CardEnc, EncType
from pysat.solvers import Solver

from mega_sat.ground.family import GroundFamily, Guard

Cube = frozenset[tuple[int, bool]]


class InvariantCores:
    """One family step with selector variables on one solver, kept for every invariant the
    loop hands over: each invariant's clauses sit under activation literals of their own,
    retired once its core is found."""

    def __init__(self, family: GroundFamily, solver: str = "cadical195"):
        self.family = family
        n = len(family.atoms)
        self._top = 0
        self.sel = [self._fresh() for _ in range(family.n_updates)]
        self.x = [self._fresh() for _ in range(n)]
        self.y = [self._fresh() for _ in range(n)]
        self.solver = Solver(name=solver)
        self._step()
        self.init_act = self._fresh()
        self._initial_state()
        self.goal_act = self._fresh()
        for p, g in family.goal:
            self._add([-self.goal_act, *self._absent(g), self.x[p]])
        self._index = {v: i for i, v in enumerate(self.sel)}

    def close(self) -> None:
        self.solver.delete()

    def __enter__(self) -> InvariantCores:
        return self

    def __exit__(self, *exc) -> None:
        self.close()

    def _fresh(self) -> int:
        self._top += 1
        return self._top

    def _add(self, clause: list[int]) -> None:
        self.solver.add_clause(clause)

    @staticmethod
    def _lit(vars_: list[int], p: int, v: bool) -> int:
        return vars_[p] if v else -vars_[p]

    def _holds(self, g: Guard) -> list[int]:
        """Literals one of which holds when the component is present (empty: always)."""
        return [] if g is None else [self.sel[g[0]] if g[1] else -self.sel[g[0]]]

    def _absent(self, g: Guard) -> list[int]:
        """The clause part "or the component is absent" (empty: it is always present)."""
        return [-lit for lit in self._holds(g)]

    def _step(self) -> None:
        """At most one action; its conditions on ``x`` and effects on ``y`` where present (an
        atom both added and deleted ends true, as in the planners); every atom no taken
        action changes keeps its value."""
        family, x, y = self.family, self.x, self.y
        acts = [self._fresh() for _ in family.actions]
        adders: dict[int, list[int]] = {}
        deleters: dict[int, list[int]] = {}
        for a, act in zip(acts, family.actions, strict=True):
            if act.exists is not None:
                self._add([-a, *self._holds(act.exists)])
            for p, g in act.pre:
                self._add([-a, *self._absent(g), x[p]])
            for p, g in act.negpre:
                self._add([-a, *self._absent(g), -x[p]])
            adds: dict[int, list[Guard]] = {}
            for p, g in act.add:
                adds.setdefault(p, []).append(g)
            dels: dict[int, list[Guard]] = {}
            for p, g in act.delete:
                dels.setdefault(p, []).append(g)
            for p, guards in adds.items():
                for g in guards:
                    self._add([-a, *self._absent(g), y[p]])
                adders.setdefault(p, []).append(a)
                if None not in guards:  # taken and p became true: one of its adds is present
                    self._add([-a, -y[p], x[p], *(lit for g in guards for lit in self._holds(g))])
            for p, guards in dels.items():
                add_guards = adds.get(p, [])
                if None in add_guards:
                    continue  # always added: never ends false
                add_lits = [lit for g in add_guards for lit in self._holds(g)]
                for g in guards:
                    self._add([-a, *self._absent(g), *add_lits, -y[p]])
                deleters.setdefault(p, []).append(a)
                if None not in guards:
                    self._add([-a, y[p], -x[p], *(lit for g in guards for lit in self._holds(g))])
        for p in range(len(family.atoms)):
            self._add([-y[p], x[p], *adders.get(p, [])])
            self._add([y[p], -x[p], *deleters.get(p, [])])
        if len(acts) > 1:
            amo = CardEnc.atmost(acts, 1, top_id=self._top, encoding=EncType.seqcounter)
            self._top = max(self._top, amo.nv)
            for clause in amo.clauses:
                self._add(clause)

    def _initial_state(self) -> None:
        """Under ``init_act``: ``x`` is an initial state of some agreeing model."""
        entries: dict[int, list[Guard]] = {}
        for p, g in self.family.init:
            entries.setdefault(p, []).append(g)
        for p in range(len(self.family.atoms)):
            guards = entries.get(p, [])
            if None in guards:
                self._add([-self.init_act, self.x[p]])
                continue
            lits = [lit for g in guards for lit in self._holds(g)]
            self._add([-self.init_act, -self.x[p], *lits])
            for lit in lits:
                self._add([-self.init_act, -lit, self.x[p]])

    def _fails(self, vars_: list[int], cubes: Sequence[Cube]) -> int:
        """An activation literal under which some cube holds on ``vars_``."""
        act = self._fresh()
        holders = []
        for cube in cubes:
            h = self._fresh()
            holders.append(h)
            for p, v in cube:
                self._add([-h, self._lit(vars_, p, v)])
        self._add([-act, *holders])
        return act

    def _unsat_core(self, query: list[int], fixed: list[int]) -> set[int] | None:
        """The selectors of ``fixed`` (literals) the UNSAT ``query`` needs; None if SAT."""
        if self.solver.solve(assumptions=query + fixed):
            return None
        core = set(self.solver.get_core() or [])
        return {lit for lit in fixed if lit in core}

    def core(self, selection: frozenset[int], cubes: Sequence[Cube]) -> frozenset[int] | None:
        """A set ``S`` of updates such that the invariant ``NOT cube`` for every cube of
        ``cubes`` (from IC3 on ``human + selection``) proves every ``E'`` agreeing with
        ``selection`` on ``S`` unsolvable; ``None`` when it does not even prove
        ``human + selection`` itself (then the invariant is not one of this model)."""
        # I on x; "I fails" on x and on y (one auxiliary per cube: the cube holds)
        inv = self._fresh()
        for cube in cubes:
            self._add([-inv, *(-self._lit(self.x, p, v) for p, v in cube)])
        fails_x = self._fails(self.x, cubes)
        fails_y = self._fails(self.y, cubes)
        queries = [[self.init_act, fails_x], [inv, self.goal_act], [inv, fails_y]]

        def needed(fixed: frozenset[int]) -> frozenset[int] | None:
            lits = [self.sel[i] if i in selection else -self.sel[i] for i in sorted(fixed)]
            need: set[int] = set()
            for q in queries:
                core = self._unsat_core(q, lits)
                if core is None:
                    return None
                need |= core
            return frozenset(self._index[abs(v)] for v in need)

        try:
            fixed = needed(frozenset(range(self.family.n_updates)))
            if fixed is None:
                return None
            for i in sorted(fixed):
                if i not in fixed:
                    continue  # an earlier core dropped it
                trial = needed(fixed - {i})
                if trial is not None:
                    fixed = trial
            return fixed
        finally:
            for act in (inv, fails_x, fails_y):  # this invariant's clauses are satisfied now
                self._add([-act])


def invariant_core(
    family: GroundFamily,
    selection: frozenset[int],
    cubes: Sequence[Cube],
    solver: str = "cadical195",
) -> frozenset[int] | None:
    """:meth:`InvariantCores.core` on a solver of its own (one invariant)."""
    with InvariantCores(family, solver) as cores:
        return cores.core(selection, cubes)
