"""One optimal planning call on one model of the family, by a chosen planner.

The A* baseline calls this at every node of its model-space search, MCE and verification use it
too.  Three planners answer the same question (optimal cost and one optimal plan of
``human + E``):

* ``builtin`` — explicit-state search on the ground task: uniform-cost, then A* with LM-cut
  (:func:`mega_sat.search.astar.solve_optimal`);
* ``sat``     — the OPT oracle of the SAT encoding (:mod:`mega_sat.sat.oracles`);
* ``fd``      — Fast Downward ``astar(lmcut())`` on PDDL files of the model, the paper's set-up.
"""

from __future__ import annotations

import time
from dataclasses import dataclass

from mega_sat.deadline import NO_DEADLINE, Deadline, TimeLimitReached
from mega_sat.errors import PlannerError, UsageError
from mega_sat.ground.family import GroundFamily, GroundTask
from mega_sat.model.lifted import PlanStep
from mega_sat.model.task import TwoModelTask

PLANNERS = ("builtin", "sat", "fd")


@dataclass(frozen=True)
class NodePlan:
    """Outcome of one optimal planning call: ``status`` is ``optimal``, ``unsolvable`` or
    ``unknown`` (time-out, horizon cap); ``exact`` is false when optimality is not proven."""

    status: str
    plan: tuple[PlanStep, ...] | None
    cost: int | None
    exact: bool
    planner: str
    time_s: float
    reason: str = ""


class NodePlanner:
    """Answers ``optimal(selection)`` for one task with one planner; keeps what it can alive
    (the SAT oracles, the ground family) across calls.

    Each call gets ``time_limit`` seconds, cut to what is left before ``deadline``; a call
    that the deadline cuts short raises :class:`TimeLimitReached` (it proved nothing), one
    that runs out of its own ``time_limit`` answers ``unknown``.
    """

    def __init__(
        self,
        task: TwoModelTask,
        family: GroundFamily,
        kind: str = "builtin",
        *,
        time_limit: float | None = None,
        oracles=None,
        solver: str = "cadical195",
        deadline: Deadline | None = None,
    ):
        if kind not in PLANNERS:
            raise UsageError(f"unknown planner {kind!r} (choose from {', '.join(PLANNERS)})")
        if kind == "fd":
            from mega_sat.planners.fast_downward import fd_available

            if not fd_available():
                raise UsageError("planner 'fd' needs Fast Downward: pip install 'mega-sat[fd]'")
        self.task, self.family, self.kind = task, family, kind
        self.time_limit = time_limit
        self.deadline = deadline if deadline is not None else NO_DEADLINE
        self._oracles = oracles
        self._solver = solver
        self.calls = 0
        self.time_s = 0.0

    @property
    def oracles(self):
        if self._oracles is None:
            from mega_sat.sat.oracles import SatOracles

            self._oracles = SatOracles(self.family, solver=self._solver)
            if self.deadline.limited:
                self._oracles.deadline = self.deadline
        return self._oracles

    def optimal(self, selection: frozenset[int]) -> NodePlan:
        from mega_sat.sat.oracles import OracleInterrupted

        t0 = time.perf_counter()
        self.calls += 1
        self.deadline.check()
        try:
            r = self._optimal(frozenset(selection), t0)
        except OracleInterrupted:
            if self.deadline.expired():
                raise TimeLimitReached(self.deadline.seconds) from None
            raise
        finally:
            self.time_s += time.perf_counter() - t0
        if r.status == "unknown" and self.deadline.expired():
            raise TimeLimitReached(self.deadline.seconds)  # cut short: nothing proven
        return r

    def _optimal(self, sel: frozenset[int], t0: float) -> NodePlan:
        limit = self.deadline.cap(self.time_limit)
        task = self.family.specialize(sel)
        if task.goal <= task.init:
            # the empty plan is optimal (costs are >= 0); some planners refuse such tasks
            return NodePlan("optimal", (), 0, True, self.kind, time.perf_counter() - t0)
        if self.kind == "builtin":
            from mega_sat.search.astar import solve_optimal

            r = solve_optimal(task, time_limit=limit)
            status = r.status if r.status in ("optimal", "unsolvable") else "unknown"
            return NodePlan(
                status,
                r.plan,
                r.cost,
                status != "unknown",
                "builtin",
                time.perf_counter() - t0,
                "" if status != "unknown" else r.status,
            )
        if self.kind == "sat":
            r = self.oracles.opt(sel)
            status = r.status if r.status.decided else "unknown"
            return NodePlan(
                status, r.plan, r.cost, r.exact, "sat", time.perf_counter() - t0, r.reason
            )
        from mega_sat.pddl.writer import domain_to_pddl, problem_to_pddl
        from mega_sat.planners.fast_downward import fd_plan

        model = self.task.updated_model(sel)
        r = None
        if not any(s.negpre for s in model.schemas.values()):
            try:
                r = fd_plan(domain_to_pddl(model), problem_to_pddl(model), time_limit=limit)
            except PlannerError as e:
                if "exit code 34" not in str(e):
                    raise
        if r is None:
            # FD compiles negative preconditions (and some add/delete overlaps) into axioms or
            # conditional effects, which LM-cut rejects: hand it the ground model with those
            # compiled away instead (same plans, same costs)
            dom, prob, names = ground_strips_pddl(task)
            r = fd_plan(dom, prob, time_limit=self.deadline.cap(self.time_limit))
            if r.status == "optimal" and r.plan is not None:
                plan = tuple(names[s[0]] for s in r.plan)
                return NodePlan("optimal", plan, r.cost, True, "fd", time.perf_counter() - t0)
        status = r.status if r.status in ("optimal", "unsolvable") else "unknown"
        if status == "optimal" and r.plan is not None:
            # FD may print names in another case or order; map back onto the family's steps
            plan = tuple(tuple(x.lower() for x in s) for s in r.plan)
            missing = [s for s in plan if s not in self.family.action_index]
            if missing:
                raise PlannerError(
                    f"Fast Downward returned an action outside the ground family: "
                    f"({' '.join(missing[0])})"
                )
            return NodePlan("optimal", plan, r.cost, True, "fd", time.perf_counter() - t0)
        return NodePlan(
            status, None, None, status != "unknown", "fd", time.perf_counter() - t0, r.status
        )


def ground_strips_pddl(task: GroundTask) -> tuple[str, str, dict[str, PlanStep]]:
    """``task`` as ground STRIPS PDDL without negative preconditions.

    Every atom ``p`` tested negatively gets a complement atom kept exactly in sync per ground
    action (an action that adds and deletes ``p`` adds it, as PDDL says).  Returns the domain,
    the problem and a map from action names back to plan steps.
    """
    neg = sorted({p for a in task.actions for p in a.negpre})
    comp = {p: len(task.atoms) + k for k, p in enumerate(neg)}
    n_atoms = len(task.atoms) + len(neg)

    def atom(i: int) -> str:
        return f"(a{i})"

    actions, names = [], {}
    for k, a in enumerate(task.actions):
        adds = set(a.add)
        dels = set(a.delete) - adds
        pre = [atom(p) for p in sorted(a.pre)] + [atom(comp[p]) for p in sorted(a.negpre)]
        eff = [atom(p) for p in sorted(adds)] + [f"(not {atom(p)})" for p in sorted(dels)]
        eff += [f"(not {atom(comp[p])})" for p in sorted(adds) if p in comp]
        eff += [atom(comp[p]) for p in sorted(dels) if p in comp]
        eff.append(f"(increase (total-cost) {a.cost})")
        name = f"act{k}"
        names[name] = a.step
        actions.append(
            f"  (:action {name}\n    :parameters ()\n"
            f"    :precondition (and {' '.join(pre)})\n"
            f"    :effect (and {' '.join(eff)}))"
        )
    preds = " ".join(f"(a{i})" for i in range(n_atoms))
    domain = (
        "(define (domain ground)\n  (:requirements :strips :action-costs)\n"
        f"  (:predicates {preds})\n  (:functions (total-cost) - number)\n"
        + "\n".join(actions)
        + ")\n"
    )
    init = [atom(p) for p in sorted(task.init)]
    init += [atom(comp[p]) for p in neg if p not in task.init]
    goal = " ".join(atom(p) for p in sorted(task.goal))
    problem = (
        "(define (problem ground-p) (:domain ground)\n"
        f"  (:init {' '.join(init)} (= (total-cost) 0))\n"
        f"  (:goal (and {goal}))\n  (:metric minimize (total-cost)))\n"
    )
    return domain, problem, names
