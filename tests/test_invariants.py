"""Invariants added to the SAT encoding (mega_sat/analysis/invariants.py) and greedy action elimination
(mega_sat/search/plan_reduction.py), against explicit-state ground truth on random families."""

from __future__ import annotations

import pytest
from helpers.fuzzing import oracle_settings
from helpers.sat_families import all_selections, families, plan_cost, selections
from hypothesis import given
from hypothesis import strategies as st

from mega_sat.analysis.invariants import family_invariants
from mega_sat.ground.family import GroundFamily, GroundTask
from mega_sat.search.plan_reduction import reduce_plan

SETTINGS = oracle_settings(150)


def _layered_states(task: GroundTask, depth: int) -> list[set[frozenset[int]]]:
    """``out[t]``: every state reachable in at most ``t`` steps (later steps may idle)."""
    layers = [{frozenset(task.init)}]
    for _ in range(depth):
        nxt = set(layers[-1])
        for s in layers[-1]:
            for a in task.actions:
                if a.pre <= s and a.negpre.isdisjoint(s):
                    nxt.add((s - a.delete) | a.add)
        layers.append(nxt)
    return layers


def _holds(lit: int, state: frozenset[int]) -> bool:
    return (abs(lit) - 1 in state) == (lit > 0)


def _check(inv, task: GroundTask, depth: int = 6) -> None:
    for t, states in enumerate(_layered_states(task, depth)):
        forced = list(inv.fixed_at(t))
        runnable = {
            a.index for s in states for a in task.actions if a.pre <= s and a.negpre.isdisjoint(s)
        }
        for j in runnable:
            assert inv.action_from[j] <= t, f"action {j} runs at step {t}"
        for s in states:
            for l1, l2 in inv.binary:
                assert _holds(l1, s) or _holds(l2, s), f"invariant ({l1}, {l2}) fails at {t}"
            for lit in forced:
                assert _holds(lit, s), f"layer literal {lit} fails at step {t}"


@SETTINGS
@given(fam=families())
def test_family_invariants_hold_in_every_reachable_state_of_every_member(fam: GroundFamily):
    inv = family_invariants(fam)
    for sel in all_selections(fam.n_updates):
        _check(inv, fam.specialize(sel))


@SETTINGS
@given(fam=families(), data=st.data())
def test_invariants_of_a_fixed_selection_hold_in_that_model(fam: GroundFamily, data):
    sel = data.draw(selections(fam.n_updates))
    _check(family_invariants(fam, sel, range(fam.n_updates)), fam.specialize(sel))


def test_invariants_find_the_mutexes_of_a_one_place_robot():
    from mega_sat.ground.family import GroundAction

    # at-a, at-b, at-c; move x->y deletes at-x, adds at-y
    atoms = (("at", "a"), ("at", "b"), ("at", "c"))
    acts = []
    for x in range(3):
        for y in range(3):
            if x != y:
                acts.append(
                    GroundAction(
                        "move", (str(x), str(y)), None, ((x, None),), (), ((y, None),),
                        ((x, None),), (((), 1),),
                    )
                )  # fmt: skip
    fam = GroundFamily(atoms, 0, tuple(acts), ((0, None),), ((2, None),))
    inv = family_invariants(fam)
    pairs = {frozenset(b) for b in inv.binary}
    for p in range(3):
        for q in range(p + 1, 3):
            assert frozenset((-(p + 1), -(q + 1))) in pairs  # never at two places
    assert inv.true_from == (0, 1, 1) and inv.false_from[0] == 1


def _random_walk(task: GroundTask, rnd, steps: int):
    state, plan = set(task.init), []
    for _ in range(steps):
        app = [a for a in task.actions if a.pre <= state and a.negpre.isdisjoint(state)]
        if not app:
            break
        a = rnd.choice(app)
        state = (state - a.delete) | a.add
        plan.append(a.step)
    return plan, frozenset(state)


@SETTINGS
@given(fam=families(), data=st.data(), seed=st.integers(0, 10_000), steps=st.integers(0, 12))
def test_reduce_plan_keeps_a_valid_plan_and_never_costs_more(fam, data, seed, steps):
    import random
    from dataclasses import replace

    sel = data.draw(selections(fam.n_updates))
    task = fam.specialize(sel)
    plan, end = _random_walk(task, random.Random(seed), steps)
    goal_task = replace(task, goal=end)  # the walk's end state is a reachable goal
    cost = plan_cost(goal_task, plan)
    assert cost is not None
    reduced, c = reduce_plan(goal_task, plan)
    assert plan_cost(goal_task, reduced) == c <= cost
    assert len(reduced) <= len(plan)


@SETTINGS
@given(fam=families())
def test_dropping_irrelevant_actions_keeps_every_members_optimum(fam: GroundFamily):
    from dataclasses import replace

    from helpers.sat_families import dijkstra

    from mega_sat.analysis.invariants import NEVER, steps_to_goal

    rel = {j for j, k in enumerate(steps_to_goal(fam)) if k < NEVER}
    for sel in all_selections(fam.n_updates):
        task = fam.specialize(sel)
        pruned = replace(task, actions=tuple(a for a in task.actions if a.index in rel))
        assert dijkstra(pruned) == dijkstra(task)


def _cheapest_within(task: GroundTask, h: int, allowed) -> int | None:
    """Cheapest plan of at most ``h`` steps whose goal is checked after step ``h`` (idle tail),
    using action ``a`` at step ``t`` only if ``allowed(a, t)``."""
    best = {frozenset(task.init): 0}
    for t in range(h):
        nxt = dict(best)  # idle from here on
        for s, c in best.items():
            for a in task.actions:
                if allowed(a, t) and a.pre <= s and a.negpre.isdisjoint(s):
                    s2 = (s - a.delete) | a.add
                    if c + a.cost < nxt.get(s2, 1 << 60):
                        nxt[s2] = c + a.cost
        best = nxt
    costs = [c for s, c in best.items() if task.goal <= s]
    return min(costs, default=None)


@SETTINGS
@given(fam=families(), h=st.integers(0, 5))
def test_backward_layers_keep_the_cheapest_plan_of_every_length(fam: GroundFamily, h: int):
    from mega_sat.analysis.invariants import steps_to_goal

    k = steps_to_goal(fam)
    for sel in all_selections(fam.n_updates):
        task = fam.specialize(sel)
        full = _cheapest_within(task, h, lambda a, t: True)
        pruned = _cheapest_within(task, h, lambda a, t: h - t >= k[a.index])
        assert pruned == full


@SETTINGS
@given(fam=families())
def test_guarded_mutexes_hold_in_every_member_where_their_guard_holds(fam: GroundFamily):
    from mega_sat.analysis.invariants import encoding_facts

    facts = encoding_facts(fam)
    for sel in all_selections(fam.n_updates):
        task = fam.specialize(sel)
        active = [(l1, l2) for g, l1, l2 in facts.guarded if ((abs(g) - 1) in sel) == (g > 0)]
        for states in _layered_states(task, 6):
            for s in states:
                for l1, l2 in active:
                    assert _holds(l1, s) or _holds(l2, s)


def _fresh_pair_fixpoints() -> None:
    """Forget the kept pair fixpoints, so that each side of a comparison computes its own."""
    from mega_sat.analysis import pair_reachability

    pair_reachability._kept = pair_reachability._Kept()


def _guarded_without_skipping(fam: GroundFamily) -> set:
    """Every update fixed both ways, with an h^2 computation each from the initial state (no
    shortcut, no seed)."""
    from mega_sat.analysis.invariants import family_invariants

    _fresh_pair_fixpoints()
    have = set(family_invariants(fam).binary)
    out = set()
    for i in range(fam.n_updates):
        for v in (False, True):
            inv = family_invariants(fam, frozenset([i]) if v else frozenset(), [i])
            guard = i + 1 if v else -(i + 1)
            out.update((guard, l1, l2) for l1, l2 in inv.binary if (l1, l2) not in have)
    _fresh_pair_fixpoints()
    return out


@SETTINGS
@given(fam=families())
def test_guarded_mutexes_skip_only_fixings_that_find_nothing(fam: GroundFamily):
    from mega_sat.analysis.invariants import encoding_facts

    want = _guarded_without_skipping(fam)
    assert set(encoding_facts(fam).guarded) == want


@pytest.mark.parametrize("name", ["rover-martian/p3", "usar-fetch/p3", "blocksworld/p3"])
def test_guarded_mutexes_skip_only_fixings_that_find_nothing_on_shipped_problems(name):
    from pathlib import Path

    from mega_sat.analysis.invariants import encoding_facts
    from mega_sat.ground.grounding import ground
    from mega_sat.pddl.loading import load_task, resolve_task_dir

    d = Path(__file__).resolve().parent.parent / "domains" / name
    fam = ground(load_task(**resolve_task_dir(d)))
    want = _guarded_without_skipping(fam)
    got = encoding_facts(fam).guarded
    assert len(set(got)) == len(got) and set(got) == want
    if name == "rover-martian/p3":
        assert len(got) == 33
