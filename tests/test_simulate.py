"""The lifted plan simulator and its ground fast path."""

from __future__ import annotations

from dataclasses import replace

from mega_sat.ground.grounding import ground_model
from mega_sat.ground.simulate import plan_cost, simulate, simulate_ground
from mega_sat.model.lifted import Model, Schema

MOVE = Schema(
    "move",
    ("?x", "?y"),
    pre=frozenset({("at", "?x"), ("clear_path", "?x", "?y")}),
    negpre=frozenset({("blocked", "?y")}),
    add=frozenset({("at", "?y")}),
    delete=frozenset({("at", "?x")}),
    cost=("dist", "?x", "?y"),
)
# deletes and re-adds (on ?x): PDDL applies deletes first, so the atom stays true
TOUCH = Schema(
    "touch",
    ("?x",),
    pre=frozenset({("at", "?x")}),
    add=frozenset({("at", "?x"), ("touched", "?x")}),
    delete=frozenset({("at", "?x")}),
    cost=1,
)
OBJS = ("p1", "p5", "p8")
MODEL = Model(
    domain_name="d",
    problem_name="p",
    predicates={"at": 1, "clear_path": 2, "blocked": 1, "touched": 1},
    schemas={"move": MOVE, "touch": TOUCH},
    objects=frozenset(OBJS),
    init=frozenset(
        {
            ("at", "p1"),
            ("clear_path", "p1", "p5"),
            ("clear_path", "p5", "p8"),
            ("clear_path", "p1", "p8"),
            ("blocked", "p8"),
        }
    ),
    goal=frozenset({("at", "p5"), ("touched", "p5")}),
    functions={("dist", x, y): 2 + (x == "p1") for x in OBJS for y in OBJS},
    function_arities={"dist": 2},
    uses_costs=True,
)


def both(plan):
    lifted = simulate(MODEL, plan)
    grounded = simulate_ground(ground_model(MODEL), plan)
    assert (lifted.valid, lifted.cost, lifted.failed_step, lifted.final_state, lifted.steps) == (
        grounded.valid,
        grounded.cost,
        grounded.failed_step,
        grounded.final_state,
        grounded.steps,
    )
    return lifted, grounded


def test_valid_plan_cost_and_delete_then_add():
    plan = [("move", "p1", "p5"), ("touch", "p5")]
    sim, gsim = both(plan)
    assert sim.valid and sim.cost == 4 and sim.failed_step is None and sim.reason is None
    assert ("at", "p5") in sim.final_state and ("touched", "p5") in sim.final_state
    assert sim.steps == 2 and gsim.valid
    assert plan_cost(MODEL, plan) == 4
    # upper case is normalised
    assert simulate(MODEL, [("MOVE", "P1", "P5"), ("touch", "p5")]).cost == 4


def test_failure_reasons():
    cases = {
        ("move", "p5", "p8"): "step 1 (move p5 p8): precondition (at p5) does not hold",
        ("move", "p1", "p8"): "step 1 (move p1 p8): negative precondition (blocked p8) holds",
        ("fly", "p1"): "step 1 (fly p1): unknown action 'fly'",
        ("move", "p1"): "step 1 (move p1): wrong number of arguments (expected 2, got 1)",
        ("move", "p1", "p9"): "step 1 (move p1 p9): unknown object 'p9'",
    }
    for step, reason in cases.items():
        sim = simulate(MODEL, [step])
        assert (sim.valid, sim.cost, sim.failed_step, sim.steps) == (False, None, 1, 0)
        assert sim.reason == reason
        assert sim.final_state == MODEL.init
    sim, gsim = both([("move", "p1", "p5"), ("move", "p1", "p8")])
    assert sim.reason == "step 2 (move p1 p8): precondition (at p1) does not hold"
    assert gsim.reason == sim.reason
    sim, gsim = both([("move", "p1", "p5"), ("move", "p5", "p8")])
    assert sim.reason == "step 2 (move p5 p8): negative precondition (blocked p8) holds"
    assert gsim.reason == sim.reason
    assert sim.steps == 1 and ("at", "p5") in sim.final_state


def test_goal_not_reached():
    sim, gsim = both([("move", "p1", "p5")])
    assert not sim.valid and sim.failed_step is None and sim.cost is None
    assert sim.reason == "goal (touched p5) not reached" == gsim.reason
    assert plan_cost(MODEL, [("move", "p1", "p5")]) is None
    sim, _ = both([])
    assert sim.reason == "goal (at p5) not reached" and sim.steps == 0


def test_preconditions_are_checked_in_the_state_before_the_step():
    # touch deletes and adds (at ?x): still applicable twice in a row
    sim, _ = both([("move", "p1", "p5"), ("touch", "p5"), ("touch", "p5")])
    assert sim.valid and sim.cost == 5


def test_missing_cost_value_is_a_failure_not_a_crash():
    model = replace(MODEL, functions={})
    sim = simulate(model, [("move", "p1", "p5")])
    assert not sim.valid and "cost function value" in (sim.reason or "")
