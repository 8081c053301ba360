"""Independent checks of an answer ``(E, pi)``: the certificate a user can trust.

A pair passes when (1) ``pi`` runs in the robot model and reaches its goal, (2) ``pi`` runs in
``human + E`` and reaches its goal, and (3) its cost there equals the optimum of ``human + E``
computed by a *different* planner than the one that produced the answer.  Plans are simulated
on the lifted models (not the ground family the engines use), and, when VAL is installed, also
validated by VAL on the PDDL files mega-sat writes.
"""

from __future__ import annotations

from collections.abc import Sequence
from dataclasses import dataclass

from mega_sat.deadline import Deadline, TimeLimitReached
from mega_sat.errors import PlannerError
from mega_sat.ground.family import GroundFamily
from mega_sat.ground.simulate import simulate, step_mismatch
from mega_sat.model.lifted import PlanStep, step_str
from mega_sat.model.task import TwoModelTask
from mega_sat.options import DEFAULT, Options
from mega_sat.status import Status


@dataclass(frozen=True)
class Check:
    name: str
    ok: bool
    detail: str

    def to_dict(self) -> dict:
        return {"name": self.name, "ok": self.ok, "detail": self.detail}


class ChecksCutShort(TimeLimitReached):  # noqa: N818 - a TimeLimitReached, named for its part
    """The time limit reached while a pair was being checked, after some checks were done:
    ``checks`` are those (each a finished answer, a pass or a failure), ``pending`` names the
    check the limit cut short.  Its ``detail`` says both, for the error line."""

    def __init__(self, stop: TimeLimitReached, checks: Sequence[Check], pending: str):
        done = "; ".join(f"{c.name}: {'ok' if c.ok else 'FAILED'} ({c.detail})" for c in checks)
        super().__init__(
            stop.seconds,
            forced=stop.forced,
            detail=f"checked: {done}; not checked: {pending}",
            partial=True,
        )
        self.checks = tuple(checks)
        self.pending = pending


@dataclass(frozen=True)
class VerifyReport:
    """All checks of one pair; ``ok`` only if every check passed.  ``explanation_cost``: the
    explanation's cost(E) under the update costs, when they are in use (``size``: its |E|).
    ``skipped`` names checks that were not run (and why): neither a pass nor a failure."""

    checks: tuple[Check, ...]
    explanation_cost: int | None = None
    size: int | None = None
    skipped: tuple[str, ...] = ()

    @property
    def ok(self) -> bool:
        return all(c.ok for c in self.checks)

    def lines(self) -> list[str]:
        out = [f"{'ok  ' if c.ok else 'FAIL'} {c.name}: {c.detail}" for c in self.checks]
        if self.explanation_cost is not None:
            out.append(
                f"explanation cost under the update costs: cost(E) = {self.explanation_cost}, "
                f"|E| = {self.size}"
            )
        return out + [f"skip {s}" for s in self.skipped]

    def to_dict(self) -> dict:
        d: dict = {
            "ok": self.ok,
            "checks": [c.to_dict() for c in self.checks],
        }
        if self.explanation_cost is not None:
            d["explanation_cost"] = self.explanation_cost
            d["size"] = self.size
        if self.skipped:
            d["skipped"] = list(self.skipped)
        return d


SUPERSET_CHECK_LIMIT = DEFAULT.superset_check_limit
"""At most this many strict supersets of an MME are re-checked, one optimal planner call each
(``Options.superset_check_limit``)."""

SUPERSETS = "optimal in every human + E' with E < E' <= Delta"


def verify_supersets(
    task: TwoModelTask,
    family: GroundFamily,
    selection: frozenset[int],
    plan: Sequence[PlanStep],
    *,
    checker: str,
    oracles=None,
    deadline: Deadline | None = None,
    limit: int | None = None,
    options: Options = DEFAULT,
) -> Check | str:
    """The check that makes an MME monotonic: ``plan`` runs in ``human + E'`` (lifted
    simulation) at the optimum of ``human + E'`` (by ``checker``) for every strict superset
    ``E'`` of ``selection``; with more than ``limit`` supersets (default
    ``options.superset_check_limit``), the reason it is skipped."""
    from mega_sat.planners.node_planner import NodePlanner

    limit = options.superset_check_limit if limit is None else limit
    rest = sorted(set(range(len(task.delta))) - set(selection))
    count = (1 << len(rest)) - 1
    if count > limit:
        return f"{SUPERSETS}: {count} supersets, more than {limit}"
    planner = NodePlanner(
        task, family, checker, oracles=oracles, deadline=deadline, options=options
    )
    plan = tuple(tuple(s) for s in plan)
    for mask in range(1, count + 1):
        added = frozenset(rest[k] for k in range(len(rest)) if mask >> k & 1)
        bigger = frozenset(selection) | added
        where = "with " + ", ".join(task.names(sorted(added))) + " also explained"
        sim = simulate(task.updated_model(bigger), plan)
        if not sim.valid:
            return Check(SUPERSETS, False, f"{where}: {sim.reason}")
        opt = planner.optimal(bigger)
        if opt.status != Status.OPTIMAL or not opt.exact:
            return Check(SUPERSETS, False, f"{where}: no proven optimum by {checker}")
        if opt.cost != sim.cost:
            return Check(SUPERSETS, False, f"{where}: optimum {opt.cost}; plan: {sim.cost}")
    if count == 0:
        return Check(SUPERSETS, True, "E is all of Delta: no strict superset")
    many = f"{count} supersets" if count > 1 else "1 superset"
    return Check(SUPERSETS, True, f"{many}, optima by {checker}")


def check_verify_arguments(producer: object, use_val: object) -> None:
    """``producer`` names a planner (the checker must be another one) and ``use_val`` is a
    bool: "FD" or "no" would quietly check an answer with its own planner, or run VAL."""
    from mega_sat.errors import UsageError
    from mega_sat.planners.node_planner import PLANNERS

    if producer is not None and producer not in PLANNERS:
        raise UsageError(f"unknown producer {producer!r} (choose from {', '.join(PLANNERS)})")
    if not isinstance(use_val, bool):
        raise UsageError(f"use_val must be True or False, got {use_val!r}")


def point_selection(task, point) -> frozenset[int]:
    """``point.selection``, once it is known to name the same updates of ``task``'s model
    difference as ``point.explanation`` (a point of another task indexes another one, and
    checking its indices here would check some other explanation)."""
    from mega_sat.errors import UsageError

    sel = point.selection
    names = None
    if all(0 <= i < len(task.delta) for i in sel):
        names = sorted(task.names(sel))
    if names != sorted(point.explanation):
        raise UsageError(
            "the point's explanation is not the same updates of this task's model "
            f"difference: {list(point.explanation)} (is it from another task?)"
        )
    return sel


VAL_INT_LIMIT = 2**31
"""VAL adds costs in 32-bit integers: a plan costing this much or more wraps around."""


def checker_for(producer: str, family: GroundFamily | None = None) -> str:
    """The planner used to re-derive the optimum: never the one that produced the answer.
    Fast Downward when installed and ``family``'s costs fit its integers (for built-in, SAT
    or portfolio results), else the built-in planner for SAT, portfolio or Fast Downward
    results and the SAT OPT oracle for built-in ones.  (The portfolio answers by SAT or by
    uniform-cost search; without Fast Downward its check shares the search code with one of
    them.)"""
    if producer == "fd":
        return "builtin"
    from mega_sat.planners.fast_downward import family_cost_problem, fd_available

    if fd_available() and (family is None or family_cost_problem(family) is None):
        return "fd"
    return "builtin" if producer in ("sat", "portfolio") else "sat"


def _not_an_action(model, plan) -> str | None:
    """Why some step of ``plan`` names no action schema of ``model`` with its number of
    arguments (``None`` when every step does)."""
    for k, raw in enumerate(plan, 1):
        step = tuple(x.lower() for x in raw)
        mismatch = step_mismatch(model, step)
        if mismatch is not None:
            return f"step {k} {step_str(step)}: {mismatch}"
    return None


def verify_pair(
    task: TwoModelTask,
    family: GroundFamily | None,
    selection: frozenset[int],
    plan: Sequence[PlanStep],
    *,
    producer: str = "sat",
    robot_cost: int | None = None,
    human_cost: int | None = None,
    use_val: bool = True,
    checker: str | None = None,
    oracles=None,
    deadline: Deadline | None = None,
    update_costs: tuple[int, ...] | None = None,
    explanation_cost: int | None = None,
    options: Options = DEFAULT,
    alone: tuple[TwoModelTask, GroundFamily] | None = None,
) -> VerifyReport:
    """Check one answer; ``robot_cost``/``human_cost``, when given, must match the simulation.

    ``alone``: ``human + E`` as a task of its own and its family
    (:func:`~mega_sat.ground.grounding.ground_member`), for the optimum when ``family`` (then
    unused, may be None) cannot be compiled.

    ``update_costs`` (one per update): the report states cost(E) under them, and a reported
    ``explanation_cost``, when given, must equal it.

    ``oracles``: live SAT oracles of this task, reused when the checker is ``sat``.  The
    checker's planner and VAL stop at ``deadline`` with :class:`ChecksCutShort` (a
    :class:`~mega_sat.deadline.TimeLimitReached` holding the checks finished before it; an
    optimum not re-derived is neither a pass nor a failure).  ``options``: the tuning knobs of
    the checker's planner.
    """
    from mega_sat.planners.node_planner import NodePlanner

    plan = tuple(tuple(s) for s in plan)
    checks: list[Check] = []
    sim_r = simulate(task.robot, plan)
    checks.append(
        Check(
            "valid in robot model",
            sim_r.valid,
            f"cost {sim_r.cost}" if sim_r.valid else sim_r.reason or "invalid",
        )
    )
    if robot_cost is not None and sim_r.valid:
        checks.append(
            Check(
                "robot cost as reported",
                sim_r.cost == robot_cost,
                f"reported {robot_cost}, simulated {sim_r.cost}",
            )
        )
    updated = task.updated_model(selection)
    sim_h = simulate(updated, plan)
    checks.append(
        Check(
            "valid in human + E",
            sim_h.valid,
            f"cost {sim_h.cost}" if sim_h.valid else sim_h.reason or "invalid",
        )
    )
    if human_cost is not None and sim_h.valid:
        checks.append(
            Check(
                "human cost as reported",
                sim_h.cost == human_cost,
                f"reported {human_cost}, simulated {sim_h.cost}",
            )
        )
    opt_task, opt_family, opt_sel = (task, family, frozenset(selection))
    if alone is not None:
        opt_task, opt_family, opt_sel = (*alone, frozenset())
    kind = checker or checker_for(producer, opt_family)
    checker = NodePlanner(
        opt_task, opt_family, kind, oracles=oracles, deadline=deadline, options=options
    )
    try:
        opt = checker.optimal(opt_sel)
    except TimeLimitReached as e:
        # the checks done so far are finished answers (even when the backstop timer cut the
        # planner short): say them rather than nothing at all
        pending = f"optimal in human + E (by {kind})"
        if use_val:
            from mega_sat.planners.val import val_available

            if val_available():
                pending += " and the VAL checks"
        raise ChecksCutShort(e, checks, pending) from None
    if opt.status == Status.OPTIMAL:
        good = sim_h.valid and sim_h.cost == opt.cost
        plan_cost = sim_h.cost if sim_h.valid else "not executable"
        detail = f"optimum of human + E by {kind}: {opt.cost}; plan: {plan_cost}"
        if not opt.exact:
            good, detail = False, detail + f" (not proven: {opt.reason})"
        checks.append(Check("optimal in human + E", good, detail))
    else:
        checks.append(
            Check(
                "optimal in human + E",
                False,
                f"{kind} found no optimal plan of human + E ({opt.status})",
            )
        )
    if use_val:
        from mega_sat.planners.val import val_available

        if val_available():
            from mega_sat.pddl.writer import domain_to_pddl, problem_to_pddl
            from mega_sat.planners.val import val_names, val_validate

            models = (("robot model", task.robot, sim_r), ("human + E", updated, sim_h))
            for label, model, sim in models:
                bad = _not_an_action(model, plan)
                if bad is not None:
                    # VAL crashes (SIGSEGV) on a step with too few arguments, and says "goal
                    # not satisfied" for too many: it is not asked about steps it cannot read
                    checks.append(Check(f"VAL: valid in {label}", False, f"not run: {bad}"))
                    continue
                val_model, val_plan = val_names(model, plan)
                try:
                    v = val_validate(
                        domain_to_pddl(val_model, plain_variables=True),
                        problem_to_pddl(val_model),
                        val_plan,
                        deadline=deadline,
                    )
                except TimeLimitReached as e:
                    # as for the optimum: the checks before VAL are finished answers
                    raise ChecksCutShort(e, checks, f"VAL: valid in {label}") from None
                except PlannerError as e:  # VAL could not read what was written for it
                    raise PlannerError(f"VAL could not check the plan in {label}: {e}") from None
                ok, detail = v.valid, f"cost {v.cost}" if v.valid else v.message
                if v.valid and sim.valid and sim.cost is not None:
                    if sim.cost >= VAL_INT_LIMIT:
                        # VAL sums costs in 32-bit integers: its validity stands, its cost not
                        detail += f" (not compared: simulated {sim.cost} is beyond VAL's range)"
                    elif v.cost != sim.cost:
                        ok, detail = False, f"cost {v.cost}, simulated {sim.cost}"
                checks.append(Check(f"VAL: valid in {label}", ok, detail))
    if update_costs is None:
        return VerifyReport(tuple(checks))
    from mega_sat.pddl.update_costs import explanation_cost as cost_of

    cost = cost_of(selection, update_costs)
    if explanation_cost is not None:
        checks.append(
            Check(
                "explanation cost as reported",
                cost == explanation_cost,
                f"reported {explanation_cost}, update costs give {cost}",
            )
        )
    return VerifyReport(tuple(checks), cost, len(selection))
