"""A schema's signature travels with it: typed schemas only one model has, and the grounding
that prunes them by their types (docs/models.md, "Schemas only one model has")."""

from __future__ import annotations

from pathlib import Path

import pytest
from helpers.fuzzing import oracle_settings
from helpers.randomtasks import two_model_tasks
from hypothesis import given
from hypothesis import strategies as st

from mega_sat.ground.grounding import ground
from mega_sat.model.features import PRE, SCHEMA
from mega_sat.pddl.loading import load_task, load_task_from_strings, resolve_task_dir

ROOT = Path(__file__).resolve().parent.parent

HEAD = """(define (domain carry)
  (:requirements :strips :typing)
  (:types box room robot)
  (:predicates (at ?r - robot ?x - room) (in ?b - box ?x - room) (holding ?r - robot ?b - box)
               (door ?x ?y - room))
  (:action move :parameters (?r - robot ?x ?y - %s)
    :precondition (and (at ?r ?x) (door ?x ?y)) :effect (and (at ?r ?y) (not (at ?r ?x))))
"""
PICK = """  (:action pick :parameters (?r - robot ?b - box ?x - room)
    :precondition (and (at ?r ?x) (in ?b ?x))
    :effect (and (holding ?r ?b) (not (in ?b ?x))))
"""
DROP = """  (:action drop :parameters (?r - robot ?b - box ?x - room)
    :precondition (and (at ?r ?x) (holding ?r ?b))
    :effect (and (in ?b ?x) (not (holding ?r ?b))))
"""
PROBLEM = """(define (problem p) (:domain carry)
  (:objects r1 - robot b1 b2 - box k1 k2 k3 - room)
  (:init (at r1 k1) (in b1 k1) (in b2 k2) (door k1 k2) (door k2 k3) (door k2 k1))
  (:goal (and (in b1 k2))))
"""


def carry_task(robot_drop: bool = True, human_drop: bool = False, human_room_type="room"):
    robot = HEAD % "room" + PICK + (DROP if robot_drop else "") + ")"
    human = HEAD % human_room_type + PICK + (DROP if human_drop else "") + ")"
    return load_task_from_strings(robot, PROBLEM, human)


def test_robot_only_schema_is_one_update_with_its_signature():
    task = carry_task()
    names = [u.name for u in task.delta]
    assert "add-drop-has-parameters-?r - robot ?b - box ?x - room" in names
    # the types are not updates of their own; the other preconditions and effects are
    assert not any(n.startswith("add-drop-has-precondition-robot") for n in names)
    assert not any(n.startswith("add-drop-has-precondition-box") for n in names)
    assert not any(n.startswith("add-drop-has-precondition-room") for n in names)
    assert "add-drop-has-precondition-holding ?r ?b" in names
    assert len(names) == 5  # schema, 2 preconditions, add, delete


def test_explaining_the_schema_in_brings_its_types():
    task = carry_task()
    i = next(k for k, u in enumerate(task.delta) if u.feature.kind == SCHEMA)
    drop = task.updated_model({i}).schemas["drop"]
    assert drop.signature == {("robot", "?r"), ("box", "?b"), ("room", "?x")}
    assert drop.pre == drop.signature  # no other component came with it
    assert drop.add == frozenset()
    assert drop.param_types() == ("robot", "box", "room")


def test_human_only_schema_leaves_with_its_signature():
    task = load_task_from_strings(
        HEAD % "room" + PICK + ")", PROBLEM, HEAD % "room" + PICK + DROP + ")"
    )
    names = [u.name for u in task.delta]
    assert "remove-drop-has-parameters-?r - robot ?b - box ?x - room" in names
    assert not any("has-precondition-robot" in n for n in names)
    assert "drop" not in task.updated_model(task.all_updates).schemas


def test_a_type_both_models_give_differently_stays_an_update():
    # the human types move's rooms as 'box': two type preconditions differ, each an update
    task = carry_task(robot_drop=True, human_drop=True, human_room_type="box")
    names = sorted(u.name for u in task.delta)
    assert names == [
        "add-move-has-precondition-room ?x",
        "add-move-has-precondition-room ?y",
        "remove-move-has-precondition-box ?x",
        "remove-move-has-precondition-box ?y",
    ]
    assert not any(u.feature.kind == SCHEMA for u in task.delta)


def test_one_model_schema_is_grounded_over_its_types_only():
    task = carry_task()
    fam = ground(task)
    drops = sorted(a.args for a in fam.actions if a.name == "drop")
    # 1 robot x 2 boxes x 3 rooms, not 6 objects ** 3
    assert len(drops) == 6
    assert all(a[0] == "r1" and a[1].startswith("b") and a[2].startswith("k") for a in drops)
    # its type preconditions hold whenever it exists: unguarded entries
    ga = next(a for a in fam.actions if a.name == "drop")
    typed = {fam.atoms[i]: g for i, g in ga.pre if fam.atoms[i][0] in ("robot", "box", "room")}
    assert typed and all(g is None for g in typed.values())
    assert ga.exists is not None


def _write_eight_parameter_task(folder: Path, per_type: int) -> Path:
    """A robot-only schema with 8 typed parameters over 5 types of ``per_type`` objects."""
    types = ("truck", "goods", "market", "depot", "level")
    objects = "\n    ".join(" ".join(f"{t}{i}" for i in range(per_type)) + f" - {t}" for t in types)
    body = """(define (domain tpp8)
  (:requirements :strips :typing)
  (:types truck goods market depot level)
  (:predicates (at ?t - truck ?m - market) (loaded ?g - goods ?t - truck ?l - level)
               (stored ?g - goods ?d - depot ?l - level) (next ?a ?b - level) (ready ?d - depot))
  (:action drive :parameters (?t - truck ?a ?b - market)
    :precondition (at ?t ?a) :effect (and (at ?t ?b) (not (at ?t ?a))))
  %s)
"""
    unload = """(:action unload
    :parameters (?t - truck ?g - goods ?m - market ?d - depot ?l1 ?l2 ?l3 ?l4 - level)
    :precondition (and (at ?t ?m) (loaded ?g ?t ?l1) (next ?l2 ?l1) (stored ?g ?d ?l3)
                       (next ?l3 ?l4))
    :effect (and (loaded ?g ?t ?l2) (not (loaded ?g ?t ?l1)) (stored ?g ?d ?l4)
                 (not (stored ?g ?d ?l3)) (ready ?d)))"""
    nexts = " ".join(f"(next level{i} level{i + 1})" for i in range(per_type - 1))
    folder.mkdir(parents=True, exist_ok=True)
    (folder / "robot-domain.pddl").write_text(body % unload)
    (folder / "human-domain.pddl").write_text(body % "")
    (folder / "p1").mkdir(exist_ok=True)
    (folder / "p1" / "robot-problem.pddl").write_text(
        f"""(define (problem p1) (:domain tpp8)
  (:objects {objects})
  (:init (at truck0 market0) (loaded goods0 truck0 level1) (stored goods0 depot0 level0)
         {nexts})
  (:goal (and (ready depot0))))
"""
    )
    return folder / "p1"


def _load_dir(d: Path):
    p = resolve_task_dir(d)
    return load_task(p["robot_domain"], p["robot_problem"], p["human_domain"], p["human_problem"])


def test_eight_parameter_robot_only_schema_grounding_size(tmp_path):
    """Regression: 20 objects of 5 types; the robot-only 8-parameter schema grounds over its
    types (4 ** 8), not over every object (20 ** 8 = 25.6 billion)."""
    task = _load_dir(_write_eight_parameter_task(tmp_path / "tpp8", per_type=4))
    assert len(task.human.objects | task.robot.objects) == 20
    assert [u.name for u in task.delta][0] == (
        "add-unload-has-parameters-?t - truck ?g - goods ?m - market ?d - depot "
        "?l1 - level ?l2 - level ?l3 - level ?l4 - level"
    )
    assert len(task.delta) == 11
    fam = ground(task)
    unloads = sum(1 for a in fam.actions if a.name == "unload")
    drives = sum(1 for a in fam.actions if a.name == "drive")
    assert unloads == 4**8
    assert drives == 4 * 4  # reachability: only truck0 is at a market, so only it drives
    assert fam == ground(task, vectorise_from=None)


class _Expired(Exception):
    pass


class _CountdownDeadline:
    """Raises after ``n`` checks: grounding must check its deadline while it works."""

    def __init__(self, n: int):
        self.n = n
        self.checks = 0

    def check(self) -> None:
        self.checks += 1
        if self.checks > self.n:
            raise _Expired


def test_grounding_checks_its_deadline(tmp_path):
    task = _load_dir(_write_eight_parameter_task(tmp_path / "tpp8", per_type=4))
    d = _CountdownDeadline(3)
    with pytest.raises(_Expired):
        ground(task, deadline=d)
    assert d.checks == 4


@pytest.mark.parametrize(
    "folder",
    sorted(
        str(p.relative_to(ROOT))
        for pattern in ("domains/*/p*", "docs/examples/*/p*")
        for p in ROOT.glob(pattern)
    ),
)
def test_vectorised_grounding_equals_per_action_on_shipped_tasks(folder):
    task = _load_dir(ROOT / folder)
    assert ground(task, vectorise_from=1) == ground(task, vectorise_from=None)


def test_vectorised_grounding_in_small_blocks_equals_per_action(monkeypatch):
    """Large schemas are grounded in blocks of rows (the deadline is checked between them);
    fresh atom ids come out in the per-action order across block boundaries too."""
    import mega_sat.ground.grounding as grounding

    monkeypatch.setattr(grounding, "_VECTOR_ROWS", 3)
    for folder in sorted(ROOT.glob("domains/*/p*")):
        task = _load_dir(folder)
        assert ground(task, vectorise_from=1) == ground(task, vectorise_from=None), folder


@oracle_settings(60, suppress_health_check=())
@given(data=st.data())
def test_vectorised_grounding_equals_per_action_on_random_tasks(data):
    task = data.draw(two_model_tasks(max_delta=8))
    a, b = ground(task, vectorise_from=1), ground(task, vectorise_from=None)
    assert a == b
    # the grounding of every one-model schema is pruned by its signature only
    for name in set(task.robot.schemas) ^ set(task.human.schemas):
        s = task.robot.schemas.get(name) or task.human.schemas[name]
        assert not any(
            u.feature.kind == PRE and u.feature.action == name and u.feature.atom in s.signature
            for u in task.delta
        )


def test_large_families_skip_the_swap_search(tmp_path):
    """The swap search is one pass over every action per candidate pair; above
    ``symmetry.MAX_ACTIONS`` it is skipped (symmetry breaking only prunes mirror plans)."""
    from mega_sat.sat.symmetry import MAX_ACTIONS, object_swaps

    task = _load_dir(_write_eight_parameter_task(tmp_path / "tpp8", per_type=4))
    fam = ground(task)
    assert len(fam.actions) > MAX_ACTIONS
    assert object_swaps(fam) == []
    small = carry_task()
    fam_small = ground(small)
    assert object_swaps(fam_small, max_actions=0) == []
    assert object_swaps(fam_small) == object_swaps(fam_small, max_actions=len(fam_small.actions))


def test_running_out_of_memory_is_one_clear_error(monkeypatch):
    """A MemoryError anywhere in a command ends in one 'error: out of memory' line (exit 2),
    as JSON with --json, never a traceback."""
    import json

    from click.testing import CliRunner

    import mega_sat.ground.grounding
    from mega_sat.cli.commands import main

    def too_large(*args, **kwargs):
        raise MemoryError

    monkeypatch.setattr(mega_sat.ground.grounding, "ground", too_large)
    for extra in ([], ["--json"]):
        r = CliRunner().invoke(main, ["frontier", "--task", "domains/usar-fetch/p1", *extra])
        assert r.exit_code == 2, r.output
        assert r.exception is None or isinstance(r.exception, SystemExit)
        if extra:
            assert json.loads(r.stdout)["error"].startswith("out of memory")
        else:
            assert r.stderr.startswith("error: out of memory") and r.stderr.count("\n") == 1
