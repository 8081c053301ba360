"""The library API: load a task, compute the frontier, solve for one alpha, explain, verify.

Typical use::

    from mega_sat import api
    task = api.load_task("domains/usar-fetch/robot-domain.pddl",
                         "domains/usar-fetch/p1/robot-problem.pddl",
                         "domains/usar-fetch/human-domain.pddl",
                         "domains/usar-fetch/p1/human-problem.pddl")
    sol = api.solve(task, alpha=0.1)                 # engine="sat" (default) or "astar"
    print(sol.chosen.explanation, sol.chosen.plan)
    assert api.verify(task, sol.chosen).ok

A :class:`MegaSolver` keeps the ground family and the SAT solvers alive, so asking it for
several alphas, the frontier and an MCE costs one grounding and one encoding.
"""

from __future__ import annotations

from collections.abc import Iterable, Mapping, Sequence
from functools import cached_property

from mega_sat.deadline import Deadline
from mega_sat.engines.progress import Progress
from mega_sat.engines.sat_loop import default_joint, default_planner
from mega_sat.engines.verify import VerifyReport, verify_pair
from mega_sat.errors import UsageError
from mega_sat.ground.family import GroundFamily
from mega_sat.model.lifted import PlanStep
from mega_sat.model.task import TwoModelTask
from mega_sat.options import Options
from mega_sat.pddl.loading import load_task, load_task_dir, load_task_from_strings
from mega_sat.pddl.multi_task import MultiHumanTask, load_multi_task, load_multi_task_dir
from mega_sat.pddl.planio import as_plan
from mega_sat.pddl.up_models import load_task_from_up
from mega_sat.pddl.update_costs import UpdateCosts, cost_vector, load_update_costs
from mega_sat.planners.node_planner import checked_run_arguments
from mega_sat.results import Explanation, Frontier, FrontierPoint, Solution, check_alpha, choose

ENGINES = ("sat", "astar")
EXPLANATION_KINDS = ("mce", "mme")

__all__ = [
    "ENGINES",
    "EXPLANATION_KINDS",
    "MegaSolver",
    "MultiHumanTask",
    "Options",
    "default_joint",
    "default_planner",
    "explain",
    "frontier",
    "load_task",
    "load_task_dir",
    "load_task_from_strings",
    "load_task_from_up",
    "load_multi_task",
    "load_multi_task_dir",
    "load_update_costs",
    "solve",
    "verify",
]


_check_alpha = check_alpha  # the name the CLI imports


class MegaSolver:
    """One task with its ground family and solvers kept alive across calls.

    ``engine``: ``sat`` (hitting-set loop, exact) or ``astar`` (the paper's Algorithm 1).
    ``planner``: the optimal planner called on candidate models (``builtin``, ``sat``, ``fd``):
    the per-node planner of ``astar``, the OPT oracle of ``sat`` (after its cheaper proofs),
    and MCE's.  ``joint``: how the ``sat`` engine answers JOINT: ``portfolio`` (SAT with a
    conflict budget, then explicit paired-state search), ``sat`` or ``search``; all exact.
    ``hitting_set``: ``rc2`` or ``ilp``.

    Defaults (``None``, see :func:`default_planner`): ``astar`` uses ``builtin``; ``sat`` uses
    SAT for both OPT and JOINT, unless some action costs 0, where the horizon argument fails
    and ``builtin`` with ``portfolio`` keep the answers exact; OPT on families of at least
    ``Options.fd_from_actions`` ground actions goes to Fast Downward when it is installed.

    ``timeout`` (seconds) is one time limit for everything the solver does from its creation
    on: grounding, the encodings, every call and every search, SAT call and subprocess within
    them (``deadline``: the same as a :class:`~mega_sat.deadline.Deadline` made by the
    caller, e.g. the CLI's, which counts from the start of the process).  At the limit the
    ``sat`` engine's frontier returns what it has proven, marked incomplete; a step with
    nothing to report raises :class:`~mega_sat.deadline.TimeLimitReached`, after which
    :meth:`partial_frontier` still gives what was proven.

    ``update_costs``: a positive integer cost per update, a mapping from update name (as
    ``mega-sat diff`` prints it) to cost or the :class:`~mega_sat.pddl.update_costs.UpdateCosts`
    of :func:`load_update_costs`; updates not given cost 1.  The explanation cost is then the
    sum of the costs instead of |E|, in the frontier, the objective, MCE and verification.  A
    name outside Delta or a cost that is not a positive integer is an
    :class:`~mega_sat.pddl.update_costs.UpdateCostError`.

    ``options``: every tuning knob (:class:`mega_sat.options.Options`, e.g.
    ``Options(quick_nodes=20_000)``); they change how fast an answer comes, never which.
    """

    def __init__(
        self,
        task: TwoModelTask,
        *,
        engine: str = "sat",
        planner: str | None = None,
        hitting_set: str = "rc2",
        solver: str = "cadical195",
        timeout: float | None = None,
        joint: str | None = None,
        deadline: Deadline | None = None,
        update_costs: Mapping[str, int] | UpdateCosts | None = None,
        options: Options | None = None,
    ):
        if not isinstance(task, TwoModelTask):
            raise UsageError(
                f"MegaSolver needs a TwoModelTask (from load_task, load_task_dir or "
                f"load_task_from_strings), got {type(task).__name__}"
            )
        if engine not in ENGINES:
            raise UsageError(f"unknown engine {engine!r} (choose from {', '.join(ENGINES)})")
        if hitting_set not in ("rc2", "ilp"):
            raise UsageError(f"unknown hitting-set solver {hitting_set!r} (choose rc2 or ilp)")
        deadline, options = checked_run_arguments(planner, solver, options, timeout, deadline)
        from mega_sat.engines.sat_loop import JOINT_METHODS

        if joint is not None and joint not in JOINT_METHODS:
            raise UsageError(
                f"unknown JOINT method {joint!r} (choose from {', '.join(JOINT_METHODS)})"
            )
        self._joint = joint
        self.task = task
        self.update_costs: tuple[int, ...] | None = cost_vector(task, update_costs)
        """The cost of every update of ``task.delta``, or ``None`` without update costs."""
        self.engine = engine
        self._planner = planner
        self.hitting_set = hitting_set
        self.solver = solver
        self.options = options
        self.deadline = deadline
        self.timeout = deadline.seconds
        self.progress = Progress()
        self._frontier: Frontier | None = None

    @property
    def planner(self) -> str:
        """The optimal planner for candidate models (given, or :func:`default_planner`)."""
        if self._planner is None:
            self._planner = default_planner(self.engine, self.family, self.options)
        return self._planner

    @property
    def joint(self) -> str:
        """How the ``sat`` engine answers JOINT (given, or :func:`default_joint`)."""
        if self._joint is None:
            self._joint = default_joint(self.family)
        return self._joint

    @cached_property
    def family(self) -> GroundFamily:
        from mega_sat.ground.grounding import ground

        self.deadline.check()
        fam = ground(self.task, deadline=self.deadline if self.deadline.limited else None)
        self.deadline.check()
        return fam

    @cached_property
    def oracles(self):
        from mega_sat.sat.oracles import SatOracles

        family = self.family
        orc = SatOracles(family, solver=self.solver, options=self.options)
        if self.deadline.limited:
            orc.deadline = self.deadline
        self.deadline.check()
        return orc

    def _oracles_if_needed(self):
        return self.oracles if (self.engine == "sat" or self.planner == "sat") else None

    def frontier(self) -> Frontier:
        """Every Pareto-optimal ``(cost(E), robot cost)`` pair with a witness (computed once;
        cost(E) is |E| without update costs)."""
        if self._frontier is None:
            if self.engine == "sat":
                from mega_sat.engines.sat_loop import sat_frontier

                self._frontier = sat_frontier(
                    self.task,
                    self.family,
                    oracles=self.oracles,
                    planner=self.planner,
                    hitting_set=self.hitting_set,
                    joint=self.joint,
                    deadline=self.deadline,
                    progress=self.progress,
                    update_costs=self.update_costs,
                    options=self.options,
                )
            else:
                from mega_sat.engines.astar import astar_frontier

                self._frontier = astar_frontier(
                    self.task,
                    self.family,
                    planner=self.planner,
                    oracles=self._oracles_if_needed(),
                    deadline=self.deadline,
                    progress=self.progress,
                    update_costs=self.update_costs,
                    options=self.options,
                )
        return self._frontier

    def partial_frontier(self, reason: str) -> Frontier | None:
        """After a run was stopped from outside (:class:`~mega_sat.deadline.TimeLimitReached`,
        :class:`~mega_sat.errors.Interrupted`): the points proven so far as an incomplete
        frontier, ``reason`` saying why it stopped; ``None`` if the robot optimum was not
        known yet (nothing to report)."""
        if self._frontier is not None:
            return self._frontier
        return self.progress.frontier(reason)

    def partial_solution(self, alpha: float, reason: str) -> Solution | None:
        """:meth:`solve`'s answer among the points proven so far (see
        :meth:`partial_frontier`); ``None`` without any point."""
        alpha = _check_alpha(alpha)  # a bad alpha is refused even with nothing to choose from
        fr = self.partial_frontier(reason)
        if fr is None or not fr.points:
            return None
        return choose(fr, alpha)

    def solve(self, alpha: float) -> Solution:
        """MEGA's answer for one alpha.

        ``sat``: the frontier point minimising the objective (ties: lower robot cost, then the
        smaller explanation, :func:`mega_sat.results.choose`).  ``astar``:
        the minimum node of the paper's Algorithm 1 run with this alpha.
        """
        exact = alpha  # a Fraction or Decimal keeps its exact value for the ties of choose
        alpha = _check_alpha(alpha)
        if self.engine == "sat":
            return choose(self.frontier(), exact)
        from mega_sat.engines.astar import astar_solve

        return astar_solve(
            self.task,
            self.family,
            alpha,
            planner=self.planner,
            oracles=self._oracles_if_needed(),
            deadline=self.deadline,
            progress=self.progress,
            update_costs=self.update_costs,
            options=self.options,
        )

    def explain(self, plan: Sequence[PlanStep] | None = None, kind: str = "mce") -> Explanation:
        """MCE (``kind="mce"``) or MME (``kind="mme"``) of ``plan`` (default: a robot-optimal
        plan; with update costs the cheapest).  An MME exists only for a plan optimal in the robot model; another plan is
        refused with a :class:`~mega_sat.errors.UsageError` naming its cost and the optimum."""
        if kind not in EXPLANATION_KINDS:
            raise UsageError(
                f"unknown explanation kind {kind!r} (choose from {', '.join(EXPLANATION_KINDS)})"
            )
        from mega_sat.engines.mce import minimal_explanation
        from mega_sat.engines.mme import minimally_monotonic_explanation

        planner = self.planner
        compute = minimal_explanation if kind == "mce" else minimally_monotonic_explanation
        return compute(
            self.task,
            self.family,
            None if plan is None else as_plan(plan),
            planner=planner,
            hitting_set=self.hitting_set,
            oracles=self.oracles if planner == "sat" else None,
            deadline=self.deadline,
            progress=self.progress,
            update_costs=self.update_costs,
            options=self.options,
        )

    def verify(
        self,
        point: FrontierPoint | Explanation | None = None,
        *,
        explanation: Iterable[str] | None = None,
        plan: Sequence[PlanStep] | None = None,
        producer: str | None = None,
        use_val: bool = True,
    ) -> VerifyReport:
        """Check a pair: a frontier point / MCE / MME, or explanation names plus a plan (with update costs
        the report states cost(E), and checks a point's reported cost).  An
        MME's check also covers every strict superset of ``E`` (when there are at most
        :data:`~mega_sat.engines.verify.SUPERSET_CHECK_LIMIT`; otherwise it is listed as skipped)."""
        from mega_sat.engines.verify import check_verify_arguments

        check_verify_arguments(producer, use_val)
        if point is not None:
            if not isinstance(point, FrontierPoint | Explanation):
                raise UsageError(
                    "verify takes a FrontierPoint or an Explanation (or explanation= and "
                    f"plan=), got {type(point).__name__}"
                )
            if explanation is not None or plan is not None:
                raise UsageError(
                    "verify takes a point or explanation= and plan=, not both (the point "
                    "carries its own explanation and plan)"
                )
            from mega_sat.engines.verify import point_selection

            sel, plan = point_selection(self.task, point), point.plan
            rc, hc = point.robot_cost, point.human_cost
            reported = point.weighted_cost
        else:
            if plan is None:
                raise UsageError("verify needs a plan")
            plan = as_plan(plan)
            sel = self.task.selection_from_names(explanation or [])
            rc = hc = reported = None
        prod = producer or self.planner
        from mega_sat.engines.verify import checker_for

        reuse = self.oracles if checker_for(prod, self.family) == "sat" else None
        report = verify_pair(
            self.task,
            self.family,
            sel,
            plan,
            producer=prod,
            robot_cost=rc,
            human_cost=hc,
            use_val=use_val,
            oracles=reuse,
            deadline=self.deadline,
            update_costs=self.update_costs,
            explanation_cost=reported,
            options=self.options,
        )
        if isinstance(point, Explanation) and point.kind == "mme":
            from dataclasses import replace

            from mega_sat.engines.verify import verify_supersets

            extra = verify_supersets(
                self.task,
                self.family,
                sel,
                plan,
                checker=checker_for(prod, self.family),
                oracles=reuse,
                deadline=self.deadline,
                options=self.options,
            )
            if isinstance(extra, str):
                return replace(report, skipped=(*report.skipped, extra))
            return replace(report, checks=(*report.checks, extra))
        return report


def _solver_for(task, **kw):
    """:class:`MegaSolver`, or for several human models (a :class:`MultiHumanTask`) the
    :class:`~mega_sat.engines.multi_human.MultiHumanSolver`."""
    if isinstance(task, MultiHumanTask):
        from mega_sat.engines.multi_human import MultiHumanSolver

        return MultiHumanSolver(task, **kw)
    return MegaSolver(task, **kw)


def frontier(task: TwoModelTask | MultiHumanTask, *, engine: str = "sat", **kw) -> Frontier:
    """The MEGA frontier of ``task`` (paper property 4: answers every alpha)."""
    return _solver_for(task, engine=engine, **kw).frontier()


def solve(
    task: TwoModelTask | MultiHumanTask, alpha: float, *, engine: str = "sat", **kw
) -> Solution:
    """MEGA's plan and explanation for one ``alpha``."""
    return _solver_for(task, engine=engine, **kw).solve(alpha)


def explain(
    task: TwoModelTask, plan: Sequence[PlanStep] | None = None, *, kind: str = "mce", **kw
) -> Explanation:
    """The MCE (or, with ``kind="mme"``, the MME) of ``plan`` (default: a robot-optimal
    plan)."""
    return MegaSolver(task, **kw).explain(plan, kind=kind)


def verify(
    task: TwoModelTask | MultiHumanTask, point: FrontierPoint | Explanation | None = None, **kw
) -> VerifyReport:
    """Independent check of an answer (see :mod:`mega_sat.engines.verify`); the solver's
    arguments (``timeout``, ``deadline``, ``planner``, ...) go to the solver, the rest to
    :meth:`MegaSolver.verify`."""
    solver_args = (
        "engine", "planner", "update_costs", "options", "timeout", "deadline", "solver",
        "hitting_set", "joint",
    )  # fmt: skip
    solver_kw = {k: kw.pop(k) for k in solver_args if k in kw}
    return _solver_for(task, **solver_kw).verify(point, **kw)
