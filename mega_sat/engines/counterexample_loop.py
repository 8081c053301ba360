"""The counterexample loop: the frontier from one JOINT formula with the explanation left free
(``encodings/counterexamples.md``).

The hitting-set loop fixes a candidate ``E``, proves its optimum ``c*`` and asks JOINT for a
plan within ``c*``; a failure becomes a clause over ``E`` (a core plus the support of the
human's plan).  Here the SAT solver chooses ``E`` and the joint plan together, under a
cardinality bound on ``|E|`` and the robot bound ``K``.  A candidate ``(E, pi)`` is checked by
OPT: if ``pi``'s human cost is ``c*(E)``, it is a solution; otherwise OPT's plan ``pi*`` is a
*counterexample*, and the formula learns "wherever ``pi*`` runs, ``pi`` costs the human at most
``cost(pi*)``", with "``pi*`` runs in ``human + E``" encoded exactly over the update variables
(a symbolic run of ``pi*``).  No core shrinking, no support: one counterexample rules out
every model in which that plan runs.
"""

from __future__ import annotations

from collections.abc import Callable, Sequence
from dataclasses import dataclass, field

from pysat.card import ITotalizer

from mega_sat.engines.support import exclusion_clause
from mega_sat.ground.family import GroundFamily, GuardLit
from mega_sat.ground.simulate import ground_plan_cost
from mega_sat.model.lifted import PlanStep
from mega_sat.sat.encoding import HUMAN, ROBOT, FamilyEncoding
from mega_sat.sat.solving import new_solver

Lit = int | bool


@dataclass(frozen=True)
class Counterexample:
    """A plan of ``human + selection`` of cost ``cost`` there (OPT's optimum for it)."""

    plan: tuple[PlanStep, ...]
    cost: int
    selection: frozenset[int]


@dataclass
class CounterexampleStats:
    counterexamples: int = 0
    coverage_checks: int = 0
    formula_horizons: list[int] = field(default_factory=list)
    joint_alone: int = 0
    plans_found: int = 0


class CounterexampleFormula:
    """The joint formula at one horizon with the selectors free, a cardinality bound on them,
    the learned counterexamples and exclusions, and a second small solver over the selectors
    alone that asks which models no cheap counterexample covers yet."""

    def __init__(self, orc, horizon: int, solver: str):
        self.orc = orc
        self.family: GroundFamily = orc.family
        self.horizon = horizon
        self.main = new_solver(solver)
        self.cover = new_solver(solver)
        joint = orc.joint_enc
        self.enc = FamilyEncoding(
            self.family,
            self.main.add_clause,
            copies=(HUMAN, ROBOT),
            symmetry_breaking=joint.symmetry_breaking,
            partial_order=joint.partial_order,
            invariants=orc._facts,
            swaps=joint.swaps,
        )
        self.enc.extend(horizon)
        n = self.family.n_updates
        self.n = n
        self.card: ITotalizer | None = None
        if n:
            self.card = ITotalizer(
                lits=[self.enc.e(i) for i in range(n)], ubound=n, top_id=self.enc.top
            )
            for c in self.card.cnf.clauses:
                self.main.add_clause(c)
                self.cover.add_clause(c)
            self.enc.top = max(self.enc.top, self.card.top_id)
        # (cost, coverage literal) per counterexample: the literal is true wherever its plan runs
        self.covered: list[tuple[int, int]] = []

    def close(self) -> None:
        self.main.delete()
        self.cover.delete()

    # ----------------------------------------------------------------- clauses
    def _new(self) -> int:
        self.enc.top += 1
        return self.enc.top

    def _both(self, clause: list[int]) -> None:
        self.main.add_clause(clause)
        self.cover.add_clause(clause)

    def _or(self, lits: Sequence[Lit]) -> Lit:
        """A literal equivalent to the disjunction (constants folded)."""
        if any(x is True for x in lits):
            return True
        rest = [x for x in lits if x is not False]
        if not rest:
            return False
        if len(rest) == 1:
            return rest[0]
        v = self._new()
        self._both([-v, *rest])
        for x in rest:
            self._both([v, -x])
        return v

    @staticmethod
    def _neg(x: Lit) -> Lit:
        return (not x) if isinstance(x, bool) else -x

    def _and(self, a: Lit, b: Lit) -> Lit:
        return self._neg(self._or([self._neg(a), self._neg(b)]))

    def _guard(self, g) -> Lit:
        return True if g is None else self.enc.guard_lit(g)

    def exclude(self, clause: Sequence[GuardLit]) -> None:
        """A clause over the selectors that every solution satisfies."""
        self._both([self.enc.guard_lit(g) for g in clause])

    def add(self, cex: Counterexample) -> None:
        """Learn "where ``cex.plan`` runs at ``cex.cost``, a solution's plan costs the human at
        most ``cex.cost``": a symbolic run of the plan over the selectors decides, exactly,
        every condition it reads; each condition is a literal true iff it holds."""
        family = self.family
        acts = [family.actions[family.action_index[s]] for s in cex.plan]
        relevant = {p for p, _ in family.goal}
        for a in acts:
            relevant.update(p for p, _ in a.pre)
            relevant.update(p for p, _ in a.negpre)
        value = {p: self._or([self._guard(g) for q, g in family.init if q == p]) for p in relevant}
        holds: list[Lit] = []
        for a in acts:
            holds.append(self._guard(a.exists))
            for p, g in a.pre:
                holds.append(self._or([self._neg(self._guard(g)), value[p]]))
            for p, g in a.negpre:
                holds.append(self._or([self._neg(self._guard(g)), self._neg(value[p])]))
            if len({v for _, v in a.cost}) > 1:
                # the cost case that applies in cex.selection must apply
                for guards, _ in a.cost:
                    if all((i in cex.selection) == v for i, v in guards):
                        holds.extend(self.enc.guard_lit(g) for g in guards)
                        break
            after = {}
            for p in relevant:
                adds = [self._guard(g) for q, g in a.add if q == p]
                dels = [self._guard(g) for q, g in a.delete if q == p]
                if adds or dels:
                    # delete-then-add
                    after[p] = self._or(
                        [self._or(adds), self._and(value[p], self._neg(self._or(dels)))]
                    )
            value.update(after)
        for p, g in family.goal:
            holds.append(self._or([self._neg(self._guard(g)), value[p]]))
        if any(h is False for h in holds):
            return  # the plan runs in no model (it ran in cex.selection: cannot happen)
        fails = [-h for h in holds if h is not True]
        cost = self.enc.cost_assumptions(HUMAN, cex.cost, self.horizon)
        if cost:  # [] cannot bite
            self.main.add_clause(fails + cost)
        v = self._new()
        self.cover.add_clause([*fails, v])
        self.covered.append((cex.cost, v))

    # ----------------------------------------------------------------- queries
    def _size(self, k: int) -> list[int]:
        return [] if self.card is None or k >= self.n else [-self.card.rhs[k]]

    def candidate(self, k: int, robot_bound: int | None, h: int, solve: Callable):
        """A selection of at most ``k`` updates and a joint plan of at most ``h`` steps, robot
        cost ``<= robot_bound``, that no counterexample refutes; ``None`` if there is none."""
        enc = self.enc
        robot = enc.cost_assumptions(ROBOT, robot_bound, self.horizon)
        if robot is None:
            return None
        ok = solve(self.main, enc.goal_assumptions(h) + self._size(k) + robot)
        if not ok:
            return None
        model = self.main.get_model()
        return enc.decode_selection(model), enc.decode_plan(model, h)

    def uncovered(self, k: int, below: int, solve: Callable) -> frozenset[int] | None:
        """A selection of at most ``k`` updates in which no counterexample of cost ``< below``
        runs (``None``: every such selection has a plan cheaper than ``below``)."""
        cheap = [-v for c, v in self.covered if c < below]
        if not solve(self.cover, self._size(k) + cheap):
            return None
        true = {lit for lit in self.cover.get_model() if lit > 0}
        return frozenset(i for i in range(self.n) if self.enc.e(i) in true)


def plan_costs(orc, sel: frozenset[int], plan) -> tuple[int, int]:
    family = orc.family
    rc = ground_plan_cost(orc.task(family.robot_selection), plan)
    hc = ground_plan_cost(orc.task(sel), plan)
    assert rc is not None and hc is not None, "the joint formula's plan must run in both models"
    return rc, hc


def usable(orc, weighted: bool) -> str | None:
    """Why the counterexample loop cannot give an exact frontier here (``None``: it can)."""
    if weighted:
        return "update costs"
    if orc.c_min <= 0 or orc.joint_oracle.c_min_robot <= 0:
        return "zero-cost actions"
    return None


def use_counterexample_loop(orc, options, weighted: bool) -> bool:
    """Whether the sat engine's frontier comes from this loop: on tasks with at least
    ``options.counterexample_loop_updates`` updates, where its answers are proofs."""
    most = options.counterexample_loop_updates
    return 0 < most <= orc.family.n_updates and usable(orc, weighted) is None


def human_steps(orc, cost: int) -> int:
    """Steps any plan of human cost ``<= cost`` fits in, in every model of the family."""
    return max((cost - orc.joint_oracle.extra_human) // orc.c_min, 0)


def robot_steps(orc, bound: int) -> int:
    """Steps any joint plan of robot cost ``<= bound`` fits in (with human-cost dominance, its
    human cost is ``<= bound`` too)."""
    j = orc.joint_oracle
    h = max((bound - j.extra_robot) // j.c_min_robot, 0)
    if j.always_dominates:
        h = min(h, human_steps(orc, bound))
    return h


class HandOver(Exception):  # noqa: N818 - the loop hands the task to the hitting-set loop
    """The counterexample loop cannot prove its answers here (a horizon past the cap)."""


@dataclass(frozen=True)
class LoopResult:
    points: list
    complete: bool
    exact: bool  # every OPT answer it used was a proof
    next_size: int | None  # every selection smaller than this is ruled out (time limit)


def counterexample_frontier(
    orc,
    *,
    c_robot: int,
    opt_of: Callable,
    unsolvable_clause: Callable,
    joint_alone: Callable,
    landmarks: Sequence[int],
    pairs,
    make_point: Callable,
    deadline,
    progress,
    stats: dict,
    notes: list,
    solver: str,
    options,
) -> LoopResult:
    """The frontier by the counterexample loop (see the module docstring).

    Levels ``k = 0, 1, ...`` bound ``|E|``; at each level candidates come from the formula
    until it has none within the robot bound ``K``; a candidate that OPT confirms is the best
    so far at this level and lowers ``K``.  While ``K`` is unbounded, an empty level is only
    proven once every selection of the level has a counterexample cheaper than the cost at
    which plans stop fitting the formula's horizon; a selection without one is settled by h^2
    on the product, a cheap plan, or OPT (a counterexample, an unsolvable core, a longer
    formula or JOINT alone)."""
    cap = options.horizon_cap
    formula: list[CounterexampleFormula] = []
    learned: list = []  # counterexamples and exclusions, replayed into a longer formula
    cx = CounterexampleStats()
    exact = [True]

    def solve(solver_, assumptions):
        return orc.solving.solve(solver_, assumptions)

    def build(h: int) -> CounterexampleFormula:
        if h > cap:
            raise HandOver(f"the counterexample formula needs {h} steps > horizon cap {cap}")
        if formula:
            formula.pop().close()
        f = CounterexampleFormula(orc, h, solver)
        for item in learned:
            if isinstance(item, Counterexample):
                f.add(item)
            else:
                f.exclude(item)
        formula.append(f)
        cx.formula_horizons.append(h)
        return f

    def learn(item) -> None:
        learned.append(item)
        if isinstance(item, Counterexample):
            cx.counterexamples += 1
            formula[0].add(item)
        else:
            formula[0].exclude(item)
            stats["learned"] += 1
            stats["learned_literals"] += len(item)

    def cheaper(sel: frozenset[int], bound: int) -> bool:
        """Learn a plan of ``human + sel`` costing at most ``bound`` as a counterexample, if
        one SAT call within ``counterexample_plan_conflicts`` finds it: finding a plan is
        cheap where proving an optimum is not."""
        budget = options.counterexample_plan_conflicts
        if budget <= 0 or bound < 0:
            return False
        got = orc.plan_within(
            sel, bound, budget, max_action_steps=options.joint_sat_action_steps or None
        )
        if got is None:
            return False
        cx.plans_found += 1
        learn(Counterexample(tuple(got[0]), got[1], sel))
        return True

    def no_joint_plan(sel: frozenset[int]) -> bool:
        """Exclude ``sel`` when h^2 on the product of the robot model and the models agreeing
        with it shows no joint plan at any length, with the updates it keeps by deletion."""
        if pairs is None:
            return False
        on = set(range(n))
        if not pairs.no_joint_plan(sel, frozenset(on)):
            return False
        for i in range(n):
            if pairs.no_joint_plan(sel, frozenset(on - {i})):
                on.discard(i)
        stats["joint_cores_without_plan"] += 1
        learn(exclusion_clause(sel, on))
        return True

    def check(sel: frozenset[int]):
        """OPT of ``sel``: its result, with an exclusion learned if it has no plan."""
        opt = opt_of(sel)
        stats["opt_calls"] += 1
        if opt.plan is None or not opt.status.decided:
            learn(unsolvable_clause(sel, opt))
            return None
        if not opt.exact:
            notes.append(f"OPT not proven optimal (|E|={len(sel)}): {opt.reason}")
            exact[0] = False
        return opt

    build(max(human_steps(orc, c_robot), 1))
    for i in landmarks:
        learn(((i, True),))
    points: list = []
    bound: int | None = None
    k = 0
    best = None
    n = orc.family.n_updates
    try:
        while k <= n:
            if deadline.expired():
                return LoopResult(points, False, exact[0], k)
            progress.lower_bound = k
            progress.step(k)
            f = formula[0]
            h = f.horizon if bound is None else robot_steps(orc, bound)
            if h > f.horizon:
                f = build(h)
            stats["iterations"] += 1
            got = f.candidate(k, bound, h, solve)
            if got is None:
                if bound is None:
                    # plans longer than the horizon cost every model of the level at least
                    # `below`; a model with a cheaper counterexample has no such solution
                    below = (f.horizon + 1) * orc.c_min + orc.joint_oracle.extra_human
                    cx.coverage_checks += 1
                    sel = f.uncovered(k, below, solve)
                    if sel is not None:
                        if no_joint_plan(sel) or cheaper(sel, below - 1):
                            continue
                        opt = check(sel)
                        if opt is not None:
                            if opt.cost < below:
                                learn(Counterexample(tuple(opt.plan), opt.cost, sel))
                            elif human_steps(orc, opt.cost) * 2 <= f.horizon * 3:
                                # a longer formula is cheaper than the JOINT proof below
                                build(human_steps(orc, opt.cost))
                            else:
                                # its plans may be longer than the formula's: JOINT alone
                                cx.joint_alone += 1
                                solution, clause = joint_alone(sel, opt)
                                if solution is not None:
                                    best = (sel, *solution)
                                    bound = solution[1] - 1
                                else:
                                    learn(clause)
                        continue
                if best is not None:
                    points.append(make_point(*best))
                    progress.points.append(points[-1])
                    if best[2] <= c_robot:
                        return LoopResult(points, True, exact[0], None)
                    best = None
                k += 1
                continue
            sel, plan = got
            rc, hc = plan_costs(orc, sel, plan)
            if cheaper(sel, hc - 1):
                continue
            opt = check(sel)
            if opt is None:  # cannot happen: the plan runs in human + sel
                continue
            if hc <= opt.cost:
                best = (sel, plan, rc, hc)
                bound = rc - 1
            else:
                learn(Counterexample(tuple(opt.plan), opt.cost, sel))
        return LoopResult(points, True, exact[0], None)
    finally:
        stats["counterexamples"] = cx.counterexamples
        stats["coverage_checks"] = cx.coverage_checks
        stats["counterexample_joint_alone"] = cx.joint_alone
        stats["counterexample_plans_by_sat"] = cx.plans_found
        stats["counterexample_horizons"] = cx.formula_horizons
        for f in formula:
            f.close()
