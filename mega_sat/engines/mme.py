"""MME: the smallest explanation after which no further update can make a plan non-optimal.

For a plan ``pi`` optimal in the robot model, an MME is a smallest ``E`` such that ``pi`` is
optimal in ``human + E'`` for every ``E'`` with ``E <= E' <= Delta`` (a monotonic explanation:
whatever else the human later learns of the robot's model, ``pi`` stays optimal).  MCE asks
this for ``E' = E`` only, so ``|MCE| <= |MME|``.

The search is a hitting-set loop over *positive* clauses ("``E`` must contain one of these
updates").  A candidate ``E`` is refuted by a witness: a superset ``E'`` in which ``pi`` is not
optimal (it fails, or another plan is cheaper), found by simulation, by one OPT call at
``E' = E``, or else by an exhaustive search over pairs (state, partial selection of the updates
outside ``E``).  The witness generalises to the clause "``E`` must contain an update of
``S \\ E'``", where ``S`` is the support of the evidence (``support(pi)`` for a failing ``pi``,
``costs(pi) ∪ causal_support(E', pi')`` for a cheaper ``pi'``); ``E'`` is first grown while it
stays a witness, which shrinks the clause.  A candidate without a witness is an MME: the
clauses only remove sets that have a non-monotonic superset.  The argument is in
``encodings/mme.md``.
"""

from __future__ import annotations

import heapq
import itertools
import time
from collections.abc import Sequence
from dataclasses import dataclass

from mega_sat.deadline import Deadline
from mega_sat.engines.hitting_set import make_hitting_set
from mega_sat.engines.progress import Progress
from mega_sat.engines.support import causal_support, support
from mega_sat.errors import PlannerError, UsageError
from mega_sat.ground.family import GroundFamily, Guard
from mega_sat.ground.simulate import simulate, simulate_ground
from mega_sat.model.lifted import PlanStep
from mega_sat.model.task import TwoModelTask
from mega_sat.options import DEFAULT, Options
from mega_sat.pddl.update_costs import explanation_cost
from mega_sat.planners.node_planner import NodePlanner, require_robot_plan
from mega_sat.results import Explanation
from mega_sat.status import Status


@dataclass(frozen=True)
class Evidence:
    """Why ``plan`` is not optimal in ``human + selection``: it fails there (``cheaper`` is
    ``None``), or ``cheaper`` runs there at a lower cost.  Every selection that agrees with
    ``selection`` on ``support`` has the same evidence."""

    selection: frozenset[int]
    cheaper: tuple[PlanStep, ...] | None
    support: frozenset[int]


@dataclass(frozen=True)
class _Decisions:
    """A partial selection: updates decided in (``on``) or out (``off``), as bitmasks; the rest
    is still free."""

    on: int
    off: int

    def status(self, g: Guard) -> bool | None:
        """Whether a guarded component is present (``None``: not decided yet)."""
        if g is None:
            return True
        bit = 1 << g[0]
        if self.on & bit:
            return g[1]
        if self.off & bit:
            return not g[1]
        return None

    def make(self, g: Guard, present: bool) -> _Decisions | None:
        """These decisions plus "``g`` is ``present``" (``None`` if that contradicts them)."""
        st = self.status(g)
        if st is not None:
            return self if st == present else None
        assert g is not None
        bit = 1 << g[0]
        if g[1] == present:
            return _Decisions(self.on | bit, self.off)
        return _Decisions(self.on, self.off | bit)


def _mask_set(mask: int) -> frozenset[int]:
    return frozenset(i for i in range(mask.bit_length()) if mask >> i & 1)


def _branches(d: _Decisions, indices: set[int]):
    """Every way to decide the free updates among ``indices``."""
    free = sorted(i for i in indices if not ((d.on | d.off) >> i & 1))
    for values in itertools.product((False, True), repeat=len(free)):
        on, off = d.on, d.off
        for i, v in zip(free, values, strict=True):
            if v:
                on |= 1 << i
            else:
                off |= 1 << i
        yield _Decisions(on, off)


EffectGroup = tuple[int, tuple[Guard, ...], tuple[Guard, ...]]
"""A relevant atom an action adds or deletes under some guard: ``(atom, add guards, delete
guards)``."""


def _effect_groups(action, relevant: int) -> tuple[EffectGroup, ...]:
    """The relevant atoms whose fate under ``action`` can depend on the selection (an atom
    with an unguarded add is always added; one with unguarded entries only is fixed)."""
    atoms = sorted({p for p, _ in action.add + action.delete if relevant >> p & 1})
    out = []
    for p in atoms:
        adds = tuple(g for q, g in action.add if q == p)
        dels = tuple(g for q, g in action.delete if q == p)
        if None in adds or all(g is None for g in adds + dels):
            continue
        out.append((p, adds, dels))
    return tuple(out)


def _effect_updates(groups: tuple[EffectGroup, ...], s: int, d: _Decisions) -> set[int]:
    """The free updates whose value changes the relevant part of an action's successor of
    ``s`` (delete-then-add: an atom ends true iff an add is present, or it was true and no
    delete is present)."""
    out: set[int] = set()
    for p, adds, dels in groups:
        st_add = [d.status(g) for g in adds]
        if True in st_add:
            continue  # added whatever else happens
        free_add = {g[0] for g, st in zip(adds, st_add, strict=True) if st is None}
        if not s >> p & 1:
            out |= free_add
            continue
        st_del = [d.status(g) for g in dels]
        if all(st is False for st in st_del):
            continue  # true and never deleted
        out |= free_add
        out |= {g[0] for g, st in zip(dels, st_del, strict=True) if st is None}
    return out


def _successor(action, s: int, d: _Decisions, relevant: int) -> int:
    """The relevant part of the state after ``action`` (its effect guards decided enough)."""
    dels = adds = 0
    for p, g in action.delete:
        if relevant >> p & 1 and d.status(g):
            dels |= 1 << p
    for p, g in action.add:
        if relevant >> p & 1 and d.status(g):
            adds |= 1 << p
    return (s & ~dels) | adds


def _cost_updates(action, d: _Decisions) -> set[int]:
    """The free updates that decide which cost case of ``action`` applies, if that matters."""
    if len({v for _, v in action.cost}) == 1:
        return set()
    return {i for guards, _ in action.cost for i, _ in guards if d.status((i, True)) is None}


def _cost(action, d: _Decisions) -> int:
    """``action``'s cost under ``d`` (its cost guards decided where the cases differ)."""
    values = {v for _, v in action.cost}
    if len(values) == 1:
        return next(iter(values))
    for guards, v in action.cost:
        if all(d.status(g) for g in guards):
            return v
    raise AssertionError("no cost case applies")


def _applicable(action, s: int, d: _Decisions) -> _Decisions | None:
    """Decisions under which ``action`` applies in ``s`` (existence present, every unsatisfied
    condition absent); ``None`` when no completion of ``d`` allows it.  Satisfied conditions
    need no decision."""
    d2 = d.make(action.exists, True)
    if d2 is None:
        return None
    for p, g in action.pre:
        if not s >> p & 1:
            d2 = d2.make(g, False)
            if d2 is None:
                return None
    for p, g in action.negpre:
        if s >> p & 1:
            d2 = d2.make(g, False)
            if d2 is None:
                return None
    return d2


def _goal_reached(family: GroundFamily, s: int, d: _Decisions) -> _Decisions | None:
    """Decisions under which ``s`` satisfies the goal (every goal entry whose atom is false
    absent), or ``None``."""
    for p, g in family.goal:
        if not s >> p & 1:
            d = d.make(g, False)
            if d is None:
                return None
    return d


def _initial(family: GroundFamily, d: _Decisions, relevant: int):
    """``(state, decisions)`` for every way to decide the free initial-state updates."""
    free = {g[0] for p, g in family.init if g and relevant >> p & 1}
    for d2 in _branches(d, free):
        s = 0
        for p, g in family.init:
            if relevant >> p & 1 and d2.status(g):
                s |= 1 << p
        yield s, d2


def failing_superset(
    family: GroundFamily, plan: Sequence[PlanStep], selection: frozenset[int]
) -> frozenset[int] | None:
    """A superset of ``selection`` in which ``plan`` does not run (or misses the goal), or
    ``None`` when it runs in every superset.

    Exhaustive: the plan is followed step by step from every initial state, branching only
    on the free updates that change a relevant atom; a condition whose update is still free
    and would fail if present is a failure."""
    acts = [family.actions[family.action_index[tuple(s)]] for s in plan]
    relevant = _condition_atoms(family, acts)
    groups = {a.step: _effect_groups(a, relevant) for a in acts}
    start = _Decisions(sum(1 << i for i in selection), 0)
    layer = set(_initial(family, start, relevant))
    full = (1 << family.n_updates) - 1

    def witness(d: _Decisions) -> frozenset[int]:
        return _mask_set(full & ~d.off)

    for a in acts:
        nxt = set()
        for s, d in layer:
            if (fail := d.make(a.exists, False)) is not None:
                return witness(fail)
            for p, g in a.pre:
                if not s >> p & 1 and (fail := d.make(g, True)) is not None:
                    return witness(fail)
            for p, g in a.negpre:
                if s >> p & 1 and (fail := d.make(g, True)) is not None:
                    return witness(fail)
            for d2 in _branches(d, _effect_updates(groups[a.step], s, d)):
                nxt.add((_successor(a, s, d2, relevant), d2))
        layer = nxt
    for s, d in layer:
        for p, g in family.goal:
            if not s >> p & 1 and (fail := d.make(g, True)) is not None:
                return witness(fail)
    return None


def _condition_atoms(family: GroundFamily, acts: Sequence) -> int:
    """The atoms some condition of ``acts`` or the goal reads, as a bit mask: the only atoms
    whose values the superset searches track."""
    relevant = 0
    for a in acts:
        for p, _ in a.pre + a.negpre:
            relevant |= 1 << p
    for p, _ in family.goal:
        relevant |= 1 << p
    return relevant


def cheaper_superset(
    family: GroundFamily,
    plan: Sequence[PlanStep],
    selection: frozenset[int],
    deadline: Deadline,
    counter: dict[str, int] | None = None,
) -> tuple[frozenset[int], tuple[PlanStep, ...]] | None:
    """A superset ``E'`` of ``selection`` and a plan of ``human + E'`` cheaper there than
    ``plan`` (which runs in every superset), or ``None`` when there is none.

    A* over (relevant state, partial selection): updates outside ``selection`` start free
    and are decided only where a step, the initial state, the goal or ``plan``'s own cost
    depends on them; a node is pruned once its cost plus ``h`` reaches ``plan``'s cost under
    the node's decisions.  ``h`` is h^max of the abstraction of every superset of
    ``selection``, so admissible for every completion of a node's decisions.  Zero-cost
    actions are fine (no horizon).  ``E'`` sets every update left free to "explained"."""
    from mega_sat.analysis.abstraction import abstract_task
    from mega_sat.analysis.relaxation import RelaxedTask

    acts = family.actions
    relevant = _condition_atoms(family, acts)
    # the conditions without a guard as masks (most actions fail one at most nodes), and the
    # effects that can depend on the selection
    unguarded = [
        (
            j,
            a,
            sum(1 << p for p, g in a.pre if g is None),
            sum(1 << p for p, g in a.negpre if g is None),
            _effect_groups(a, relevant),
        )
        for j, a in enumerate(acts)
    ]
    n = len(family.atoms)
    relaxed = RelaxedTask(abstract_task(family, selection, selection))
    # an untracked atom may be true or false: both of its facts (only lowers h^max)
    untracked = [p for p in range(n) if not relevant >> p & 1]
    untracked += [n + p for p in untracked]
    tracked = [p for p in range(n) if relevant >> p & 1]
    h_cache: dict[int, float] = {}

    def h(s: int) -> float:
        if (v := h_cache.get(s)) is None:
            facts = untracked + [p if s >> p & 1 else n + p for p in tracked]
            v = h_cache[s] = relaxed.h_max(facts)
        return v

    plan_acts = [acts[family.action_index[tuple(s)]] for s in plan]
    pi_costs = {i for a in plan_acts for guards, _ in a.cost for i, _ in guards}
    full = (1 << family.n_updates) - 1
    start = _Decisions(sum(1 << i for i in selection), 0)
    tie = itertools.count()
    heap: list[tuple[float, int, int, int, _Decisions, int]] = []
    best: dict[tuple[int, _Decisions], int] = {}
    parent: dict[tuple[int, _Decisions], tuple[tuple[int, _Decisions], int] | None] = {}
    for d0 in _branches(start, pi_costs):
        bound = sum(_cost(a, d0) for a in plan_acts) - 1
        if bound < 0:
            continue  # nothing is cheaper than a plan of cost 0
        for s, d in _initial(family, d0, relevant):
            if (s, d) not in best and h(s) <= bound:
                best[(s, d)] = 0
                parent[(s, d)] = None
                heapq.heappush(heap, (h(s), next(tie), 0, s, d, bound))
    expanded = 0
    while heap:
        _, _, g, s, d, bound = heapq.heappop(heap)
        if best[(s, d)] < g:
            continue
        if (done := _goal_reached(family, s, d)) is not None:
            steps = []
            key: tuple[int, _Decisions] | None = (s, d)
            while (link := parent[key]) is not None:
                key, j = link
                steps.append(acts[j].step)
            if counter is not None:
                counter["expanded"] = counter.get("expanded", 0) + expanded
            return _mask_set(full & ~done.off), tuple(reversed(steps))
        expanded += 1
        # every expansion: one passes over every action and takes h^max of its successors,
        # so on large families a few hundred of them take seconds
        deadline.check()
        for j, a, hard_pre, hard_neg, groups in unguarded:
            if s & hard_pre != hard_pre or s & hard_neg:
                continue  # a condition every model has fails
            d1 = _applicable(a, s, d)
            if d1 is None:
                continue
            free = _effect_updates(groups, s, d1) | _cost_updates(a, d1)
            for d2 in _branches(d1, free):
                g2 = g + _cost(a, d2)
                if g2 > bound:
                    continue
                s2 = _successor(a, s, d2, relevant)
                old = best.get((s2, d2))
                if old is not None and old <= g2:
                    continue
                f2 = g2 + h(s2)
                if f2 > bound:
                    continue
                best[(s2, d2)] = g2
                parent[(s2, d2)] = ((s, d), j)
                heapq.heappush(heap, (f2, next(tie), g2, s2, d2, bound))
    if counter is not None:
        counter["expanded"] = counter.get("expanded", 0) + expanded
    return None


def _cheaper_impossible(family: GroundFamily, plan_acts, selection: frozenset[int]) -> bool:
    """LM-cut of the abstraction of every superset of ``selection`` reaches ``plan``'s
    greatest cost over those supersets: no superset has a cheaper plan (a cheap proof that
    often settles the final candidate without a search)."""
    from mega_sat.analysis.abstraction import abstract_task
    from mega_sat.analysis.relaxation import RelaxedTask

    greatest = 0
    for a in plan_acts:
        greatest += max(
            v for guards, v in a.cost if all(i not in selection or val for i, val in guards)
        )
    abstraction = abstract_task(family, selection, selection)
    return RelaxedTask(abstraction).lmcut(sorted(abstraction.init)) >= greatest


def minimally_monotonic_explanation(
    task: TwoModelTask,
    family: GroundFamily,
    plan: Sequence[PlanStep] | None = None,
    *,
    planner: str = "builtin",
    hitting_set: str = "rc2",
    oracles=None,
    timeout: float | None = None,
    deadline: Deadline | None = None,
    progress: Progress | None = None,
    update_costs: tuple[int, ...] | None = None,
    options: Options = DEFAULT,
) -> Explanation:
    """Smallest ``E`` such that ``plan`` (default: a robot-optimal plan) is optimal in
    ``human + E'`` for every ``E <= E' <= Delta`` (with ``update_costs``: the cheapest by the
    sum of its updates' costs; the learned clauses do not depend on costs).  ``progress``
    shows each candidate as it is checked (for a live display).

    A plan that is not optimal in the robot model (``human + Delta``) has no MME and is
    refused with its cost and the robot optimum.  Stops at ``deadline`` (or ``timeout``
    seconds from now) with :class:`~mega_sat.deadline.TimeLimitReached`: like MCE there is no
    partial answer.  ``options``: the tuning knobs of the planner."""
    t0 = time.perf_counter()
    progress = progress if progress is not None else Progress()
    progress.start("mme", tuple(u.name for u in task.delta))
    deadline = deadline if deadline is not None else Deadline.after(timeout)
    np_ = NodePlanner(task, family, planner, oracles=oracles, deadline=deadline, options=options)
    r = np_.optimal(family.robot_selection)
    require_robot_plan(task, r)
    if plan is None:
        plan = r.plan
    plan = tuple(tuple(s) for s in plan)
    sim_r = simulate(task.robot, plan)
    if not sim_r.valid:
        raise UsageError(f"the plan is not executable in the robot model: {sim_r.reason}")
    if sim_r.cost > r.cost:
        raise UsageError(_not_robot_optimal(sim_r.cost, r.cost))
    plan_acts = [family.actions[family.action_index[s]] for s in plan]
    cost_guards = frozenset(i for a in plan_acts for guards, _ in a.cost for i, _ in guards)
    hints: list[tuple[PlanStep, ...]] = []
    calls = {"candidates": 0, "learned": 0, "searches": 0, "expanded": 0}

    def evidence(sel: frozenset[int], extra=(), use_opt: bool = True) -> Evidence | None:
        """Proof that ``plan`` is not optimal in ``human + sel``, or ``None`` if none is found
        (``plan`` runs there, and neither a known plan nor OPT, with ``use_opt``, is
        cheaper)."""
        ground = family.specialize(sel)
        sim = simulate_ground(ground, plan)
        if not sim.valid:
            return Evidence(sel, None, support(family, plan))
        for h in (*extra, *reversed(hints)):
            other = simulate_ground(ground, h)
            if other.valid and other.cost < sim.cost:
                return Evidence(sel, h, cost_guards | _indices(causal_support(family, sel, h)))
        if not use_opt:
            return None
        opt = np_.optimal(sel)
        if opt.status == Status.OPTIMAL and opt.cost < sim.cost:
            hints.append(opt.plan)
            return Evidence(
                sel, opt.plan, cost_guards | _indices(causal_support(family, sel, opt.plan))
            )
        return None

    def grown(ev: Evidence) -> frozenset[int]:
        """The clause of ``ev`` after growing its selection while it stays a witness (shown
        by simulation alone: an OPT call per try would cost more than the clause saves)."""
        clause = ev.support - ev.selection
        tried: set[int] = set()
        while True:
            for i in sorted(clause - tried):
                tried.add(i)
                deadline.check()
                extra = (ev.cheaper,) if ev.cheaper else ()
                bigger = evidence(ev.selection | {i}, extra, use_opt=False)
                if bigger is not None:
                    ev = bigger
                    clause = ev.support - ev.selection
                    break
            else:
                return clause

    hs = make_hitting_set(hitting_set, len(task.delta), deadline=deadline, costs=update_costs)
    try:
        while True:
            deadline.check()
            sel = hs.minimum()
            if sel is not None:
                progress.step(len(sel))
            if sel is None:
                deadline.check()  # time running out is never the plan's fault
                # only a witness at Delta itself empties a clause: a cheaper robot plan
                found = cheaper_superset(family, plan, family.robot_selection, deadline)
                robot = family.specialize(family.robot_selection)
                better = simulate_ground(robot, found[1]).cost if found else r.cost
                raise UsageError(_not_robot_optimal(sim_r.cost, better))
            calls["candidates"] += 1
            ev = evidence(sel)
            if ev is None:
                calls["searches"] += 1
                bigger = failing_superset(family, plan, sel)
                if bigger is None:
                    if sel == family.robot_selection and r.exact:
                        found = None  # the robot model is the only superset: proven above
                    elif _cheaper_impossible(family, plan_acts, sel):
                        found = None
                    else:
                        found = cheaper_superset(family, plan, sel, deadline, calls)
                    if found is None:
                        human = simulate_ground(family.specialize(sel), plan)
                        return Explanation(
                            plan=plan,
                            explanation=tuple(task.names(sel)),
                            selection=sel,
                            robot_cost=sim_r.cost,
                            human_cost=human.cost,
                            exact=True,
                            time_s=time.perf_counter() - t0,
                            stats={
                                **calls,
                                "opt_calls": np_.calls,
                                "planner": planner,
                                "hitting_set": hitting_set,
                                "hitting_set_calls": hs.calls,
                            },
                            kind="mme",
                            weighted_cost=None
                            if update_costs is None
                            else explanation_cost(sel, update_costs),
                        )
                    bigger, cheaper = found
                    ev = evidence(bigger, (cheaper,))
                else:
                    ev = evidence(bigger)
                if ev is None or not sel <= ev.selection:
                    raise PlannerError("internal: a superset witness did not check out")
            hs.add((i, True) for i in grown(ev))
            calls["learned"] += 1
    finally:
        hs.close()


def _indices(lits) -> frozenset[int]:
    return frozenset(i for i, _ in lits)


def _not_robot_optimal(cost: int, optimum: int) -> str:
    return (
        f"the plan is not optimal in the robot model (it costs {cost}, the robot optimum is "
        f"{optimum}): only a robot-optimal plan has an MME"
    )
