"""Which updates a plan's behaviour depends on, and the clauses learned from failed candidates.

``support(plan)`` is the set of updates whose flip could change whether ``plan`` executes in a
model of the family, or what it costs there.  Any selection that agrees with ``E`` on
``support(plan)`` runs ``plan`` exactly as ``human + E`` does (same relevant atoms at every
step, same preconditions, same cost) — see ``encodings/hitting-set.md`` for the argument.  That
is what makes a learned clause ``NOT(E restricted to core ∪ support)`` generalise beyond ``E``.
"""

from __future__ import annotations

from collections.abc import Iterable, Sequence

from mega_sat.deadline import NO_DEADLINE, Deadline
from mega_sat.ground.family import GroundFamily, GuardLit
from mega_sat.model.lifted import PlanStep
from mega_sat.options import DEFAULT
from mega_sat.status import Status


def support(family: GroundFamily, plan: Sequence[PlanStep]) -> frozenset[int]:
    """Updates that can change ``plan``'s executability, goal achievement or cost."""
    acts = [family.actions[family.action_index[s]] for s in plan]
    relevant = {p for a in acts for p, _ in a.pre + a.negpre}
    relevant.update(p for p, _ in family.goal)
    out: set[int] = set()
    for a in acts:
        if a.exists:
            out.add(a.exists[0])
        out.update(g[0] for _, g in a.pre + a.negpre if g)
        out.update(g[0] for p, g in a.add + a.delete if g and p in relevant)
        out.update(i for guards, _ in a.cost for i, _ in guards)
    out.update(g[0] for p, g in family.init if g and p in relevant)
    out.update(g[0] for _, g in family.goal if g)
    return frozenset(out)


def exclusion_clause(selection: frozenset[int], on: Iterable[int]) -> tuple[GuardLit, ...]:
    """The clause ``NOT(selection restricted to on)``: some update in ``on`` must differ."""
    return tuple(sorted((i, i not in selection) for i in set(on)))


def _relaxed_goal_reachable(
    family: GroundFamily, selection: frozenset[int], fixed: frozenset[int]
) -> bool:
    """Delete-relaxed reachability of the goal in the most permissive model that agrees with
    ``selection`` on ``fixed``: an unfixed guard counts as present for initial atoms, add
    effects and schema existence, and as absent for preconditions and goals."""

    def present(g, helps: bool) -> bool:
        if g is None:
            return True
        if g[0] not in fixed:
            return helps
        return (g[0] in selection) == g[1]

    reached = {p for p, g in family.init if present(g, True)}
    acts = [a for a in family.actions if present(a.exists, True)]
    changed = True
    while changed:
        changed = False
        rest = []
        for a in acts:
            if all(p in reached for p, g in a.pre if present(g, False)):
                for p, g in a.add:
                    if p not in reached and present(g, True):
                        reached.add(p)
                        changed = True
            else:
                rest.append(a)
        acts = rest
    return all(p in reached for p, g in family.goal if present(g, False))


class Ic3Streak:
    """IC3's record on the cut-short trials of one run's unsolvable cores: after ``limit``
    runs in a row that reach their query limit (no proof between them; a run that finds the
    abstraction has a plan does not count), IC3 is not tried again in the run.  Where the
    invariants exist, the proofs come early and in runs; where none is found within the
    limit, each run costs the whole limit and proves nothing.  Counted in runs, not
    seconds, so the cores are the same on any machine."""

    def __init__(self, limit: int):
        self.limit = limit
        self.misses = 0

    def open(self) -> bool:
        return self.limit <= 0 or self.misses < self.limit

    def record(self, verdict: Status) -> None:
        if verdict == Status.UNSOLVABLE:
            self.misses = 0
        elif verdict != Status.PLAN:
            self.misses += 1


def unsolvable_core(
    family: GroundFamily,
    selection: frozenset[int],
    *,
    state_limit: int = DEFAULT.unsolvable_core_states,
    work_limit: int | None = None,
    trial_limit: int | None = None,
    trial_growth: int = DEFAULT.unsolvable_core_trial_growth,
    deadline: Deadline | None = None,
    cut_short: list[int] | None = None,
    ic3_queries: int = DEFAULT.unsolvable_core_ic3_queries,
    ic3_streak: Ic3Streak | None = None,
) -> frozenset[int] | None:
    """A set ``S`` of updates such that every selection agreeing with ``selection`` on ``S`` has
    no plan, for an unsolvable ``human + selection``; ``None`` when nothing smaller than "all
    updates" can be shown.

    Deletion from all updates: an update is dropped when the model stays unsolvable with it
    free.  Proofs, cheapest first: relaxed reachability of the most permissive model; then the
    may-reachable states (:class:`mega_sat.search.may_reachability.MayReachability`, at most
    ``state_limit`` of them, grown one freed update at a time); where those run past a limit
    (or the model's own reachable states exceed ``state_limit``), h^2 pair reachability of the
    abstraction with the update free (:func:`mega_sat.analysis.abstraction.abstract_task`),
    which needs no states.  (Where the may-reachable states reach the goal, the coarser pair
    abstraction does too, so it is not tried.)  The may-reachability proofs of one core
    visit at most ``work_limit`` states in all (a count, not seconds, so that the core is the
    same on any machine; the model's own reachable states do not count), and one trial adds at
    most ``max(trial_growth * |R|, trial_limit)`` states; a proof cut short proves nothing
    and keeps the update; with ``ic3_queries`` > 0, IC3 on that abstraction (at most that many
    SAT calls, :mod:`mega_sat.search.pdr`, starting from the core's last invariant) then
    tries to prove it has no plan, while ``ic3_streak`` (shared by a run's cores) is open.  Once
    ``deadline`` has passed no update is tried any more: the updates not yet dropped stay in
    ``S``, which is still sound, only larger.  ``cut_short`` (a list) receives the number of
    trials whose proof ran out of states or time.
    """
    from mega_sat.analysis.abstraction import abstract_task
    from mega_sat.analysis.pair_reachability import goal_pairs_reached, pair_masks
    from mega_sat.search.may_reachability import MayReachability

    deadline = deadline if deadline is not None else NO_DEADLINE
    everything = frozenset(range(family.n_updates))
    may: MayReachability | None = None  # built at the first update relaxed reachability keeps
    # updates dropped by another proof that the may-reachable states do not free yet
    pending: set[int] = set()
    short = 0

    def searched(i: int) -> Status:
        nonlocal may, short
        if may is None:
            may = MayReachability(
                family,
                selection,
                node_limit=state_limit,
                work_limit=work_limit,
                trial_limit=trial_limit,
                trial_growth=trial_growth,
                deadline=deadline,
            )
            short += not may.ok
        if not may.ok:
            return Status.LIMIT
        verdict = may.try_free(pending | {i})
        if verdict == Status.UNSOLVABLE:
            pending.clear()
        short += verdict in (Status.LIMIT, Status.TIMEOUT)
        return verdict

    # pair masks of an abstraction every later trial relaxes (its fixed set only shrinks):
    # each trial's fixpoint starts from them
    seed: list[int] | None = None

    def paired(trial: frozenset[int]) -> bool:
        nonlocal seed
        if seed is None:
            seed = pair_masks(abstract_task(family, selection, everything))
        task = abstract_task(family, selection, trial)
        masks = pair_masks(task, seed)
        if goal_pairs_reached(masks, task):
            return False
        seed = masks  # the trial becomes the fixed set
        return True

    # the cubes of the last invariant IC3 found: the next trial frees one more update, and
    # its abstraction (same atom ids) often keeps most of them
    lemmas: tuple = ()

    def invariant(trial: frozenset[int]) -> bool:
        """IC3 proves the abstraction with ``trial`` fixed unsolvable: an invariant where
        the pairs are too coarse and the states too many."""
        nonlocal lemmas
        if ic3_queries <= 0 or (ic3_streak is not None and not ic3_streak.open()):
            return False
        from mega_sat.search.pdr import Pdr

        with Pdr(abstract_task(family, selection, trial)) as pdr:
            pdr.seed(lemmas)  # no cubes yet: only the first frame, as run() would make
            verdict = pdr.run(ic3_queries, deadline=deadline)
            if ic3_streak is not None and verdict != Status.TIMEOUT:
                ic3_streak.record(verdict)
            if verdict != Status.UNSOLVABLE:
                return False
            lemmas = pdr.invariant()
            return True

    fixed = everything
    for i in sorted(everything):
        if deadline.expired():
            break
        trial = fixed - {i}
        if not _relaxed_goal_reachable(family, selection, trial):
            fixed = trial
            pending.add(i)
            continue
        verdict = searched(i)
        if verdict == Status.UNSOLVABLE:
            fixed = trial
        elif verdict != Status.PLAN and (paired(trial) or invariant(trial)):
            # neither proof needs states: they may succeed where R outgrew its limits
            fixed = trial
            pending.add(i)
    if cut_short is not None:
        cut_short.append(short)
    return None if fixed == everything else fixed


def tight_support(
    family: GroundFamily, selection: frozenset[int], plan: Sequence[PlanStep]
) -> tuple[GuardLit, ...]:
    """Literals that keep ``plan`` executable at no higher cost in every selection satisfying
    them, where ``plan`` runs in ``human + selection``.

    Tighter than :func:`support` because a precondition (or goal) whose atom already holds at
    that step of the plan's trajectory is satisfied whether or not the model has it: only
    conditions that are absent *and* would fail must stay absent.  The trajectory of every
    atom a condition mentions is kept identical by fixing the guards of its initial-state and
    effect entries; schema existence and cost cases are fixed as well.  (Argument in
    ``encodings/hitting-set.md``.)
    """
    from mega_sat.ground.family import holds

    acts = [family.actions[family.action_index[s]] for s in plan]
    relevant = {p for a in acts for p, _ in a.pre + a.negpre}
    relevant.update(p for p, _ in family.goal)
    fixed: set[int] = set()
    state = {p for p, g in family.init if holds(g, selection)}
    fixed.update(g[0] for p, g in family.init if g and p in relevant)
    for a in acts:
        if a.exists:
            fixed.add(a.exists[0])
        for p, g in a.pre:
            if g and p not in state:
                fixed.add(g[0])  # absent now (else the plan would fail): must stay absent
        for p, g in a.negpre:
            if g and p in state:
                fixed.add(g[0])
        fixed.update(i for guards, _ in a.cost for i, _ in guards)
        fixed.update(g[0] for p, g in a.add + a.delete if g and p in relevant)
        dels = {p for p, g in a.delete if holds(g, selection)}
        adds = {p for p, g in a.add if holds(g, selection)}
        state = (state - dels) | adds
    for p, g in family.goal:
        if g and p not in state:
            fixed.add(g[0])
    return tuple(sorted((i, i in selection) for i in fixed))


class _Links:
    """The causal links of a plan's run in ``human + selection``: :meth:`pin` fixes, in
    ``fixed``, the guards that keep an atom at its value before a step (shared by
    :func:`causal_support` and :func:`failure_core`)."""

    def __init__(self, family: GroundFamily, acts: list, selection: frozenset[int]):
        self.acts, self.selection = acts, selection
        self.fixed: set[int] = set()
        self.init_entries: dict[int, list] = {}
        for p, g in family.init:
            self.init_entries.setdefault(p, []).append(g)
        self._pinned: set[tuple[int, int, bool]] = set()

    def pin(self, p: int, t: int, value: bool) -> None:
        """Fix the guards that keep ``p`` at ``value`` just before step ``t``."""
        from mega_sat.ground.family import holds

        if (p, t, value) in self._pinned:
            return
        self._pinned.add((p, t, value))
        fixed, selection = self.fixed, self.selection
        for s in range(t - 1, -1, -1):
            a = self.acts[s]
            adds = [g for q, g in a.add if q == p]
            if value:
                present = [g for g in adds if holds(g, selection)]
                if present:  # the last achiever: one present add keeps p true after s
                    if None not in present:
                        fixed.add(present[0][0])
                    return
                # not added here, and p stays true: every delete of p here is absent
                fixed.update(g[0] for q, g in a.delete if q == p and g)
            else:
                fixed.update(g[0] for g in adds if g)  # every add absent, stays absent
                dels = [g for q, g in a.delete if q == p and holds(g, selection)]
                if dels:
                    if dels[0]:
                        fixed.add(dels[0][0])
                    return  # the last deleter
        here = self.init_entries.get(p, [])
        if not value:
            fixed.update(g[0] for g in here if g)  # absent initially, and stays absent
        elif None not in here:
            fixed.add(next(g for g in here if holds(g, selection))[0])


def causal_support(
    family: GroundFamily, selection: frozenset[int], plan: Sequence[PlanStep]
) -> tuple[GuardLit, ...]:
    """Like :func:`tight_support` (same guarantee, same use), but an atom's history is pinned
    only along the causal link that makes each condition hold, not as a whole.

    For a condition that holds at its step (a precondition whose atom is true, a negative
    precondition whose atom is false, a goal at the end), only the entries that decide the
    atom's value since its last change matter: for a true atom, the add (or initial) entry of
    its last achiever and the deletes after it, which are absent and must stay absent; for a
    false atom, the delete and the absent adds of its last deleter (or its absent initial
    entries) and the adds after it.  Entries outside these links may flip without changing
    the truth of any condition the plan looks at.  A condition that does not hold is absent
    (or the plan would fail) and its guard stays fixed, as in :func:`tight_support`.
    (Argument in ``encodings/hitting-set.md``, "The causal support".)
    """
    from mega_sat.ground.family import holds

    acts = [family.actions[family.action_index[s]] for s in plan]
    # the trajectory in human + selection: states[t] holds before step t
    state = {p for p, g in family.init if holds(g, selection)}
    states = [state]
    for a in acts:
        dels = {p for p, g in a.delete if holds(g, selection)}
        adds = {p for p, g in a.add if holds(g, selection)}
        state = (state - dels) | adds
        states.append(state)
    links = _Links(family, acts, selection)
    fixed = links.fixed
    pin = links.pin

    for t, a in enumerate(acts):
        if a.exists:
            fixed.add(a.exists[0])
        fixed.update(i for guards, _ in a.cost for i, _ in guards)
        for p, g in a.pre:
            if p in states[t]:
                pin(p, t, True)
            elif g:
                fixed.add(g[0])  # absent now (else the plan would fail): must stay absent
        for p, g in a.negpre:
            if p not in states[t]:
                pin(p, t, False)
            elif g:
                fixed.add(g[0])
    end = len(acts)
    for p, g in family.goal:
        if p in states[end]:
            pin(p, end, True)
        elif g:
            fixed.add(g[0])
    return tuple(sorted((i, i in selection) for i in fixed))


def failure_core(
    family: GroundFamily, selection: frozenset[int], plan: Sequence[PlanStep]
) -> tuple[GuardLit, ...] | None:
    """Literals under which ``plan`` fails in every selection satisfying them, where ``plan``
    does not run in ``human + selection``; ``None`` if it runs there.

    Much smaller than :func:`support`: only the first failure matters.  The failing component
    (the step's schema existence, its violated (negative) precondition, or the missed goal)
    keeps its guard, and the atom it looks at keeps its value at that point along the causal
    link of :func:`causal_support` (the last achiever or deleter and the absent entries after
    it).  In a selection satisfying the literals either an earlier step fails, or every earlier
    step runs with those same entries deciding the atom, so the same component fails.
    """
    from mega_sat.ground.family import holds

    acts = [family.actions[family.action_index[s]] for s in plan]
    links = _Links(family, acts, selection)
    fixed = links.fixed
    pin = links.pin

    def core() -> tuple[GuardLit, ...]:
        return tuple(sorted((i, i in selection) for i in fixed))

    state = {p for p, g in family.init if holds(g, selection)}
    for t, a in enumerate(acts):
        if not holds(a.exists, selection):
            fixed.add(a.exists[0])
            return core()
        for p, g in a.pre:
            if p not in state and holds(g, selection):
                if g:
                    fixed.add(g[0])
                pin(p, t, False)
                return core()
        for p, g in a.negpre:
            if p in state and holds(g, selection):
                if g:
                    fixed.add(g[0])
                pin(p, t, True)
                return core()
        dels = {p for p, g in a.delete if holds(g, selection)}
        adds = {p for p, g in a.add if holds(g, selection)}
        state = (state - dels) | adds
    for p, g in family.goal:
        if p not in state and holds(g, selection):
            if g:
                fixed.add(g[0])
            pin(p, len(acts), False)
            return core()
    return None
