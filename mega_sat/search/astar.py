"""Built-in optimal classical planner: explicit-state A* on a :class:`GroundTask`.

This is the per-node planner of the A* MEGA baseline and the independent optimal planner used by
verification, so it must be exactly optimal (also with zero-cost actions) and deterministic.

* States are ``int`` bitmasks over atom ids; applicability is two mask tests.
* Heuristics: ``lmcut`` (Helmert & Domshlak 2009, admissible), ``hmax`` and ``blind``.  Both
  relaxation heuristics ignore delete effects and negative preconditions, which only makes the
  relaxation weaker, so they stay admissible.  LM-cut is not consistent, so closed states are
  reopened when a cheaper path is found.
* Tie-breaking is deterministic: lower ``f``, then lower ``h``, then first generated (FIFO).
* ``UNSOLVABLE`` is returned only when the search space is exhausted or the goal is
  relaxed-unreachable from the initial state.

:class:`PlanResult` is the answer of every optimal planning call on one model, whichever planner
gives it (this search, Fast Downward, the SAT OPT oracle through
:class:`mega_sat.planners.node_planner.NodePlanner`).
"""

from __future__ import annotations

import heapq
import time
from collections.abc import Callable
from dataclasses import dataclass

from mega_sat.analysis.relaxation import RelaxedTask, bits
from mega_sat.deadline import NO_DEADLINE, Deadline
from mega_sat.ground.family import GroundTask
from mega_sat.model.lifted import PlanStep
from mega_sat.status import Status

HEURISTICS = ("lmcut", "hmax", "blind")
_INF = float("inf")
_MIX = 0x9E3779B97F4A7C15F39CC0605CEDC835  # odd: multiplying by it is a bijection mod 2^k


def state_key_mask(n_facts: int) -> int | None:
    """``None`` when states (bitsets over ``n_facts`` facts) hash well as they are, else the
    mask ``2^k - 1`` of the injective map ``s -> (s * _MIX) & mask`` whose values serve as
    dictionary keys.

    A Python int hashes to its value modulo ``2^61 - 1``, so bits ``i`` and ``i + 61`` count
    the same: with 61 or more facts, states that trade one such fact for the other collide.
    The two-fact abstraction of a family with 61 atoms (``T_p`` at ``p``, ``F_p`` at
    ``61 + p``) is the worst case: every state hashes alike and each lookup scans them all.
    Multiplying by an odd constant modulo ``2^k`` is injective on ``k``-bit states and spreads
    every bit over the high ones."""
    return None if n_facts <= 60 else (1 << (n_facts + 64)) - 1


def _key(s: int, mask: int | None) -> int:
    """The dictionary key of state ``s`` under :func:`state_key_mask`'s ``mask``."""
    return s if mask is None else (s * _MIX) & mask


_CHECK_EVERY = 32
"""Expansions between two reads of the clock: often enough to stop within milliseconds of the
deadline, rarely enough that the clock costs nothing."""


@dataclass(frozen=True)
class PlanResult:
    """The answer of one optimal planning call on one model.

    ``status`` is :attr:`Status.OPTIMAL` (``plan`` and ``cost`` set), :attr:`Status.UNSOLVABLE`
    (proven), :attr:`Status.TIMEOUT` (the deadline or the call's own time limit passed) or
    :attr:`Status.LIMIT` (a node budget or the SAT horizon cap ran out); the last two prove
    nothing.  ``exact`` is false when the answer is not a proof (a SAT optimum with zero-cost
    actions, or no answer); ``reason`` says why in words; ``expanded`` counts the states an
    explicit search expanded (0 for the other planners).
    """

    status: Status
    plan: tuple[PlanStep, ...] | None
    cost: int | None
    exact: bool
    planner: str
    time_s: float
    reason: str = ""
    expanded: int = 0


def _successor_groups(task: GroundTask) -> list[tuple[int, list[tuple]]]:
    """Actions grouped by one of their preconditions (the least shared one), so a state only
    tests actions whose key atom is true.  Group bit 0 means "always test"."""
    count: dict[int, int] = {}
    for a in task.actions:
        for p in a.pre:
            count[p] = count.get(p, 0) + 1
    groups: dict[int, list[tuple]] = {}
    for j, a in enumerate(task.actions):
        key = min(a.pre, key=lambda p: (count[p], p)) if a.pre else -1
        pre = sum(1 << p for p in a.pre)
        neg = sum(1 << p for p in a.negpre)
        add = sum(1 << p for p in a.add)
        dl = sum(1 << p for p in a.delete)
        groups.setdefault(key, []).append((j, pre, neg, ~dl, add, a.cost))
    return [(0 if k < 0 else 1 << k, acts) for k, acts in sorted(groups.items())]


def astar(
    task: GroundTask,
    *,
    heuristic: str = "lmcut",
    deadline: Deadline | None = None,
    node_limit: int | None = None,
    time_limit: float | None = None,
    after: tuple[int, Callable[[], None]] | None = None,
) -> PlanResult:
    """Optimal plan of ``task`` by A* with reopening; ``TIMEOUT`` once ``deadline`` has passed
    (or ``time_limit`` seconds, a limit of this call alone, still used by the SAT oracles'
    fallback search), ``LIMIT`` after ``node_limit`` expansions.  ``after = (n, call)``:
    ``call()`` once the search has expanded ``n`` states and goes on (not with zero-cost
    actions, whose uniform-cost search runs without pauses)."""
    deadline = within(deadline, time_limit)
    if heuristic not in HEURISTICS:
        raise ValueError(f"unknown heuristic {heuristic!r} (choose from {', '.join(HEURISTICS)})")
    t0 = time.perf_counter()
    goal = sum(1 << p for p in task.goal)
    init = sum(1 << p for p in task.init)
    min_cost = min((a.cost for a in task.actions), default=0)
    stop_at = (deadline or NO_DEADLINE).at
    if heuristic == "blind" and min_cost <= 0:
        # h is 0 everywhere: Dijkstra, in the same order as the heap below (by g, then first
        # generated), but with a FIFO list per g; OPT's lowered-cost search lives here
        status, plan, cost, expanded = _uniform_cost(task, init, goal, node_limit, stop_at)
    else:
        steps = astar_steps(task, init, goal, heuristic, node_limit)
        at, call = after if after is not None else (None, None)
        try:
            while True:
                expanded, _ = next(steps)
                if at is not None and expanded >= at:
                    at = None
                    call()
                if stop_at is not None and time.perf_counter() > stop_at:
                    status, plan, cost = Status.TIMEOUT, None, None
                    break
        except StopIteration as done:
            status, plan, cost, expanded, _ = done.value
    return PlanResult(
        status,
        plan,
        cost,
        status.decided,
        f"builtin-astar({heuristic})",
        time.perf_counter() - t0,
        "" if status.decided else str(status),
        expanded,
    )


def astar_steps(
    task: GroundTask,
    init: int,
    goal: int,
    heuristic: str = "lmcut",
    node_limit: int | None = None,
    every: int = _CHECK_EVERY,
    bound: float = _INF,
):
    """A* with reopening as a generator that can be paused and resumed: it yields
    ``(expanded, evaluations)`` so far every ``every`` expansions (with LM-cut the heuristic
    evaluations are nearly all of the work) and returns ``(status, plan, cost, expanded,
    evaluations)``.  ``bound``: states whose f = g + h exceeds it are pruned (h is
    admissible), and an exhausted search answers ``INFEASIBLE``: no plan costs at most
    ``bound``."""
    min_cost = min((a.cost for a in task.actions), default=0)
    if heuristic == "blind":

        def h_of(s: int) -> float:
            return 0 if s & goal == goal else min_cost
    else:
        relaxed = RelaxedTask(task)
        fn = relaxed.lmcut if heuristic == "lmcut" else relaxed.h_max

        def h_of(s: int) -> float:
            return fn(bits(s))

    expanded = evaluations = 0
    none = Status.UNSOLVABLE if bound == _INF else Status.INFEASIBLE
    h0 = h_of(init)
    if h0 == _INF or h0 > bound:
        return none, None, None, 0, 1
    groups = _successor_groups(task)
    actions = task.actions
    mask = state_key_mask(len(task.atoms))
    k0 = _key(init, mask)
    best_g: dict[int, int] = {k0: 0}
    parent: dict[int, tuple[int, int] | None] = {k0: None}
    h_cache: dict[int, float] = {k0: h0}
    counter = 0
    open_list: list[tuple] = [(h0, h0, counter, 0, init, k0)]
    while open_list:
        _, _, _, g, s, k = heapq.heappop(open_list)
        if g > best_g[k]:
            continue
        if s & goal == goal:
            return Status.OPTIMAL, _trace(parent, actions, s, mask), g, expanded, evaluations
        if node_limit is not None and expanded >= node_limit:
            return Status.LIMIT, None, None, expanded, evaluations
        if expanded % every == 0:
            yield expanded, evaluations
        expanded += 1
        for bit, acts in groups:
            if bit and not s & bit:
                continue
            for j, pre, neg, keep, add, c in acts:
                if s & pre != pre or s & neg:
                    continue
                s2 = (s & keep) | add
                k2 = s2 if mask is None else (s2 * _MIX) & mask
                g2 = g + c
                old = best_g.get(k2)
                if old is not None and g2 >= old:
                    continue
                h2 = h_cache.get(k2)
                if h2 is None:
                    evaluations += 1
                    h2 = h_cache[k2] = h_of(s2)
                if h2 == _INF or g2 + h2 > bound:
                    continue
                best_g[k2] = g2
                parent[k2] = (s, j)
                counter += 1
                heapq.heappush(open_list, (g2 + h2, h2, counter, g2, s2, k2))
    return none, None, None, expanded, evaluations


def bounded_search(
    task: GroundTask, bound: int, node_limit: int
) -> tuple[Status, tuple[PlanStep, ...] | None, int | None]:
    """A plan of ``task`` costing at most ``bound``, by A* with the blind heuristic (the least
    action cost) pruned at ``bound``, within ``node_limit`` expansions: ``(OPTIMAL, plan,
    cost)`` (the task's optimum, which is then within the bound), ``(INFEASIBLE, None, None)``
    when no plan costs at most ``bound``, or ``(LIMIT, None, None)``.  Blind, because the
    states below a bound near the optimum are few and LM-cut in pure Python costs more per
    state than it prunes there (bench/README.md)."""
    init = sum(1 << p for p in task.init)
    goal = sum(1 << p for p in task.goal)
    steps = astar_steps(task, init, goal, "blind", node_limit, bound=bound)
    try:
        while True:
            next(steps)
    except StopIteration as done:
        return done.value[:3]


def _trace(
    parent: dict[int, tuple[int, int] | None], actions: tuple, s: int, mask: int | None = None
) -> tuple[PlanStep, ...]:
    """The plan that reached state ``s``, read back along ``parent`` (state, action index;
    keyed by :func:`_key` under ``mask``, see :func:`state_key_mask`)."""
    steps = []
    while (link := parent[_key(s, mask)]) is not None:
        s, j = link
        steps.append(actions[j].step)
    return tuple(reversed(steps))


def _uniform_cost(
    task: GroundTask,
    init: int,
    goal: int,
    node_limit: int | None,
    stop_at: float | None,
) -> tuple[Status, tuple[PlanStep, ...] | None, int | None, int]:
    """Uniform-cost search with one FIFO list per path cost ``g`` (``(status, plan, cost,
    expanded)``; it stops once ``time.perf_counter()`` passes ``stop_at``).  It expands states
    in exactly the order of :func:`astar`'s heap with ``h = 0`` (lower ``g``, then first
    generated), without the heap, which pays off on tasks where most actions cost 0 and whole
    layers share one ``g``."""
    steps = uniform_cost_steps(task, init, goal, node_limit)
    try:
        while True:
            expanded = next(steps)
            if stop_at is not None and time.perf_counter() > stop_at:
                return Status.TIMEOUT, None, None, expanded
    except StopIteration as done:
        return done.value


VECTOR_AFTER = 2048
"""Expansions after which uniform-cost search moves to numpy layers: building the arrays
costs a few milliseconds, what a pure-Python search of a few hundred states costs."""


def uniform_cost_steps(task: GroundTask, init: int, goal: int, node_limit: int | None = None):
    """:func:`_uniform_cost` as a generator that can be paused and resumed: it yields the
    count of expanded states every few expansions and returns ``(status, plan, cost,
    expanded)``.  The portfolio planner runs it in time slices without starting over.

    Small searches run in pure Python; one that passes ``VECTOR_AFTER`` expansions starts
    again as :func:`mega_sat.search.vector_search.vector_uniform_cost_steps`, which expands the
    same states in the same order and yields the same counts, so the caller sees one search."""
    python = _python_uniform_cost_steps(task, init, goal, node_limit)
    try:
        while (seen := next(python)) < VECTOR_AFTER:
            yield seen
    except StopIteration as done:
        return done.value
    python.close()
    from mega_sat.search.vector_search import vector_uniform_cost_steps

    order = [act[0] for _, acts in _successor_groups(task) for act in acts]
    vector = vector_uniform_cost_steps(
        task, init, goal, node_limit, order=order, check_every=_CHECK_EVERY
    )
    try:
        while True:
            if (count := next(vector)) >= seen:  # the counts up to ``seen`` are yielded
                yield count
    except StopIteration as done:
        return done.value


def _python_uniform_cost_steps(
    task: GroundTask, init: int, goal: int, node_limit: int | None = None
):
    """:func:`uniform_cost_steps` one state at a time."""
    groups = _successor_groups(task)
    actions = task.actions
    mask = state_key_mask(len(task.atoms))
    best_g: dict[int, int] = {_key(init, mask): 0}
    parent: dict[int, tuple[int, int] | None] = {_key(init, mask): None}
    buckets: dict[int, list[int]] = {0: [init]}
    pending = [0]  # the g values with a list, as a heap
    expanded = 0
    while pending:
        g = heapq.heappop(pending)
        queue = buckets.pop(g)
        i = 0
        while i < len(queue):  # zero-cost successors are appended while we go
            s = queue[i]
            i += 1
            if best_g[s if mask is None else (s * _MIX) & mask] != g:
                continue
            if s & goal == goal:
                return Status.OPTIMAL, _trace(parent, actions, s, mask), g, expanded
            if node_limit is not None and expanded >= node_limit:
                return Status.LIMIT, None, None, expanded
            if expanded % _CHECK_EVERY == 0:
                yield expanded
            expanded += 1
            for bit, acts in groups:
                if bit and not s & bit:
                    continue
                for j, pre, neg, keep, add, c in acts:
                    if s & pre != pre or s & neg:
                        continue
                    s2 = (s & keep) | add
                    k2 = s2 if mask is None else (s2 * _MIX) & mask
                    g2 = g + c
                    old = best_g.get(k2)
                    if old is not None and g2 >= old:
                        continue
                    best_g[k2] = g2
                    parent[k2] = (s, j)
                    if g2 == g:
                        queue.append(s2)
                    elif g2 in buckets:
                        buckets[g2].append(s2)
                    else:
                        buckets[g2] = [s2]
                        heapq.heappush(pending, g2)
    return Status.UNSOLVABLE, None, None, expanded


def uniform_cost_work(expanded: int, vector_weight: float) -> float:
    """The work of ``expanded`` uniform-cost expansions counted in pure-Python ones: those
    past the first ``VECTOR_AFTER`` run vectorised and count ``vector_weight`` each."""
    return min(expanded, VECTOR_AFTER) + vector_weight * max(expanded - VECTOR_AFTER, 0)


def _evaluations(steps):
    """:func:`astar_steps` with its progress as the evaluation count alone (its work), and
    the same return value."""
    while True:
        try:
            _, evaluations = next(steps)
        except StopIteration as done:
            return done.value
        yield evaluations


def blind_and_lmcut_steps(
    task: GroundTask,
    init: int,
    goal: int,
    lmcut_weight: float,
    node_limit: int | None = None,
    vector_weight: float = 1.0,
):
    """Uniform-cost search and A* with LM-cut on the same task, taking turns by work, as a
    generator: it yields the work spent so far (uniform-cost expansions, ``vector_weight``
    each past the first ``VECTOR_AFTER``, where they run vectorised: :func:`uniform_cost_work`;
    plus ``lmcut_weight`` per LM-cut evaluation) and returns ``(status, plan, cost, work,
    method)`` from whichever ends first.  Both are exact, so either answer is a proof; blind
    search wins on small state spaces, LM-cut where the heuristic prunes most of the space (it
    can expand a few hundred states where blind search expands hundreds of thousands).  Turns
    follow the work counts only, so every run ends the same way.  ``node_limit`` caps each
    search's expansions (``LIMIT`` once both are capped)."""
    informed = astar_steps(task, init, goal, "lmcut", node_limit, every=1)
    work = {"uniform-cost search": 0.0, "A* with LM-cut": 0.0}
    running = {
        "uniform-cost search": uniform_cost_steps(task, init, goal, node_limit),
        "A* with LM-cut": _evaluations(informed),
    }

    def weighed(method: str, count: int) -> float:
        if method == "uniform-cost search":
            return uniform_cost_work(count, vector_weight)
        return lmcut_weight * count

    while running:
        method = min(running, key=lambda m: (work[m], m))
        try:
            work[method] = weighed(method, next(running[method]))
        except StopIteration as done:
            status, plan, cost = done.value[:3]
            if status.decided:
                return status, plan, cost, sum(work.values()), method
            del running[method]
            continue
        yield sum(work.values())
    return Status.LIMIT, None, None, sum(work.values()), "search"


def solve_optimal(
    task: GroundTask,
    *,
    deadline: Deadline | None = None,
    blind_nodes: int = 300_000,
    time_limit: float | None = None,
    hand_over: Callable[[Deadline], PlanResult | None] | None = None,
) -> PlanResult:
    """The built-in planner's portfolio: uniform-cost search first, A* with LM-cut after.

    Both are optimal, so the answer is exact either way.  On the small state spaces of model
    families blind search wins by a wide margin (LM-cut in pure Python costs milliseconds per
    state); when blind search passes ``blind_nodes`` expansions (``Options.blind_nodes``),
    LM-cut's pruning pays off.  ``hand_over``, when given, answers in LM-cut's place (an
    optimal planner outside this process, e.g. Fast Downward); its ``None`` leaves the call
    to LM-cut.  The search stops with ``TIMEOUT`` at ``deadline``, or after ``time_limit``
    seconds when that comes first (a limit of this call alone).
    """
    t0 = time.perf_counter()
    deadline = within(deadline, time_limit)
    r = astar(task, heuristic="blind", deadline=deadline, node_limit=blind_nodes)
    if r.status != Status.LIMIT:
        return r
    if hand_over is not None:
        other = hand_over(deadline)
        if other is not None:
            return other
    r2 = astar(task, heuristic="lmcut", deadline=deadline)
    return PlanResult(
        r2.status,
        r2.plan,
        r2.cost,
        r2.exact,
        "builtin(blind+lmcut)",
        time.perf_counter() - t0,
        r2.reason,
        r.expanded + r2.expanded,
    )


def within(deadline: Deadline | None, seconds: float | None) -> Deadline:
    """``deadline``, or the point ``seconds`` from now when that comes first (a step's own
    limit inside the run's)."""
    deadline = deadline if deadline is not None else NO_DEADLINE
    if seconds is None:
        return deadline
    at = time.perf_counter() + seconds
    if deadline.at is not None and deadline.at <= at:
        return deadline
    return Deadline(at, seconds)
