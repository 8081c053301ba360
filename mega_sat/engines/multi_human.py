"""MEGA with several human models: one plan that is optimal for every human model at once.

A solution is ``(E, pi)`` with ``E`` a subset of the union ``Delta`` of the model differences
(:mod:`mega_sat.pddl.multi_task`), ``pi`` valid in the robot model, and ``pi`` optimal in every
``human_i + E``.  The objective, the frontier and its tie-breaking are those of one human
model (the explanation cost is ``|E|``, or cost(E) with update costs).

The engine enumerates the selections of ``Delta`` in order of explanation cost
(:func:`selections_by_cost`) with a robot-cost bound ``K`` (initially none)::

    for E in order:
        c*_i = OPT(human_i + E)                      (each human model's exact optimum)
        pi   = cheapest robot plan with robot cost <= K and cost <= c*_i in every human_i + E
        if pi: new frontier point; stop if robot-optimal; K = cost(pi) - 1

Each success has the least explanation cost among solutions with robot cost ``<= cost(pi)``:
every selection earlier in the order was checked under a bound ``>= K`` and had no plan within
it (argument in ``encodings/several-humans.md``).  OPT is the one-human engine's (cheap proofs
first, then the chosen planner, per human model's own ground family); the joint check is the
explicit product search of :mod:`mega_sat.search.multi`, which needs no horizon.
"""

from __future__ import annotations

import heapq
import time
from collections.abc import Iterable, Iterator, Mapping, Sequence
from dataclasses import dataclass, fields, replace
from functools import cached_property
from typing import Any

from mega_sat.deadline import Deadline, TimeLimitReached
from mega_sat.engines.progress import Progress, lower_bound_note
from mega_sat.engines.verify import Check, VerifyReport
from mega_sat.errors import UnsolvableError, UsageError
from mega_sat.ground.family import GroundFamily, PlanStep
from mega_sat.options import DEFAULT, Options
from mega_sat.pddl.multi_task import MultiHumanTask
from mega_sat.pddl.update_costs import UpdateCosts, cost_vector, explanation_cost
from mega_sat.results import Frontier, FrontierPoint, Solution, check_alpha, choose, pareto_filter
from mega_sat.search.multi import MultiJointResult, MultiJointSearcher

ENGINE = "multi-human"
"""The ``engine`` name of results with several human models."""


@dataclass(frozen=True)
class MultiHumanPoint(FrontierPoint):
    """A solution ``(E, pi)`` for several human models; ``human_costs[i]`` is the cost of
    ``pi`` in ``human_i + E`` (its optimum there).  ``human_cost`` repeats the first."""

    human_costs: tuple[int, ...] = ()

    def to_dict(self) -> dict[str, Any]:
        # one list of costs in the place of the one-human key
        return {
            ("human_costs" if k == "human_cost" else k): (
                list(self.human_costs) if k == "human_cost" else v
            )
            for k, v in super().to_dict().items()
        }


@dataclass(frozen=True)
class MultiHumanFrontier(Frontier):
    """A :class:`Frontier` over several human models; ``human_models`` names each (its files
    and its own model difference), in the order of ``human_costs``."""

    human_models: tuple[tuple[tuple[str, Any], ...], ...] = ()

    def to_dict(self) -> dict[str, Any]:
        out: dict[str, Any] = {}
        for k, v in super().to_dict().items():
            out[k] = v
            if k == "model_difference":
                out["human_models"] = [dict(h) for h in self.human_models]
        return out


def human_models_info(task: MultiHumanTask) -> tuple[tuple[tuple[str, Any], ...], ...]:
    """Per human model: its domain and problem files (``None`` when not loaded from files) and
    its own model difference."""
    out = []
    for t in task.tasks:
        out.append(
            (
                ("domain", t.sources.get("human_domain")),
                ("problem", t.sources.get("human_problem")),
                ("model_difference", [u.name for u in t.delta]),
            )
        )
    return tuple(out)


def selections_by_cost(costs: Sequence[int]) -> Iterator[frozenset[int]]:
    """Every subset of ``range(len(costs))`` exactly once, in order of nondecreasing total cost
    (then size); ``costs`` are positive.

    Items are sorted by cost; a subset with largest position ``j`` has two successors, itself
    plus ``j + 1`` and itself with ``j`` replaced by ``j + 1``.  Every non-empty subset has
    exactly one predecessor and no successor is cheaper, so a heap yields them in order."""
    n = len(costs)
    yield frozenset()
    if n == 0:
        return
    order = sorted(range(n), key=lambda i: (costs[i], i))
    heap = [(costs[order[0]], 1, (0,))]
    while heap:
        c, size, pos = heapq.heappop(heap)
        yield frozenset(order[p] for p in pos)
        j = pos[-1]
        if j + 1 < n:
            heapq.heappush(heap, (c + costs[order[j + 1]], size + 1, (*pos, j + 1)))
            heapq.heappush(
                heap, (c - costs[order[j]] + costs[order[j + 1]], size, (*pos[:-1], j + 1))
            )


def _default_planner(family: GroundFamily, options: Options = DEFAULT) -> str:
    """As for one human model (:func:`mega_sat.engines.sat_loop.default_planner`)."""
    from mega_sat.engines.sat_loop import default_planner

    return default_planner("sat", family, options)


def multi_frontier(
    task: MultiHumanTask,
    families: Sequence[GroundFamily],
    *,
    planner: str | None = None,
    solver: str = "cadical195",
    deadline: Deadline | None = None,
    progress: Progress | None = None,
    update_costs: tuple[int, ...] | None = None,
    options: Options = DEFAULT,
) -> MultiHumanFrontier:
    """The Pareto frontier of MEGA solutions for several human models (module docstring).

    ``families[i]`` is the ground family of ``task.tasks[i]``.  ``planner`` answers OPT for
    every human model (``None``: per human model, ``sat``, or ``builtin`` if some action costs
    0).  At ``deadline`` the points proven so far come back, marked incomplete, with a lower
    bound on the explanation cost of the next point; before the robot optimum is known it
    raises :class:`TimeLimitReached`.  ``update_costs``: a positive cost per update of
    ``task.delta``."""
    from mega_sat.ground.simulate import simulate_ground
    from mega_sat.planners.node_planner import NodePlanner
    from mega_sat.planners.tiered_opt import TieredOpt
    from mega_sat.sat.oracles import OracleInterrupted, SatOracles

    t0 = time.perf_counter()
    deadline = deadline if deadline is not None else Deadline()
    progress = progress if progress is not None else Progress()
    weighted = update_costs is not None
    progress.start(ENGINE, tuple(u.name for u in task.delta), update_costs)
    n_humans = len(task.tasks)
    planners = [planner or _default_planner(f, options) for f in families]
    tiers = []
    for t, fam, kind in zip(task.tasks, families, planners, strict=True):
        orc = None
        if kind == "sat":
            orc = SatOracles(fam, solver=solver, options=options)
            if deadline.limited:
                orc.deadline = deadline
        tiers.append(
            TieredOpt(
                fam,
                NodePlanner(t, fam, kind, oracles=orc, deadline=deadline, options=options),
            )
        )
    notes = progress.notes
    exact = True
    stats: dict[str, Any] = {
        "candidates": 0,
        "opt_calls": 0,
        "unsolvable_models": 0,
        "joint_searches": 0,
        "joint_expanded": 0,
        "joint_by_fd": 0,
        "opt_planners": planners,
    }
    progress.stats = stats

    def opt_of(i: int, sel: frozenset[int]):
        r = tiers[i].optimal(sel)
        if not r.status.decided and planners[i] != "sat" and not deadline.expired():
            r = NodePlanner(
                task.tasks[i], families[i], "sat", deadline=deadline, options=options
            ).optimal(sel)
        return r

    try:
        robot = opt_of(0, families[0].robot_selection)
    except OracleInterrupted:
        raise TimeLimitReached(deadline.seconds) from None
    src = task.sources.get("robot_problem", "robot problem")
    if robot.status == "unsolvable":
        raise UnsolvableError("the robot problem has no plan", path=src)
    if robot.status != "optimal":
        raise UnsolvableError(f"no plan found for the robot problem ({robot.reason})", path=src)
    if not robot.exact:
        exact = False
        notes.append(f"robot optimum not proven: {robot.reason}")
    c_robot = robot.cost
    progress.robot_optimal_cost = c_robot

    robot_task = families[0].specialize(families[0].robot_selection)
    searcher = MultiJointSearcher(robot_task)
    # Fast Downward on the product of the robot's and every human's task, when installed
    # (encodings/hitting-set.md, "JOINT by Fast Downward on the product task")
    by_fd = None
    if options.joint_fd and robot.exact:
        from mega_sat.planners.fast_downward import family_cost_problem, fd_available
        from mega_sat.planners.joint_fd import JointByFd

        if fd_available() and all(family_cost_problem(f) is None for f in families):
            by_fd = JointByFd(robot_task, c_robot, options=options)
    opt_cache: dict[tuple[int, frozenset[int]], Any] = {}
    # per projection tuple: the cheapest joint plan found under the bound of its search, or None
    joint_cache: dict[tuple[frozenset[int], ...], Any] = {}
    points: list[MultiHumanPoint] = []
    bound: int | None = None
    complete = False
    lower_bound: int | None = None
    costs = update_costs if weighted else (1,) * len(task.delta)

    def stopped(at_cost: int) -> None:
        nonlocal lower_bound
        lower_bound = at_cost
        note = lower_bound_note(at_cost, bool(points), weighted)
        notes.append(
            f"time limit {deadline.seconds}s reached: frontier incomplete"
            + (f"; {note}" if note else "")
        )

    for sel in selections_by_cost(costs):
        cost_e = explanation_cost(sel, update_costs)
        if deadline.expired():
            stopped(cost_e)
            break
        progress.lower_bound = cost_e
        progress.step(len(sel))
        stats["candidates"] += 1
        proj = tuple(task.project(sel, i) for i in range(n_humans))
        try:
            opts = []
            for i in range(n_humans):
                key = (i, proj[i])
                if key not in opt_cache:
                    opt_cache[key] = opt_of(i, proj[i])
                    stats["opt_calls"] += 1
                    if opt_cache[key].status == "unsolvable":
                        stats["unsolvable_models"] += 1
                opts.append(opt_cache[key])
                if opts[-1].status != "optimal":
                    break  # no plan is optimal in a model without plans
        except (OracleInterrupted, TimeLimitReached) as e:
            if getattr(e, "forced", False):
                raise
            stopped(cost_e)
            break
        if opts[-1].status != "optimal":
            if opts[-1].status != "unsolvable":
                exact = False
                notes.append(
                    f"OPT undecided for {task.human_label(len(opts) - 1)} with |E|={len(sel)}: "
                    f"{opts[-1].reason}"
                )
            continue
        for i, o in enumerate(opts):
            if not o.exact:
                exact = False
                notes.append(
                    f"OPT not proven optimal for {task.human_label(i)} (|E|={len(sel)}): {o.reason}"
                )
        if proj in joint_cache:
            # K only decreases: a cheapest plan under an earlier bound is the answer under
            # this one if it fits, and no plan under an earlier bound means none under this
            res = joint_cache[proj]
            if res is not None and bound is not None and res.robot_cost > bound:
                res = None
        else:
            humans = [families[i].specialize(proj[i]) for i in range(n_humans)]
            stats["joint_searches"] += 1
            optima = [o.cost for o in opts]
            fd = by_fd if all(o.exact for o in opts) else None
            # a search that runs past joint_fd_after_work goes to FD, and back to the search
            # (without a limit) if FD cannot answer
            limit = fd.search_nodes if fd is not None else None
            r = searcher.search(humans, bound, optima, deadline=deadline, node_limit=limit)
            stats["joint_expanded"] += r.expanded
            if r.status == "nodes":
                got = fd.several(humans, bound, optima, deadline=deadline)
                stats["joint_by_fd"] += got is not None
                if got is None:
                    r = searcher.search(humans, bound, optima, deadline=deadline)
                    stats["joint_expanded"] += r.expanded
                elif got is False:
                    r = MultiJointResult("none", None, None, None, 0)
                else:
                    r = MultiJointResult("plan", got[0], got[1], None, 0)
            if r.status == "limit":
                stopped(cost_e)
                break
            res = r if r.status == "plan" else None
            joint_cache[proj] = res
        if res is None:
            continue
        # reported costs come from simulating the plan, never from the search's counters
        sim_r = simulate_ground(robot_task, res.plan)
        sims = [simulate_ground(families[i].specialize(proj[i]), res.plan) for i in range(n_humans)]
        if not sim_r.valid or not all(s.valid for s in sims):
            raise AssertionError("the product search returned a plan that does not run")
        human_costs = tuple(s.cost for s in sims)
        points.append(
            MultiHumanPoint(
                tuple(task.names(sel)),
                sel,
                tuple(res.plan),
                sim_r.cost,
                human_costs[0],
                cost_e if weighted else None,
                human_costs,
            )
        )
        progress.points.append(points[-1])
        if sim_r.cost <= c_robot:
            complete = True
            break
        bound = sim_r.cost - 1
    else:
        complete = True
    return MultiHumanFrontier(
        engine=ENGINE,
        robot_optimal_cost=c_robot,
        model_difference=tuple(u.name for u in task.delta),
        points=pareto_filter(points),
        exact=exact and complete,
        complete=complete,
        notes=tuple(dict.fromkeys(notes)),
        next_size_lower_bound=None if weighted else lower_bound,
        time_s=time.perf_counter() - t0,
        stats={
            **stats,
            "joint_fd_runs": by_fd.runs if by_fd is not None else 0,
            "joint_fd_time_s": round(by_fd.time_s, 6) if by_fd is not None else 0.0,
            **{f"human_{i + 1}_{k}": v for i, t in enumerate(tiers) for k, v in t.stats.items()},
        },
        update_costs=update_costs,
        next_cost_lower_bound=lower_bound,
        human_models=human_models_info(task),
    )


@dataclass(frozen=True)
class MultiFamily:
    """The ground families of the human models (one per human model), for ``-v``."""

    families: tuple[GroundFamily, ...]

    def describe(self) -> str:
        return "; ".join(
            f"human model {i + 1}: {f.describe()}" for i, f in enumerate(self.families)
        )


class MultiHumanSolver:
    """:class:`~mega_sat.api.MegaSolver` for a :class:`MultiHumanTask`: the same methods
    (``frontier``, ``solve``, ``verify``, ``partial_frontier``, ``partial_solution``).

    Only the exact enumeration engine exists for several human models: ``engine="astar"``,
    ``joint`` and ``hitting_set="ilp"`` are refused with a :class:`UsageError`.
    """

    def __init__(
        self,
        task: MultiHumanTask,
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
        if not isinstance(task, MultiHumanTask):
            raise UsageError(f"MultiHumanSolver needs a MultiHumanTask, got {type(task).__name__}")
        if engine != "sat":
            raise UsageError(
                f"engine {engine!r} takes one human model; several human models are solved by "
                "the exact 'sat' engine only"
            )
        if joint is not None:
            raise UsageError("--joint does not apply to several human models (explicit search)")
        if hitting_set != "rc2":
            raise UsageError(
                "--hitting-set does not apply to several human models (explanations are "
                "enumerated in order of cost)"
            )
        from mega_sat.planners.node_planner import checked_run_arguments

        deadline, options = checked_run_arguments(planner, solver, options, timeout, deadline)
        self.task = task
        self.engine = engine
        self._planner = planner
        self.solver = solver
        self.options = options
        self.deadline = deadline
        self.timeout = deadline.seconds
        self.update_costs: tuple[int, ...] | None = cost_vector(task, update_costs)
        self.progress = Progress()
        self._frontier: MultiHumanFrontier | None = None

    @cached_property
    def families(self) -> tuple[GroundFamily, ...]:
        from mega_sat.ground.grounding import ground

        out = []
        for t in self.task.tasks:
            self.deadline.check()
            out.append(ground(t, deadline=self.deadline if self.deadline.limited else None))
        self.deadline.check()
        return tuple(out)

    @property
    def family(self) -> MultiFamily:
        return MultiFamily(self.families)

    def frontier(self) -> MultiHumanFrontier:
        """Every Pareto-optimal ``(cost(E), robot cost)`` pair with a witness."""
        if self._frontier is None:
            self._frontier = multi_frontier(
                self.task,
                self.families,
                planner=self._planner,
                solver=self.solver,
                deadline=self.deadline,
                progress=self.progress,
                update_costs=self.update_costs,
                options=self.options,
            )
        return self._frontier

    def solve(self, alpha: float) -> Solution:
        check_alpha(alpha)  # before the run; choose keeps a Fraction's exact value for ties
        return choose(self.frontier(), alpha)

    def partial_frontier(self, reason: str) -> MultiHumanFrontier | None:
        """The points proven before a stop from outside, as an incomplete frontier."""
        if self._frontier is not None:
            return self._frontier
        fr = self.progress.frontier(reason)
        if fr is None:
            return None
        return MultiHumanFrontier(
            **{f.name: getattr(fr, f.name) for f in fields(Frontier)},
            human_models=human_models_info(self.task),
        )

    def partial_solution(self, alpha: float, reason: str) -> Solution | None:
        alpha = check_alpha(alpha)
        fr = self.partial_frontier(reason)
        if fr is None or not fr.points:
            return None
        return choose(fr, alpha)

    def verify(
        self,
        point: FrontierPoint | None = None,
        *,
        explanation: Iterable[str] | None = None,
        plan: Sequence[PlanStep] | None = None,
        producer: str | None = None,
        use_val: bool = True,
    ) -> VerifyReport:
        """Check a pair in the robot model and in every ``human_i + E`` (see
        :func:`verify_multi`)."""
        from mega_sat.engines.verify import check_verify_arguments
        from mega_sat.pddl.planio import as_plan

        check_verify_arguments(producer, use_val)

        if point is not None:
            if not isinstance(point, FrontierPoint):
                raise UsageError(f"verify takes a FrontierPoint, got {type(point).__name__}")
            if explanation is not None or plan is not None:
                raise UsageError("verify takes a point or explanation= and plan=, not both")
            from mega_sat.engines.verify import point_selection

            sel, steps = point_selection(self.task, point), point.plan
            rc = point.robot_cost
            hcs = getattr(point, "human_costs", None) or None
            reported = point.weighted_cost
        else:
            if plan is None:
                raise UsageError("verify needs a plan")
            steps = as_plan(plan)
            sel = self.task.selection_from_names(explanation or [])
            rc, hcs, reported = None, None, None
        producers = [
            producer or self._planner or _default_planner(f, self.options) for f in self.families
        ]
        return verify_multi(
            self.task,
            self.families,
            sel,
            steps,
            producers=producers,
            robot_cost=rc,
            human_costs=hcs,
            use_val=use_val,
            deadline=self.deadline,
            update_costs=self.update_costs,
            explanation_cost=reported,
        )


def verify_multi(
    task: MultiHumanTask,
    families: Sequence[GroundFamily],
    selection: frozenset[int],
    plan: Sequence[PlanStep],
    *,
    producers: Sequence[str],
    robot_cost: int | None = None,
    human_costs: Sequence[int] | None = None,
    use_val: bool = True,
    deadline: Deadline | None = None,
    update_costs: tuple[int, ...] | None = None,
    explanation_cost: int | None = None,
) -> VerifyReport:
    """The one-human checks (:func:`mega_sat.engines.verify.verify_pair`) for every human model: the
    plan runs in the robot model, and in every ``human_i + E`` at the optimum re-derived by
    another planner than the one that produced it.  The human models' checks are named by
    their number; the robot's are listed once."""
    from mega_sat.engines.verify import verify_pair

    checks: list[Check] = []
    for i, t in enumerate(task.tasks):
        rep = verify_pair(
            t,
            families[i],
            task.project(selection, i),
            plan,
            producer=producers[i],
            robot_cost=robot_cost,
            human_cost=None if human_costs is None else human_costs[i],
            use_val=use_val,
            deadline=deadline,
        )
        for c in rep.checks:
            if "robot" in c.name:
                if i == 0:
                    checks.append(c)
            else:
                checks.append(replace(c, name=f"human model {i + 1}: {c.name}"))
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
