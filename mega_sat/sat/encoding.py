"""Sequential SAT encoding of a whole model family (``encodings/sequential.md`` explains it).

One :class:`FamilyEncoding` covers every model ``human + E`` of a :class:`GroundFamily` at once:
components that depend on an update are guarded by the selector variable ``e_i`` (variable
``i + 1``), so a candidate model is a set of assumptions and the encoding is built once per
task.  It has one or two *state copies* that share the action variables:

* ``human``: guards are selector literals (the model ``human + E`` for the assumed ``E``);
* ``robot``: guards are constants (every update selected: the robot model).

At most one action runs per step (a step without an action is a no-op); with symmetry breaking
no-op steps only come at the end.  The horizon grows with :meth:`FamilyEncoding.extend`; goals
are switched on per horizon by an activation literal, and cost bounds are assumptions: on an
incremental totalizer over unary cost units while actions cost few units, else on a comparator
over a binary sum of per-step costs (:data:`UNARY_MAX_UNITS`).  Clauses go to a *sink* (a live
SAT solver or a CNF being written), so the same code serves the oracles and the DIMACS export.
"""

from __future__ import annotations

import math
import time
from collections.abc import Callable, Iterable, Sequence
from dataclasses import dataclass

from pysat.card import ITotalizer

from mega_sat.analysis.invariants import NEVER, EncodingFacts, Invariants, encoding_facts
from mega_sat.ground.family import GroundFamily, Guard, GuardLit
from mega_sat.model.lifted import PlanStep, step_str
from mega_sat.sat.cost_bounds import CostBounds
from mega_sat.sat.ordering import StepOrdering
from mega_sat.sat.symmetry import Swap, object_swaps

HUMAN = "human"
ROBOT = "robot"
GUARDED_FROM_STEPS = 4
"""The human copy gets its guarded mutexes once the encoding has this many steps (then on
every state layer): they cost up to two h^2 computations per update, which the short queries
of one or two steps do not repay."""

UNARY_MAX_UNITS = 16
"""Costs are counted in unary (one variable per cost unit and step, a totalizer for the bound)
while the costliest action costs at most this many cost units (multiples of the gcd of all
costs); above it, in binary (one variable per bit of a step's cost, a ripple-carry sum over the
steps, a comparator per bound), whose size grows with the bit length of the costs, not their
value.  The totalizer propagates better on small costs, but it has ``steps * units`` inputs and
grows with the bound as well, so large costs need the binary form.  Every shipped domain has at
most 5 units per step and keeps the unary form."""

# Template literal kinds: e variable, action at t, state at t, state at t+1, and cost at t (a
# unary unit, or a bit of the step's binary cost).
_E, _A, _X0, _X1, _U = range(5)

Lit = tuple[int, int, int]
"""A template literal ``(kind, offset >= 1, sign)``; resolved per step by layer bases."""

Sink = Callable[[list[int]], None]


@dataclass(frozen=True)
class EncodingSize:
    """Size of the formula so far (for stats and export headers)."""

    variables: int
    clauses: int
    horizon: int


def _state_lit(base: int, lit: int) -> int:
    """A state literal ``±(p+1)`` of :class:`Invariants` at the state layer with ``base``."""
    return base + lit if lit > 0 else -(base - lit)


class FamilyEncoding(StepOrdering, CostBounds):
    """Bounded-horizon sequential encoding of ``family`` with one or two state copies.

    ``sink`` receives every clause (``Solver.add_clause`` or ``CNF.append``).  Variables are
    numbered from 1: first the ``n_updates`` selector variables, then everything else in order
    of creation (``self.top`` is the largest used).
    """

    built = 0
    """Encodings constructed in this process so far (the per-call benchmark checks that the
    oracles build theirs once per task, never per call)."""

    def __init__(
        self,
        family: GroundFamily,
        sink: Sink,
        *,
        copies: Sequence[str] = (HUMAN,),
        symmetry_breaking: bool = True,
        partial_order: bool = False,
        invariants: bool | EncodingFacts | Callable[[], EncodingFacts] = True,
        symmetry: bool = True,
        unary_max_units: int = UNARY_MAX_UNITS,
        swaps: Sequence[Swap] | None = None,
    ):
        if (
            not copies
            or any(c not in (HUMAN, ROBOT) for c in copies)
            or len(set(copies)) != len(copies)
        ):
            raise ValueError(f"copies must be distinct names among {HUMAN!r}, {ROBOT!r}")
        FamilyEncoding.built += 1
        self.family = family
        self.copies = tuple(copies)
        self.symmetry_breaking = symmetry_breaking
        self._sink = sink
        self.n_clauses = 0
        # seconds spent growing the formula after construction (steps, invariants, goal and
        # cost clauses): building work that happens lazily inside oracle calls
        self.grow_s = 0.0
        self.top = family.n_updates
        self.n_actions = len(family.actions)
        self.n_atoms = len(family.atoms)
        values = [v for a in family.actions for _, v in a.cost]
        if any(v < 0 for v in values):
            raise ValueError("negative action costs are not supported")
        # Costs are counted in units of their gcd: fewer units, same "cost <= B" answers.
        self.cost_unit = math.gcd(*values) if any(values) else 1
        self.max_units = max(values, default=0) // self.cost_unit
        # binary step costs when unary units would be too many (see UNARY_MAX_UNITS)
        self.binary = self.max_units > unary_max_units
        self.cost_bits = self.max_units.bit_length() if self.binary else 0
        self._step_vars = self.cost_bits if self.binary else self.max_units
        # Per-step layer bases (variable = base + offset, offsets start at 1).
        self.a_base: list[int] = []
        self.act: list[int] = []  # act[t]: some action runs at step t
        self.x_base: dict[str, list[int]] = {c: [] for c in self.copies}
        self.u_base: dict[str, list[int]] = {c: [] for c in self.copies}
        self.goal_act: dict[int, int] = {}
        self._tot: dict[str, ITotalizer | None] = {c: None for c in self.copies}
        # binary form: sum_bits[c][t] = bits (least significant first) of the cost of steps
        # 0..t-1 in units; one comparator literal per (copy, horizon, bound in units)
        self.sum_bits: dict[str, list[list[int]]] = {c: [[]] for c in self.copies}
        self._cmp: dict[tuple[str, int, int], int] = {}
        # per-copy step clause templates, built with the first step (many tasks need none)
        self._templates: dict[str, list[list[Lit]]] = {}
        self.prefix: list[list[int]] = []
        self.roles: list[dict[tuple[str, int], int]] = []
        self.partial_order = partial_order and symmetry_breaking
        if self.partial_order:
            self._prepare_ordering()
        # redundant clauses (mega_sat/analysis/invariants.py; the human copy's hold for every selection,
        # the robot copy's for the robot model), computed when the first step is encoded (many
        # tasks never need a SAT call); ``invariants`` may be the facts themselves or a function
        # returning them, so that the encodings of one family share one computation
        self._facts_source = invariants
        self._facts_ready = False
        self.facts: EncodingFacts | None = None
        self.invariants: dict[str, Invariants] = {}
        self._to_goal: tuple[int, ...] = (1,) * self.n_actions
        self.irrelevant: tuple[int, ...] = ()
        # object swaps (mega_sat/sat/symmetry.py): keep only plans pi <=lex swap(pi); lex[s][t]
        # says "the actions before step t are all fixed by swap s" (exact both ways)
        # (``swaps``: the family's swaps when the caller has them, for two encodings of it)
        if not (symmetry and symmetry_breaking):
            self.swaps = []
        else:
            self.swaps = list(object_swaps(family) if swaps is None else swaps)
        self._lex: list[list[int]] = []
        for _ in self.swaps:
            v = self._alloc(1) + 1
            self._lex.append([v])
            self._emit([v])
        # cheapest step of each copy in cost units: "some action runs at t" implies them
        self._min_units = {c: self._copy_min_units(c) for c in self.copies}
        for c in self.copies:
            self.x_base[c].append(self._alloc(self.n_atoms))
            self._init_clauses(c)

    # ----------------------------------------------------------------- basics
    def _alloc(self, n: int) -> int:
        """Reserve ``n`` fresh variables; return the base (first variable is base + 1)."""
        base = self.top
        self.top += n
        return base

    def _emit(self, clause: list[int]) -> None:
        self._sink(clause)
        self.n_clauses += 1

    @property
    def horizon(self) -> int:
        return len(self.a_base)

    def size(self) -> EncodingSize:
        return EncodingSize(self.top, self.n_clauses, self.horizon)

    def e(self, i: int) -> int:
        """Selector variable of update ``i``."""
        return i + 1

    def guard_lit(self, g: GuardLit) -> int:
        return self.e(g[0]) if g[1] else -self.e(g[0])

    def selection_assumptions(self, selection: Iterable[int]) -> list[int]:
        """Literals fixing every selector to ``selection`` (the model ``human + E``)."""
        sel = frozenset(selection)
        return [self.e(i) if i in sel else -self.e(i) for i in range(self.family.n_updates)]

    def lits_assumptions(self, lits: Iterable[GuardLit]) -> list[int]:
        return [self.guard_lit(g) for g in lits]

    def a(self, t: int, j: int) -> int:
        return self.a_base[t] + j + 1

    def x(self, copy: str, t: int, p: int) -> int:
        return self.x_base[copy][t] + p + 1

    def u(self, copy: str, t: int, k: int) -> int:
        """Cost variable ``k`` (1-based) of step ``t``: unary, "step t costs at least k units";
        binary, bit ``k - 1`` of an upper bound on the step's cost in units."""
        return self.u_base[copy][t] + k

    def step_cost_literals(self, copy: str, t: int) -> list[tuple[int, int]]:
        """``(variable, weight in cost units)`` pairs whose true weights add up to at least the
        cost of step ``t``, and to exactly it in some model (the MaxSAT export's soft units)."""
        if self.binary:
            return [(self.u(copy, t, b + 1), 1 << b) for b in range(self.cost_bits)]
        return [(self.u(copy, t, k), 1) for k in range(1, self.max_units + 1)]

    def _ensure_facts(self) -> None:
        """Compute (or fetch) the invariants, guarded mutexes and backward layers once."""
        if self._facts_ready:
            return
        self._facts_ready = True
        src = self._facts_source
        if isinstance(src, EncodingFacts):
            facts = src
        elif callable(src):
            facts = src()
        else:
            facts = encoding_facts(self.family) if src else None
        self.facts = facts
        if facts is None:
            return
        for c in self.copies:
            self.invariants[c] = facts.robot if c == ROBOT else facts.human
        # backward layers (mega_sat/analysis/invariants.py): no plan needs an action fewer steps before
        # its goal than its layer; irrelevant actions (no finite layer) are never usable
        self._to_goal = facts.to_goal
        self.irrelevant = tuple(j for j, k in enumerate(self._to_goal) if k >= NEVER)

    def _copy_min_units(self, copy: str) -> int:
        """Cost units every action usable in ``copy`` costs at least (0 with zero costs)."""
        vals = []
        for a in self.family.actions:
            if self._guard(copy, a.exists) is False:
                continue
            for guards, v in a.cost:
                if all(self._guard(copy, g) is not False for g in guards):
                    vals.append(v)
        return min(vals, default=0) // self.cost_unit

    # ------------------------------------------------------ guard evaluation
    def _guard(self, copy: str, g: Guard) -> bool | Lit:
        """A guard as a constant (robot copy, or no guard) or a template literal on ``e``."""
        if g is None:
            return True
        if copy == ROBOT:
            return g[1]  # the robot model selects every update: (i in all) == v  <=>  v
        return (_E, g[0] + 1, 1 if g[1] else -1)

    @staticmethod
    def _neg(g: bool | Lit) -> bool | Lit:
        if isinstance(g, bool):
            return not g
        return (g[0], g[1], -g[2])

    @staticmethod
    def _clause(parts: Iterable[bool | Lit]) -> list[Lit] | None:
        """A disjunction of constants and literals: ``None`` if it is always true."""
        out: list[Lit] = []
        for p in parts:
            if p is True:
                return None
            if p is False:
                continue
            out.append(p)
        return out

    # -------------------------------------------------------------- templates
    def _step_template(self, copy: str) -> list[list[Lit]]:
        """Every clause of one step of one copy, with literals relative to the step's layers."""
        cl: list[list[Lit]] = []

        def put(parts: Iterable[bool | Lit]) -> None:
            c = self._clause(parts)
            if c is not None:
                cl.append(c)

        adders: dict[int, list[tuple[int, list[bool | Lit]]]] = {}
        deleters: dict[int, list[tuple[int, list[bool | Lit]]]] = {}
        for j, act in enumerate(self.family.actions):
            na = (_A, j + 1, -1)
            ex = self._guard(copy, act.exists)
            if ex is False:
                cl.append([na])  # the action does not exist in this copy's model
                continue
            put([na, ex])
            for p, g in act.pre:
                put([na, self._neg(self._guard(copy, g)), (_X0, p + 1, 1)])
            for p, g in act.negpre:
                put([na, self._neg(self._guard(copy, g)), (_X0, p + 1, -1)])
            adds: dict[int, list[bool | Lit]] = {}
            for p, g in act.add:
                adds.setdefault(p, []).append(self._guard(copy, g))
            dels: dict[int, list[bool | Lit]] = {}
            for p, g in act.delete:
                dels.setdefault(p, []).append(self._guard(copy, g))
            for p, gs in adds.items():
                for g in gs:
                    put([na, self._neg(g), (_X1, p + 1, 1)])
                if any(g is not False for g in gs):
                    adders.setdefault(p, []).append((j, gs))
            for p, gs in dels.items():
                add_gs = adds.get(p, [])
                # delete-then-add: the delete takes effect only if no add of p is active
                for g in gs:
                    put([na, self._neg(g), *add_gs, (_X1, p + 1, -1)])
                if any(g is not False for g in gs):
                    deleters.setdefault(p, []).append((j, gs))
            for guards, value in act.cost:
                k = value // self.cost_unit
                neg = [self._neg(self._guard(copy, g)) for g in guards]
                if self.binary:  # every bit of k is set (other bits are free: cost >= k)
                    for b in range(k.bit_length()):
                        if k >> b & 1:
                            put([na, *neg, (_U, b + 1, 1)])
                elif k > 0:
                    put([na, *neg, (_U, k, 1)])
        # explanatory frame axioms (exact because at most one action runs per step)
        for p in range(self.n_atoms):
            up, keep = (_X1, p + 1, 1), (_X0, p + 1, 1)
            js = adders.get(p, [])
            cl.append([(_X1, p + 1, -1), keep, *((_A, j + 1, 1) for j, _ in js)])
            for j, gs in js:
                put([(_A, j + 1, -1), *gs, (_X1, p + 1, -1), keep])
            js = deleters.get(p, [])
            cl.append([up, (_X0, p + 1, -1), *((_A, j + 1, 1) for j, _ in js)])
            for j, gs in js:
                put([(_A, j + 1, -1), *gs, up, (_X0, p + 1, -1)])
        # unary cost units are monotone: unit k+1 implies unit k
        for k in range(1, 0 if self.binary else self.max_units):
            cl.append([(_U, k + 1, -1), (_U, k, 1)])
        return cl

    def _init_clauses(self, copy: str) -> None:
        """``x0[p] <-> OR of the guards of p's initial-state entries`` (false if none)."""
        by_atom: dict[int, list[bool | Lit]] = {}
        for p, g in self.family.init:
            by_atom.setdefault(p, []).append(self._guard(copy, g))
        for p in range(self.n_atoms):
            x0 = self.x(copy, 0, p)
            gs = by_atom.get(p, [])
            if any(g is True for g in gs):
                self._emit([x0])
                continue
            lits = [self._resolve(g, None) for g in gs if g is not False]
            self._emit([-x0, *lits])
            for lit in lits:
                self._emit([-lit, x0])

    def _resolve(self, lit: Lit, bases: Sequence[int] | None) -> int:
        kind, off, sign = lit
        return sign * ((bases[kind] if bases is not None else 0) + off)

    # ------------------------------------------------------------- extension
    def extend(self, horizon: int) -> None:
        """Append step layers until the encoding has ``horizon`` steps."""
        if self.horizon >= horizon:
            return
        t0 = time.perf_counter()
        while self.horizon < horizon:
            self._add_step()
        self.grow_s += time.perf_counter() - t0

    def _add_step(self) -> None:
        self._ensure_facts()
        t = self.horizon
        n = self.n_actions
        a_base = self._alloc(n)
        self.a_base.append(a_base)
        act = self._alloc(1) + 1
        self.act.append(act)
        # at most one action (sequential counter), and act <-> some action
        acts = [a_base + j + 1 for j in range(n)]
        # s[i] <-> some of a[0..i] (exact both ways: the ordering clauses below read it)
        s: list[int] = []
        if n > 1:
            s_base = self._alloc(n - 1)
            s = [s_base + i + 1 for i in range(n - 1)]
            for i in range(n - 1):
                self._emit([-acts[i], s[i]])
                if i > 0:
                    self._emit([-s[i - 1], s[i]])
                    self._emit([-s[i - 1], -acts[i]])
                    self._emit([-s[i], s[i - 1], acts[i]])
                else:
                    self._emit([-s[0], acts[0]])
            self._emit([-s[n - 2], -acts[n - 1]])
        self.prefix.append(s)
        for lit in acts:
            self._emit([-lit, act])
        self._emit([-act, *acts])
        if self.symmetry_breaking:
            if t > 0:
                self._emit([-act, self.act[t - 1]])  # no-op steps only at the end
            if self.partial_order:
                self._ordering(t)
        for sw, lex in zip(self.swaps, self._lex, strict=True):
            self._lex_step(sw, lex, a_base)
        new_units: dict[str, list[int]] = {}
        for c in self.copies:
            x1 = self._alloc(self.n_atoms)
            self.x_base[c].append(x1)
            u_base = self._alloc(self._step_vars)
            self.u_base[c].append(u_base)
            new_units[c] = [] if self.binary else [u_base + k for k in range(1, self.max_units + 1)]
            bases = (0, a_base, self.x_base[c][t], x1, u_base)
            # the bulk of every step, resolved inline: a function call per literal and per
            # clause would dominate the time to build a step
            if c not in self._templates:
                self._templates[c] = self._step_template(c)
            sink, template = self._sink, self._templates[c]
            for clause in template:
                sink([sign * (bases[kind] + off) for kind, off, sign in clause])
            self.n_clauses += len(template)
            if self.binary:
                bits = [u_base + b + 1 for b in range(self.cost_bits)]
                width = ((t + 1) * self.max_units).bit_length()
                self.sum_bits[c].append(self._add_binary(self.sum_bits[c][t], bits, width))
            elif self._min_units[c] > 0:
                self._emit([-act, u_base + self._min_units[c]])
            inv = self.invariants.get(c)
            if inv is not None:
                for l1, l2 in inv.binary:
                    self._emit([_state_lit(x1, l1), _state_lit(x1, l2)])
                for lit in inv.fixed_at(t + 1):
                    self._emit([_state_lit(x1, lit)])
            if c == HUMAN and self.facts is not None and t + 1 >= GUARDED_FROM_STEPS:
                # the first time: every state layer so far (1..t+1); afterwards the new one
                layers = range(1, t + 2) if t + 1 == GUARDED_FROM_STEPS else (t + 1,)
                for layer in layers:
                    xl = self.x_base[c][layer]
                    for g, l1, l2 in self.facts.guarded:
                        self._emit([-g, _state_lit(xl, l1), _state_lit(xl, l2)])
        off = {
            j for inv in self.invariants.values() for j, f in enumerate(inv.action_from) if f > t
        }
        for j in sorted(off.union(self.irrelevant)):
            self._emit([-(a_base + j + 1)])
        for c in self.copies:
            tot = self._tot[c]
            if tot is not None and new_units[c]:
                tot.extend(lits=new_units[c], top_id=self.top)
                self._take_totalizer_clauses(tot, tot.nof_new)

    # ---------------------------------------------------------------- decode
    def decode_plan(self, model: Sequence[int], h: int) -> tuple[PlanStep, ...]:
        """The actions true in ``model`` at steps ``0..h-1`` (no-op steps skipped)."""
        true = set(lit for lit in model if lit > 0)
        plan = []
        for t in range(min(h, self.horizon)):
            for j in range(self.n_actions):
                if self.a(t, j) in true:
                    plan.append(self.family.actions[j].step)
                    break
        return tuple(plan)

    def decode_selection(self, model: Sequence[int]) -> frozenset[int]:
        n = self.family.n_updates
        return frozenset(i for i in range(n) if i < len(model) and model[i] > 0)

    # ------------------------------------------------------------- var names
    def var_map(self) -> dict[int, str]:
        """Human-readable meaning of every named variable (auxiliaries are left out)."""
        fam = self.family
        out: dict[int, str] = {}
        for i in range(fam.n_updates):
            out[self.e(i)] = f"e[{i}]"
        for t in range(self.horizon):
            out[self.act[t]] = f"act[{t}]"
            for j, a in enumerate(fam.actions):
                out[self.a(t, j)] = f"a[{t}]={step_str(a.step)}"
        for c in self.copies:
            for t in range(self.horizon + 1):
                for p in range(self.n_atoms):
                    out[self.x(c, t, p)] = f"x[{c}][{t}]{fam.atom_name(p)}"
            for t in range(self.horizon):
                if self.binary:
                    for b in range(self.cost_bits):
                        out[self.u(c, t, b + 1)] = f"w[{c}][{t}][{b}]"
                else:
                    for k in range(1, self.max_units + 1):
                        out[self.u(c, t, k)] = f"u[{c}][{t}][{k}]"
            if self.binary:
                for t, bits in enumerate(self.sum_bits[c]):
                    for b, v in enumerate(bits):
                        out.setdefault(v, f"sum[{c}][{t}][{b}]")
            tot = self._tot[c]
            if tot is not None:
                for b, v in enumerate(tot.rhs):
                    out[v] = f"cost[{c}]>={(b + 1) * self.cost_unit}"
        for (c, h, b), g in self._cmp.items():
            out[g] = f"cost[{c}][{h}]<={b * self.cost_unit}"
        for h, g in self.goal_act.items():
            out[g] = f"goal[{h}]"
        return out
