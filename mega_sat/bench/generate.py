"""Seeded human-model generator: a human model exactly ``k`` features away from the robot's.

The paper's Table "times" measures MEGA at ``|Delta|`` = 2, 7 and 10.  We derive such human
models from any robot model by random, seeded feature flips — removing a precondition, effect,
initial or goal atom the robot has, or adding one it does not — and keep a draw only if both
problems stay solvable.  Added lifted atoms are taken from the same domain's own usage
(a predicate is only placed on parameters whose types match a use elsewhere), and added ground
atoms from the robot's relaxed-reachable atoms, so the human models stay type-sane.
"""

from __future__ import annotations

import random
import time
from dataclasses import dataclass

from mega_sat.errors import UnsolvableError, UsageError
from mega_sat.model.features import (
    ADD,
    DEL,
    GOAL,
    INIT,
    NEGGOAL,
    NEGPRE,
    PRE,
    Feature,
    Update,
    apply_updates,
)
from mega_sat.model.lifted import EQUALITY, Atom, Model, Schema

# seconds a generator searches for a solvable human model before it gives up
DEFAULT_TIME_BUDGET = 120.0

LIFTED_KINDS = (PRE, NEGPRE, ADD, DEL)


@dataclass(frozen=True)
class Generated:
    human: Model
    updates: tuple[Update, ...]
    attempts: int


def _param_types(s: Schema, type_preds: frozenset[str]) -> dict[str, frozenset[str]]:
    return {
        p: frozenset(a[0] for a in s.pre if len(a) == 2 and a[1] == p and a[0] in type_preds)
        for p in s.params
    }


def _candidate_updates(robot: Model, reachable: frozenset[Atom]) -> list[Update]:
    """Every single-feature change the generator may draw (removals and additions)."""
    # types and equality are left as the domain states them: the generator draws no change
    tp = robot.type_predicates | {EQUALITY}
    cands: list[Update] = []
    # removals of robot features (type atoms excluded: those are not beliefs about the robot)
    for s in robot.schemas.values():
        for kind, atoms in ((PRE, s.pre), (NEGPRE, s.negpre), (ADD, s.add), (DEL, s.delete)):
            for a in sorted(atoms):
                if a[0] not in tp:
                    cands.append(Update(Feature(kind, s.name, a), True))
    cands += [Update(Feature(INIT, "", a), True) for a in sorted(robot.init) if a[0] not in tp]
    cands += [Update(Feature(GOAL, "", a), True) for a in sorted(robot.goal)]
    cands += [Update(Feature(NEGGOAL, "", a), True) for a in sorted(robot.neggoal)]
    # additions: lifted atoms shaped like the domain's own uses of each predicate
    shapes: set[tuple[str, tuple[frozenset[str], ...]]] = set()
    for s in robot.schemas.values():
        pt = _param_types(s, tp)
        for atoms in (s.pre, s.negpre, s.add, s.delete):
            for a in atoms:
                if a[0] not in tp and all(x.startswith("?") for x in a[1:]):
                    shapes.add((a[0], tuple(pt.get(x, frozenset()) for x in a[1:])))
    for s in sorted(robot.schemas.values(), key=lambda s: s.name):
        pt = _param_types(s, tp)
        for pred, types in sorted(shapes, key=lambda x: (x[0], [sorted(t) for t in x[1]])):
            options = [[p for p in s.params if pt[p] == t] for t in types]
            if any(not o for o in options):
                continue
            args = tuple(o[0] for o in options)
            atom = (pred, *args)
            for kind, have in ((PRE, s.pre), (NEGPRE, s.negpre), (ADD, s.add), (DEL, s.delete)):
                if atom not in have:
                    cands.append(Update(Feature(kind, s.name, atom), False))
    extra = sorted(a for a in reachable if a[0] not in tp)
    cands += [Update(Feature(INIT, "", a), False) for a in extra if a not in robot.init]
    cands += [
        Update(Feature(GOAL, "", a), False)
        for a in extra
        if a not in robot.goal and a[0] not in _static_preds(robot)
    ]
    return cands


def _static_preds(m: Model) -> set[str]:
    changed = {a[0] for s in m.schemas.values() for a in s.add | s.delete}
    return set(m.predicates) - changed


def generate_human(
    robot: Model,
    k: int,
    seed: int,
    *,
    max_attempts: int = 200,
    time_limit: float = 30.0,
    time_budget: float = DEFAULT_TIME_BUDGET,
    greedy_evaluations: int = 10_000,
    source: str | None = None,
) -> Generated:
    """A human model with ``|Delta| == k`` against ``robot``, both problems solvable.

    Only whether each model has a plan matters (:func:`_has_plan`), not its optimum.
    ``time_limit`` bounds each draw's check, ``time_budget`` the whole generation, the robot's
    own check included (a large ``k`` makes most draws unsolvable, and 200 draws at 30 s each
    would look like a hang).  The robot's check may take the whole budget.
    ``greedy_evaluations`` is the work the cheap first test of each check may spend; it
    changes how fast a draw is decided, not which draws are kept.  ``source`` names the robot
    problem in messages.

    A candidate ``Update(f, True)`` above means "the robot has f and the human will not"
    (a removal from the human's view); ``Update(f, False)`` "the human will believe f".
    """
    from mega_sat.errors import PDDLError
    from mega_sat.ground.grounding import ground
    from mega_sat.model.task import TwoModelTask

    if k < 0:
        raise UsageError(f"--delta must be >= 0, got {k}")
    if not time_budget >= 0:  # nan too: it compares false with everything
        raise UsageError(f"--time-budget must be a number of seconds >= 0, got {time_budget}")
    # the budget covers the robot's own plan too: a user who gave 5 s waits about 5 s
    deadline = time.perf_counter() + time_budget
    robot_alone = TwoModelTask.from_models(robot, robot)
    robot_family = ground(robot_alone)
    rt = robot_family.specialize(frozenset())
    r = _has_plan(robot_alone, robot_family, deadline, None, greedy_evaluations)
    if r is False:
        raise UnsolvableError(
            "the robot problem has no plan; nothing to generate from", path=source
        )
    if r is None:
        raise UsageError(
            f"no solvable human model with |Delta| = {k} found within {time_budget:g}s (a "
            f"plan of the robot problem was still being searched; seed {seed})",
            path=source,
        )
    # the model's own atoms, without the complement atoms grounding adds for negative goals
    reachable = frozenset(a for a in rt.atoms if a[0] in robot.predicates)
    cands = _candidate_updates(robot, reachable)
    if len(cands) < k:
        raise UsageError(
            f"the robot model offers only {len(cands)} features to flip; --delta {k} is too large"
        )
    rng = random.Random(seed)
    for attempt in range(1, max_attempts + 1):
        left = deadline - time.perf_counter()
        if left <= 0:
            raise UsageError(
                f"no solvable human model with |Delta| = {k} found in {attempt - 1} "
                f"seeded draws within {time_budget:g}s (seed {seed})"
            )
        picks = rng.sample(cands, k)
        # human = robot with each picked feature flipped; express as robot + flips
        flips = [Update(u.feature, not u.robot_has) for u in picks]
        human = apply_updates(robot, robot, flips)
        task = TwoModelTask.from_models(robot, human)
        if len(task.delta) != k:
            continue
        try:
            # a dropped precondition can make an action reachable whose cost term the
            # problem leaves undefined (elevators' travel tables): that draw is no task
            ground(task)
            human_alone = TwoModelTask.from_models(human, human)
            human_family = ground(human_alone)
        except PDDLError:
            continue
        h = _has_plan(
            human_alone, human_family, deadline, min(time_limit, left), greedy_evaluations
        )
        if h is None and left < time_limit:
            # cut short by the budget, not by its own limit: stop here rather than move on to
            # the next draw, so that a found instance never depends on the machine's speed
            raise UsageError(
                f"no solvable human model with |Delta| = {k} found within {time_budget:g}s "
                f"(draw {attempt} was still being checked; seed {seed})"
            )
        if not h:
            continue
        return Generated(human, task.delta, attempt)
    raise UsageError(
        f"no solvable human model with |Delta| = {k} found in {max_attempts} "
        f"seeded draws (seed {seed})"
    )


def _has_plan(
    task, family, deadline: float, time_limit: float | None, greedy_evaluations: int
) -> bool | None:
    """Whether one model (``task``, a model paired with itself, and its ground ``family``) has
    a plan; ``None`` if that is not decided within the generation's budget (``deadline``, a
    :func:`time.perf_counter` value) and ``time_limit`` seconds.

    A greedy best-first search on h_add (:mod:`mega_sat.search.greedy`, ``greedy_evaluations``
    heuristic evaluations) finds a plan of most solvable models in a fraction of a second,
    where an optimal planner may need minutes on a large model, and proves a small model
    unsolvable by running out of states.  What it leaves open, the built-in optimal planner
    decides: blind search, then Fast Downward when installed, else LM-cut.  Both answer by
    work, not by the clock, so a draw they decide is decided alike on every machine."""
    from mega_sat.deadline import Deadline, TimeLimitReached
    from mega_sat.planners.node_planner import NodePlanner
    from mega_sat.search.greedy import greedy_search
    from mega_sat.status import Status

    end = deadline if time_limit is None else min(deadline, time.perf_counter() + time_limit)
    until = Deadline(end, max(0.0, end - time.perf_counter()))
    if greedy_evaluations > 0:
        found = greedy_search(family.specialize(frozenset()), greedy_evaluations, until)
        if found is not None:
            return found is not False  # a plan (maybe empty), or every state expanded
    planner = NodePlanner(task, family, "builtin", deadline=until)
    try:
        status = planner.optimal(frozenset()).status
    except TimeLimitReached:
        return None
    return {Status.OPTIMAL: True, Status.UNSOLVABLE: False}.get(status)


def write_instance(
    robot_domain: str,
    robot_problem: str,
    k: int,
    seed: int,
    out_dir,
    *,
    overwrite: bool = False,
    time_budget: float = DEFAULT_TIME_BUDGET,
) -> Generated:
    """Generate and write a task folder: the robot files copied verbatim, the human files
    written by mega-sat, so ``--task out_dir`` loads it."""
    import shutil
    from pathlib import Path

    from mega_sat.output import OutputError, check_target
    from mega_sat.pddl.reader import read_model
    from mega_sat.pddl.writer import write_model

    robot = read_model(robot_domain, robot_problem)
    out = Path(out_dir)
    targets = [out / n for n in ("robot-domain.pddl", "robot-problem.pddl")]
    for name in (
        "robot-domain.pddl",
        "robot-problem.pddl",
        "human-domain.pddl",
        "human-problem.pddl",
    ):
        check_target(out / name, force=overwrite)  # before the draws, not after
    g = generate_human(robot, k, seed, time_budget=time_budget, source=str(robot_problem))
    try:
        out.mkdir(parents=True, exist_ok=True)
        write_model(
            g.human,
            out,
            domain_file="human-domain.pddl",
            problem_file="human-problem.pddl",
            overwrite=overwrite,
        )
        shutil.copyfile(robot_domain, targets[0])
        shutil.copyfile(robot_problem, targets[1])
    except OSError as e:
        where = e.filename if e.filename is not None else out
        raise OutputError(f"cannot write: {e.strerror or e}", path=str(where)) from None
    return g


def instance_seed(base_seed: int, domain: str, problem: str, k: int) -> int:
    """A stable per-instance seed, so the whole suite is reproducible from one number."""
    import zlib

    return base_seed * 1_000_003 + zlib.crc32(f"{domain}/{problem}/{k}".encode())
