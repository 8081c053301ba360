"""MCE: the smallest explanation that makes one given plan optimal in the human's model.

This is the model-reconciliation problem MEGA extends (the paper's reference [explain]).  The
same hitting-set machinery as the ``sat`` engine, with a cheaper check per candidate: the plan
is fixed, so a candidate ``E`` only needs a simulation of the plan in ``human + E`` and one OPT
call.  A failed candidate teaches a clause: if the plan does not run in ``human + E``,
``NOT(failure_core(E, plan))`` (the first failing component and the causal link that makes it
fail: every selection agreeing there fails too, :func:`~mega_sat.engines.support.failure_core`);
if it runs but costs more than ``pi*``, ``NOT(E restricted to costs(plan) ∪ support(pi*))``
(the plan keeps its cost, ``pi*`` still runs no dearer, so the plan stays non-optimal).
"""

from __future__ import annotations

import time
from collections.abc import Sequence

from mega_sat.deadline import Deadline
from mega_sat.engines.hitting_set import make_hitting_set
from mega_sat.engines.progress import Progress
from mega_sat.engines.support import causal_support, exclusion_clause, failure_core
from mega_sat.errors import PlannerError, UsageError
from mega_sat.ground.family import GroundFamily
from mega_sat.ground.simulate import simulate, simulate_ground
from mega_sat.model.lifted import PlanStep
from mega_sat.model.task import TwoModelTask
from mega_sat.options import DEFAULT, Options
from mega_sat.pddl.update_costs import explanation_cost
from mega_sat.planners.node_planner import NodePlanner, require_robot_plan
from mega_sat.results import Explanation
from mega_sat.status import Status


def minimal_explanation(
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
    """Smallest ``E`` making ``plan`` (default: a robot-optimal plan) optimal in ``human + E``
    (with ``update_costs``: the cheapest by the sum of its updates' costs).

    Stops at ``deadline`` (or ``timeout`` seconds from now) with
    :class:`~mega_sat.deadline.TimeLimitReached`: a candidate that is not the smallest proves
    nothing, so there is no partial answer.  ``progress`` shows each candidate as it is
    checked (for a live display); ``options``: the tuning knobs of the planner."""
    t0 = time.perf_counter()
    progress = progress if progress is not None else Progress()
    progress.start("mce", tuple(u.name for u in task.delta))
    deadline = deadline if deadline is not None else Deadline.after(timeout)
    np_ = NodePlanner(task, family, planner, oracles=oracles, deadline=deadline, options=options)
    notes: list[str] = []
    exact = True
    undecided = 0  # candidates excluded without a proof
    if plan is None:
        r = np_.optimal(family.robot_selection)
        require_robot_plan(task, r)
        plan = r.plan
        exact &= r.exact
    plan = tuple(tuple(s) for s in plan)
    sim_r = simulate(task.robot, plan)
    if not sim_r.valid:
        raise UsageError(f"the plan is not executable in the robot model: {sim_r.reason}")
    hs = make_hitting_set(hitting_set, len(task.delta), deadline=deadline, costs=update_costs)
    calls = {"candidates": 0, "opt_calls": 0, "learned": 0}
    try:
        while True:
            deadline.check()
            sel = hs.minimum()
            if sel is None:
                # time running out is never the plan's fault: report it as such
                deadline.check()
                if undecided:
                    raise PlannerError(
                        f"no explanation found: the optimum of {undecided} candidate "
                        f"model(s) was not decided ({'; '.join(dict.fromkeys(notes))})"
                    )
                raise UsageError(
                    "no explanation makes this plan optimal in the human's model "
                    "(it is not optimal in the robot model either)"
                )
            calls["candidates"] += 1
            progress.step(len(sel))
            fail = failure_core(family, sel, plan)
            if fail is not None:
                # the first failure alone, kept along its causal link (support.failure_core)
                hs.add(tuple((i, not v) for i, v in fail))
                calls["learned"] += 1
                continue
            sim = simulate_ground(family.specialize(sel), plan)
            opt = np_.optimal(sel)
            calls["opt_calls"] += 1
            if opt.status != Status.OPTIMAL:
                # the plan itself runs, so the model has a plan: this is an undecided call
                deadline.check()
                exact = False
                undecided += 1
                notes.append(f"optimal cost of a candidate model not found: {opt.reason}")
                hs.add(exclusion_clause(sel, range(len(task.delta))))
                continue
            exact &= opt.exact
            if sim.cost <= opt.cost:
                return Explanation(
                    plan=plan,
                    explanation=tuple(task.names(sel)),
                    selection=sel,
                    robot_cost=sim_r.cost,
                    human_cost=sim.cost,
                    exact=exact,
                    notes=tuple(dict.fromkeys(notes)),
                    time_s=time.perf_counter() - t0,
                    weighted_cost=None
                    if update_costs is None
                    else explanation_cost(sel, update_costs),
                    stats={
                        **calls,
                        "planner": planner,
                        "hitting_set": hitting_set,
                        "hitting_set_calls": hs.calls,
                    },
                )
            # plan costs the same, pi* still runs at cost <= c*: the plan stays non-optimal
            cost_guards = {
                i
                for s in plan
                for guards, _ in family.actions[family.action_index[s]].cost
                for i, _ in guards
            }
            on = cost_guards | {i for i, _ in causal_support(family, sel, opt.plan)}
            hs.add(exclusion_clause(sel, on))
            calls["learned"] += 1
    finally:
        hs.close()
