"""Random ground families and brute-force oracles for the SAT encoding tests.

The families are tiny (a handful of atoms, actions and updates) so explicit-state search over
single states (OPT) and paired robot/human states (JOINT) is an independent ground truth.
"""

from __future__ import annotations

import heapq
import itertools
from collections.abc import Sequence

from hypothesis import strategies as st

from mega_sat.ground.family import CostCase, Entry, GroundAction, GroundFamily, GroundTask, Guard


@st.composite
def guards(draw, n_updates: int, p_none: float = 0.5) -> Guard:
    if n_updates == 0 or draw(st.floats(0, 1)) < p_none:
        return None
    return (draw(st.integers(0, n_updates - 1)), draw(st.booleans()))


@st.composite
def entries(draw, n_atoms: int, n_updates: int, max_size: int) -> tuple[Entry, ...]:
    k = draw(st.integers(0, max_size))
    return tuple((draw(st.integers(0, n_atoms - 1)), draw(guards(n_updates))) for _ in range(k))


@st.composite
def cost_cases(draw, n_updates: int, min_cost: int) -> tuple[CostCase, ...]:
    values = st.integers(min_cost, 3)
    if n_updates == 0 or draw(st.booleans()):
        return (((), draw(values)),)
    i = draw(st.integers(0, n_updates - 1))
    return (((i, True),), draw(values)), (((i, False),), draw(values))


@st.composite
def families(
    draw, *, max_atoms: int = 4, max_actions: int = 6, max_updates: int = 5, min_cost: int = 1
) -> GroundFamily:
    """A random family: random guards over 0-5 updates, costs ``min_cost``-3, often no plan."""
    n_atoms = draw(st.integers(1, max_atoms))
    n_updates = draw(st.integers(0, max_updates))
    n_actions = draw(st.integers(1, max_actions))
    acts = []
    for j in range(n_actions):
        acts.append(
            GroundAction(
                name=f"a{j}",
                args=(f"o{j % 2}",),
                exists=draw(guards(n_updates, 0.7)),
                pre=draw(entries(n_atoms, n_updates, 2)),
                negpre=draw(entries(n_atoms, n_updates, 1)),
                add=draw(entries(n_atoms, n_updates, 2)),
                delete=draw(entries(n_atoms, n_updates, 2)),
                cost=draw(cost_cases(n_updates, min_cost)),
            )
        )
    return GroundFamily(
        atoms=tuple((f"p{i}",) for i in range(n_atoms)),
        n_updates=n_updates,
        actions=tuple(acts),
        init=draw(entries(n_atoms, n_updates, 3)),
        goal=draw(entries(n_atoms, n_updates, 3)),
    )


def selections(n_updates: int):
    return (
        st.frozensets(st.integers(0, n_updates - 1), max_size=n_updates)
        if n_updates
        else st.just(frozenset())
    )


def all_selections(n_updates: int):
    for r in range(n_updates + 1):
        for c in itertools.combinations(range(n_updates), r):
            yield frozenset(c)


def _succ(task: GroundTask, s: frozenset[int]):
    for a in task.actions:
        if a.pre <= s and not (a.negpre & s):
            yield a, (s - a.delete) | a.add


def dijkstra(task: GroundTask) -> int | None:
    """Optimal plan cost of a ground task by uniform-cost search (None: no plan)."""
    start = frozenset(task.init)
    dist = {start: 0}
    heap = [(0, 0, start)]
    tie = itertools.count()
    while heap:
        d, _, s = heapq.heappop(heap)
        if d > dist[s]:
            continue
        if task.goal <= s:
            return d
        for a, s2 in _succ(task, s):
            if d + a.cost < dist.get(s2, 1 << 60):
                dist[s2] = d + a.cost
                heapq.heappush(heap, (d + a.cost, next(tie), s2))
    return None


def joint_brute(
    family: GroundFamily, selection: frozenset[int], robot_bound: int | None, human_bound: int
) -> int | None:
    """Minimum robot cost of a plan valid in the robot model (cost <= robot_bound) and in
    ``human + selection`` (cost <= human_bound), by search over paired states (None: none).

    Requires positive costs (the human cost then bounds the plan length).
    """
    rt = family.specialize(family.robot_selection)
    ht = family.specialize(selection)
    r_by = {a.index: a for a in rt.actions}
    h_by = {a.index: a for a in ht.actions}
    common = sorted(set(r_by) & set(h_by))
    start = (frozenset(rt.init), frozenset(ht.init), 0)
    best = {start: 0}
    heap = [(0, 0, start)]
    tie = itertools.count()
    while heap:
        rc, _, node = heapq.heappop(heap)
        if rc > best[node]:
            continue
        rs, hs, hc = node
        if rt.goal <= rs and ht.goal <= hs:
            return rc
        for j in common:
            ra, ha = r_by[j], h_by[j]
            if not (ra.pre <= rs and not ra.negpre & rs and ha.pre <= hs and not ha.negpre & hs):
                continue
            rc2, hc2 = rc + ra.cost, hc + ha.cost
            if hc2 > human_bound or (robot_bound is not None and rc2 > robot_bound):
                continue
            n2 = ((rs - ra.delete) | ra.add, (hs - ha.delete) | ha.add, hc2)
            if rc2 < best.get(n2, 1 << 60):
                best[n2] = rc2
                heapq.heappush(heap, (rc2, next(tie), n2))
    return None


def random_run(fam: GroundFamily, sel: frozenset[int], data, max_steps: int = 8) -> tuple:
    """A random plan that runs in ``human + sel`` (stops where no action applies), drawn from
    hypothesis ``data``, and the state it ends in."""
    task = fam.specialize(sel)
    state = frozenset(task.init)
    plan = []
    for _ in range(data.draw(st.integers(0, max_steps))):
        ok = [a for a in task.actions if a.pre <= state and not (a.negpre & state)]
        if not ok:
            break
        a = data.draw(st.sampled_from(ok))
        plan.append(a.step)
        state = (state - a.delete) | a.add
    return tuple(plan), state


def agreeing(core, n_updates: int) -> list[frozenset[int]]:
    """Every selection that agrees with the guard literals ``core``."""
    fixed = dict(core)
    free = [i for i in range(n_updates) if i not in fixed]
    base = {i for i, v in fixed.items() if v}
    out = []
    for r in range(len(free) + 1):
        for c in itertools.combinations(free, r):
            out.append(frozenset(base | set(c)))
    return out


def plan_cost(task: GroundTask, plan: Sequence[tuple[str, ...]]) -> int | None:
    from mega_sat.ground.simulate import simulate_ground

    sim = simulate_ground(task, plan)
    return sim.cost if sim.valid else None


def assert_optimum(task: GroundTask, status, cost, plan) -> None:
    """An optimal planner's answer on ``task`` agrees with :func:`dijkstra`: unsolvable when
    it finds no plan, else optimal with its cost and a valid plan of that cost."""
    c = dijkstra(task)
    if c is None:
        assert status == "unsolvable"
    else:
        assert status == "optimal" and cost == c and plan_cost(task, plan) == c


@st.composite
def symmetric_families(draw, **kw) -> GroundFamily:
    """A random family doubled over two interchangeable objects ``oa`` and ``ob``: each atom is
    either shared or one copy per object, each action one copy per object, initial state and
    goal symmetric.  Swapping them maps the family onto itself."""
    base = draw(families(**kw))
    per_obj = [draw(st.booleans()) for _ in base.atoms]
    atoms: list[tuple[str, ...]] = []
    index: dict[tuple[int, str], int] = {}
    for i, atom in enumerate(base.atoms):
        for x in ("oa", "ob") if per_obj[i] else ("",):
            index[(i, x)] = len(atoms)
            atoms.append((atom[0], x) if x else atom)

    def lift(entries, x: str):
        return tuple((index[(p, x if per_obj[p] else "")], g) for p, g in entries)

    def both(entries):
        return tuple(dict.fromkeys(lift(entries, "oa") + lift(entries, "ob")))

    acts = []
    for a in base.actions:
        for x in ("oa", "ob"):
            acts.append(
                GroundAction(
                    a.name, (x,), a.exists, lift(a.pre, x), lift(a.negpre, x), lift(a.add, x),
                    lift(a.delete, x), a.cost,
                )
            )  # fmt: skip
    return GroundFamily(tuple(atoms), base.n_updates, tuple(acts), both(base.init), both(base.goal))


def check_bounded_answer(solver, enc, task: GroundTask, lits, h: int, best, bound) -> None:
    """The encoding's answer to "a plan of at most ``h`` steps with cost <= ``bound``" under
    ``lits`` agrees with ``best`` (the true cheapest such cost, None if none), and a decoded
    plan is valid in ``task`` and within the bound."""
    expect = best is not None and (bound is None or best <= bound)
    assert solver.solve(assumptions=lits) == expect
    if expect:
        plan = enc.decode_plan(solver.get_model(), h)
        cost = plan_cost(task, plan)
        assert cost is not None and len(plan) <= h
        assert bound is None or cost <= bound
