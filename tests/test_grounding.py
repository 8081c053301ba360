"""Grounding of two-model tasks: guards, costs, pruning, completeness and speed."""

from __future__ import annotations

import time
from dataclasses import replace
from itertools import product

from helpers.fuzzing import oracle_settings
from helpers.randomtasks import applicable_steps, plans, selections, two_model_tasks
from hypothesis import given
from hypothesis import strategies as st

from mega_sat.ground.family import holds
from mega_sat.ground.grounding import ground, ground_model
from mega_sat.ground.simulate import simulate, simulate_ground
from mega_sat.model.features import COST, FVALUE, GOAL, INIT, PRE, SCHEMA
from mega_sat.model.lifted import Model, Schema
from mega_sat.model.task import TwoModelTask


def mk(schemas, init, goal, objects=("a", "b", "c"), functions=None, preds=None) -> Model:
    preds = preds or {"at": 1, "conn": 2, "loc": 1, "visited": 1, "free": 0}
    return Model(
        domain_name="d",
        problem_name="p",
        predicates=preds,
        schemas={s.name: s for s in schemas},
        objects=frozenset(objects),
        init=frozenset(init),
        goal=frozenset(goal),
        functions=functions or {},
        function_arities={"dist": 2} if functions else {},
        uses_costs=True,
    )


MOVE = Schema(
    "move",
    ("?x", "?y"),
    pre=frozenset({("at", "?x"), ("conn", "?x", "?y")}),
    add=frozenset({("at", "?y"), ("visited", "?y")}),
    delete=frozenset({("at", "?x")}),
    cost=2,
)
INIT_ATOMS = {("at", "a"), ("conn", "a", "b"), ("conn", "b", "c")}


def idx(task: TwoModelTask, kind: str, action: str = "") -> int:
    (i,) = [
        i for i, u in enumerate(task.delta) if u.feature.kind == kind and u.feature.action == action
    ]
    return i


def test_guards_of_each_component_kind():
    jump = Schema("jump", ("?x",), pre=frozenset({("free",)}), add=frozenset({("at", "?x")}))
    robot = mk([MOVE, jump], INIT_ATOMS, {("at", "c")})
    human_move = Schema(
        "move",
        ("?from", "?to"),
        pre=frozenset({("at", "?from")}),  # lacks (conn ?x ?y)
        add=frozenset({("at", "?to")}),  # lacks (visited ?y)
        delete=frozenset({("at", "?from")}),
        cost=1,  # robot: 2
    )
    human = mk([human_move], INIT_ATOMS | {("free",)}, {("at", "c"), ("visited", "b")})
    task = TwoModelTask.from_models(robot, human)
    fam = ground(task)
    ids = fam.atom_index
    i_conn = task.update_index["add-move-has-precondition-conn ?x ?y"]
    i_vis = task.update_index["add-move-has-add-effect-visited ?y"]
    i_cost = idx(task, COST, "move")
    i_jump = idx(task, SCHEMA, "jump")
    i_free = idx(task, INIT)
    i_goal = idx(task, GOAL)

    # the human has no (conn a c), yet (move a c) must exist: some E drops the precondition
    mv = fam.actions[fam.action_index[("move", "a", "c")]]
    assert mv.exists is None
    assert set(mv.pre) == {(ids[("at", "a")], None), (ids[("conn", "a", "c")], (i_conn, True))}
    assert set(mv.add) == {(ids[("at", "c")], None), (ids[("visited", "c")], (i_vis, True))}
    assert mv.delete == ((ids[("at", "a")], None),)
    assert sorted(mv.cost) == [(((i_cost, False),), 1), (((i_cost, True),), 2)]

    jp = fam.actions[fam.action_index[("jump", "b")]]
    assert jp.exists == (i_jump, True)
    assert set(jp.pre) == {(ids[("free",)], (idx(task, PRE, "jump"), True))}
    assert set(fam.init) >= {(ids[("free",)], (i_free, False)), (ids[("at", "a")], None)}
    assert (ids[("visited", "b")], (i_goal, False)) in fam.goal

    # the specialisations are exactly the two models
    human_task = fam.specialize(frozenset())
    assert ("jump", "a") not in human_task.by_step
    assert human_task.by_step[("move", "a", "c")].cost == 1
    assert human_task.by_step[("move", "a", "c")].pre == {ids[("at", "a")]}
    robot_task = fam.specialize(fam.robot_selection)
    assert robot_task.by_step[("move", "a", "b")].cost == 2
    assert ids[("free",)] not in robot_task.init
    assert robot_task.goal == {ids[("at", "c")]}


def test_shared_static_preconditions_prune_and_unshared_do_not():
    typed = Schema(
        "visit",
        ("?x",),
        pre=frozenset({("loc", "?x")}),
        add=frozenset({("visited", "?x")}),
    )
    robot = mk([typed], {("loc", "a")}, {("visited", "a")})
    assert sorted(a.args for a in ground(TwoModelTask.from_models(robot, robot)).actions) == [
        ("a",)
    ]
    # the human lacks the type precondition: every object becomes a candidate
    human = mk(
        [Schema("visit", ("?x",), add=frozenset({("visited", "?x")}))],
        {("loc", "a")},
        {("visited", "a")},
    )
    fam = ground(TwoModelTask.from_models(robot, human))
    assert sorted(a.args for a in fam.actions) == [("a",), ("b",), ("c",)]


def test_schema_only_in_one_model_is_grounded_without_its_preconditions():
    # any E may add the schema but not its precondition, so it is unconstrained in the family
    robot = mk([MOVE], INIT_ATOMS, {("at", "c")})
    human = mk([], INIT_ATOMS, {("at", "c")})
    task = TwoModelTask.from_models(robot, human)
    fam = ground(task)
    assert len(fam.actions) == 9
    assert all(a.exists == (idx(task, SCHEMA, "move"), True) for a in fam.actions)
    assert ground_model(human).actions == ()


def test_repeated_atom_from_two_lifted_atoms_keeps_both_guards():
    robot = mk(
        [Schema("s", ("?x", "?y"), pre=frozenset({("at", "?x")}), add=frozenset({("free",)}))],
        {("at", "a")},
        {("free",)},
    )
    human = mk(
        [Schema("s", ("?x", "?y"), pre=frozenset({("at", "?y")}), add=frozenset({("free",)}))],
        {("at", "a")},
        {("free",)},
    )
    task = TwoModelTask.from_models(robot, human)
    fam = ground(task)
    ix = task.update_index["add-s-has-precondition-at ?x"]
    iy = task.update_index["remove-s-has-precondition-at ?y"]
    at_a = fam.atom_index[("at", "a")]
    s_aa = fam.actions[fam.action_index[("s", "a", "a")]]
    assert sorted(s_aa.pre, key=str) == sorted([(at_a, (ix, True)), (at_a, (iy, False))], key=str)
    for sel in (frozenset(), frozenset({ix}), frozenset({iy}), frozenset({ix, iy})):
        present = ix in sel or iy not in sel
        assert fam.specialize(sel).by_step[("s", "a", "a")].pre == ({at_a} if present else set())


def test_cost_cases_combine_cost_and_function_value_updates():
    dist = {("dist", x, y): 1 for x, y in product("abc", repeat=2)}
    robot_move = Schema(
        "move", MOVE.params, MOVE.pre, add=MOVE.add, delete=MOVE.delete, cost=("dist", "?x", "?y")
    )
    robot = mk([robot_move], INIT_ATOMS, {("at", "c")}, functions={**dist, ("dist", "a", "b"): 5})
    human_move = Schema("move", MOVE.params, MOVE.pre, add=MOVE.add, delete=MOVE.delete, cost=3)
    human = mk([human_move], INIT_ATOMS, {("at", "c")}, functions=dist)
    task = TwoModelTask.from_models(robot, human)
    fam = ground(task)
    i_cost, i_fv = idx(task, COST, "move"), idx(task, FVALUE)
    cases = fam.actions[fam.action_index[("move", "a", "b")]].cost
    for sel in (frozenset(), {i_cost}, {i_fv}, {i_cost, i_fv}):
        applying = [v for g, v in cases if all(holds(x, frozenset(sel)) for x in g)]
        expected = task.updated_model(sel).schema_cost(
            task.updated_model(sel).schemas["move"], ("a", "b")
        )
        assert applying == [expected]  # exactly one case applies, with the model's cost
    assert fam.actions[fam.action_index[("move", "b", "c")]].cost == (
        (((i_cost, True),), 1),
        (((i_cost, False),), 3),
    )
    # equal values in every case collapse to one unguarded case
    same = mk([human_move], INIT_ATOMS, {("at", "c")}, functions=dist)
    assert ground(TwoModelTask.from_models(same, same)).actions[0].cost == (((), 3),)


def test_ground_model_matches_single_model():
    robot = mk([MOVE], INIT_ATOMS, {("at", "c")})
    gt = ground_model(robot)
    assert sorted(a.step for a in gt.actions) == [("move", "a", "b"), ("move", "b", "c")]
    assert simulate_ground(gt, [("move", "a", "b"), ("move", "b", "c")]).cost == 4


@oracle_settings(120, suppress_health_check=())
@given(data=st.data())
def test_specialisation_agrees_with_lifted_simulation(data):
    task = data.draw(two_model_tasks())
    fam = ground(task)
    for _ in range(3):
        walk = task.updated_model(data.draw(selections(task)))
        plan = data.draw(plans(walk, max_len=6))
        sel = data.draw(selections(task))
        lifted = simulate(task.updated_model(sel), plan)
        grounded = simulate_ground(fam.specialize(sel), plan)
        assert (lifted.valid, lifted.cost, lifted.failed_step, lifted.steps) == (
            grounded.valid,
            grounded.cost,
            grounded.failed_step,
            grounded.steps,
        )
        assert lifted.final_state == grounded.final_state
        if "precondition" in (grounded.reason or "") or "goal" in (grounded.reason or ""):
            assert lifted.reason == grounded.reason


@oracle_settings(60, suppress_health_check=())
@given(data=st.data())
def test_every_reachable_applicable_step_is_grounded_identically(data):
    """Completeness: explore each sampled member's reachable states by brute force; every
    applicable lifted step must exist in the specialisation with the same effects and cost."""
    task = data.draw(two_model_tasks())
    fam = ground(task)
    for sel in (frozenset(), task.all_updates, data.draw(selections(task))):
        model = task.updated_model(sel)
        gt = fam.specialize(sel)
        atoms = gt.atoms
        assert {atoms[i] for i in gt.init} == model.init
        assert {atoms[i] for i in gt.goal} == model.goal
        seen = {model.init}
        frontier = [model.init]
        dropped = set()  # lifted negative preconditions / deletes the grounding left out
        while frontier:
            state = frontier.pop()
            for step in applicable_steps(model, state):
                ga = gt.by_step[step]
                s = model.schemas[step[0]]
                b = dict(zip(s.params, step[1:], strict=True))

                def g(atoms_, b=b):
                    return {(a[0], *(b.get(x, x) for x in a[1:])) for a in atoms_}

                assert {atoms[i] for i in ga.pre} == g(s.pre)
                assert {atoms[i] for i in ga.add} == g(s.add)
                assert {atoms[i] for i in ga.negpre} <= g(s.negpre)
                assert {atoms[i] for i in ga.delete} <= g(s.delete)
                dropped |= g(s.negpre) - {atoms[i] for i in ga.negpre}
                dropped |= g(s.delete) - {atoms[i] for i in ga.delete}
                assert ga.cost == model.schema_cost(s, step[1:])
                nxt = frozenset((state - g(s.delete)) | g(s.add))
                if nxt not in seen:
                    seen.add(nxt)
                    frontier.append(nxt)
        # only atoms that are never true may be left out
        assert not dropped & set().union(*seen)


def barman_like(n_shots: int = 20, n_ingredients: int = 5, n_cocktails: int = 6) -> Model:
    """A barman-style model with ~40 objects and 6-parameter schemas (types as predicates)."""
    shots = [f"shot{i}" for i in range(n_shots)]
    ingr = [f"ingredient{i}" for i in range(n_ingredients)]
    cocktails = [f"cocktail{i}" for i in range(n_cocktails)]
    dispensers = [f"dispenser{i}" for i in range(n_ingredients)]
    levels = ["l0", "l1", "l2"]
    objects = [*shots, *ingr, *cocktails, *dispensers, *levels, "left", "right", "shaker1"]
    S = lambda name, params, pre, add=(), dele=(): Schema(  # noqa: E731
        name, params, frozenset(pre), frozenset(), frozenset(add), frozenset(dele), 1
    )
    schemas = [
        S(
            "grasp",
            ("?h", "?c"),
            [("hand", "?h"), ("container", "?c"), ("ontable", "?c"), ("handempty", "?h")],
            [("holding", "?h", "?c")],
            [("ontable", "?c"), ("handempty", "?h")],
        ),
        S(
            "leave",
            ("?h", "?c"),
            [("hand", "?h"), ("container", "?c"), ("holding", "?h", "?c")],
            [("ontable", "?c"), ("handempty", "?h")],
            [("holding", "?h", "?c")],
        ),
        S(
            "fill-shot",
            ("?s", "?i", "?h1", "?h2", "?d"),
            [
                ("shot", "?s"),
                ("ingredient", "?i"),
                ("hand", "?h1"),
                ("hand", "?h2"),
                ("dispenser", "?d"),
                ("holding", "?h1", "?s"),
                ("handempty", "?h2"),
                ("dispenses", "?d", "?i"),
                ("empty", "?s"),
                ("clean", "?s"),
            ],
            [("contains", "?s", "?i"), ("used", "?s", "?i")],
            [("empty", "?s"), ("clean", "?s")],
        ),
        S(
            "pour-shot-to-clean-shaker",
            ("?s", "?i", "?d", "?h1", "?l", "?l1"),
            [
                ("shot", "?s"),
                ("ingredient", "?i"),
                ("shaker", "?d"),
                ("hand", "?h1"),
                ("level", "?l"),
                ("level", "?l1"),
                ("holding", "?h1", "?s"),
                ("contains", "?s", "?i"),
                ("empty", "?d"),
                ("clean", "?d"),
                ("shaker-level", "?d", "?l"),
                ("next", "?l", "?l1"),
            ],
            [("contains", "?d", "?i"), ("empty", "?s"), ("shaker-level", "?d", "?l1")],
            [
                ("contains", "?s", "?i"),
                ("empty", "?d"),
                ("clean", "?d"),
                ("shaker-level", "?d", "?l"),
            ],
        ),
        S(
            "shake",
            ("?b", "?d1", "?d2", "?s", "?h1", "?h2"),
            [
                ("cocktail", "?b"),
                ("ingredient", "?d1"),
                ("ingredient", "?d2"),
                ("shaker", "?s"),
                ("hand", "?h1"),
                ("hand", "?h2"),
                ("holding", "?h1", "?s"),
                ("handempty", "?h2"),
                ("contains", "?s", "?d1"),
                ("contains", "?s", "?d2"),
                ("cocktail-part1", "?b", "?d1"),
                ("cocktail-part2", "?b", "?d2"),
            ],
            [("contains", "?s", "?b")],
            [("contains", "?s", "?d1"), ("contains", "?s", "?d2")],
        ),
        S(
            "pour-shaker-to-shot",
            ("?b", "?d", "?h", "?s", "?l", "?l1"),
            [
                ("beverage", "?b"),
                ("shot", "?d"),
                ("hand", "?h"),
                ("shaker", "?s"),
                ("level", "?l"),
                ("level", "?l1"),
                ("holding", "?h", "?s"),
                ("empty", "?d"),
                ("clean", "?d"),
                ("contains", "?s", "?b"),
                ("shaker-level", "?s", "?l"),
                ("next", "?l1", "?l"),
            ],
            [("contains", "?d", "?b"), ("shaker-level", "?s", "?l1")],
            [("clean", "?d"), ("empty", "?d"), ("shaker-level", "?s", "?l")],
        ),
    ]
    init = {
        ("hand", "left"),
        ("hand", "right"),
        ("handempty", "left"),
        ("handempty", "right"),
        ("shaker", "shaker1"),
        ("container", "shaker1"),
        ("ontable", "shaker1"),
        ("empty", "shaker1"),
        ("clean", "shaker1"),
        ("shaker-level", "shaker1", "l0"),
        ("next", "l0", "l1"),
        ("next", "l1", "l2"),
    }
    init |= {("level", x) for x in levels}
    for s in shots:
        init |= {("shot", s), ("container", s), ("ontable", s), ("empty", s), ("clean", s)}
    for i, d in zip(ingr, dispensers, strict=True):
        init |= {("ingredient", i), ("beverage", i), ("dispenser", d), ("dispenses", d, i)}
    for k, c in enumerate(cocktails):
        init |= {
            ("cocktail", c),
            ("beverage", c),
            ("cocktail-part1", c, ingr[k % n_ingredients]),
            ("cocktail-part2", c, ingr[(k + 1) % n_ingredients]),
        }
    preds = {a[0]: len(a) - 1 for s in schemas for a in s.pre | s.add} | {
        a[0]: len(a) - 1 for a in init
    }
    return mk(schemas, init, {("contains", "shot0", "cocktail0")}, objects=objects, preds=preds)


def test_barman_like_grounding_is_fast():
    robot = barman_like()
    assert len(robot.objects) >= 40
    s = robot.schemas["pour-shot-to-clean-shaker"]
    weaker = replace(s, pre=s.pre - {("clean", "?d")}, cost=2)
    human = replace(robot, schemas={**robot.schemas, s.name: weaker})
    task = TwoModelTask.from_models(robot, human)
    t0 = time.perf_counter()
    fam = ground(task)
    elapsed = time.perf_counter() - t0
    assert elapsed < 2.0, fam.describe()
    # typed preconditions prune: far fewer than the 40^6 cartesian product
    assert 1000 < len(fam.actions) < 50_000
    shake = [a for a in fam.actions if a.name == "shake"]
    assert shake and all(a.args[0].startswith("cocktail") for a in shake)
    gt = fam.specialize(fam.robot_selection)
    assert simulate_ground(gt, [("grasp", "left", "shot0")]).steps == 1
