"""JOINT by Fast Downward on the product task: the paired-state search's question, in C++.

The hitting-set loop hands the paired-state search (:mod:`mega_sat.search.joint`) the JOINT
calls SAT cannot settle: zero-cost actions (SAT's horizon then bounds no plan length), a
horizon past the cap, an encoding past the size limit.  When the human bound ``c`` is the
proven optimum of ``human + E`` (the loop's usual call), the question is lexicographic, and a
single-cost optimal planner answers it:

* every plan of ``human + E`` costs at least ``c``, so the joint plans within the human bound
  are the joint plans of human cost exactly ``c``, and JOINT wants the robot-cheapest of them;
* let ``K`` be the robot bound, or the robot cost of a joint plan of human cost ``c`` already
  known (the smaller if both), and ``r`` a proven lower bound on every robot plan (the robot
  optimum).  In the product of the robot task and ``human + E``
  (:func:`~mega_sat.planners.sas.product_sas`) with action cost
  ``M * human cost + robot cost``, ``M = K - r + 1``, a joint plan of human cost ``c`` and
  robot cost ``x <= K`` costs ``M c + x``, while every plan of human cost ``c + 1`` or more
  costs at least ``M (c + 1) + r > M c + K``.  So the product's optimum is ``M c + x*`` with
  ``x*`` JOINT's answer when one exists within ``K``, and above ``M c + K`` when none does.
* with several human models (:mod:`mega_sat.engines.multi_human`) the same holds with the sum
  of their costs and of their optima: every plan's sum is at least the optima's, with
  equality exactly when each human cost is its model's optimum.

"No joint plan" needs a core for the loop to learn from (``encodings/hitting-set.md``).  It is
found by deletion on abstractions (:mod:`mega_sat.analysis.abstraction`), one FD run per
trial: the product of the robot task and the abstraction that fixes the trial's updates has
an optimum above ``M c + K`` only if no model it covers has a joint plan of human cost ``<= c``
and robot cost ``<= K`` (such a plan would be a plan of the abstraction costing at most
``M c + K``).  The test is one-sided, since the abstraction may have cheaper human plans, so a
trial that fails keeps its update: the core is always sound, possibly larger than minimal.
"""

from __future__ import annotations

import time
from collections.abc import Sequence

from mega_sat.analysis.abstraction import abstract_task
from mega_sat.deadline import Deadline
from mega_sat.errors import PlannerError
from mega_sat.ground.family import GroundFamily, GroundTask, PlanStep
from mega_sat.ground.simulate import ground_plan_cost
from mega_sat.options import DEFAULT, Options
from mega_sat.planners.fast_downward import FD_INT_LIMIT, fd_cost_problem, fd_plan
from mega_sat.planners.sas import product_sas
from mega_sat.search.answers import JointResult
from mega_sat.status import Status


class JointByFd:
    """JOINT calls of one task answered by Fast Downward (see the module docstring): the robot
    task and its proven lower bound ``robot_lower_bound`` are fixed for the task; ``family``
    (the robot's and the human's, for cores) is needed by :meth:`joint` only."""

    def __init__(
        self,
        robot: GroundTask,
        robot_lower_bound: int,
        *,
        family: GroundFamily | None = None,
        options: Options = DEFAULT,
    ):
        self.family = family
        self.robot = robot
        self.r_lb = robot_lower_bound
        self.search = "astar(lmcut())" if options.joint_fd_lmcut else "astar(blind())"
        self.core_trials = options.joint_fd_core_trials
        # expansions the paired-state search makes before FD takes a call: the
        # search's heuristic work per expansion grows with the ground actions, while an FD
        # run costs about the same on small tasks (Options.joint_fd_after_work)
        work = options.joint_fd_after_work
        self.search_nodes = 0 if work <= 0 else max(1, work // max(1, len(robot.actions)))
        self.runs = 0
        self.time_s = 0.0

    def joint(
        self,
        selection: frozenset[int],
        robot_bound: int | None,
        human_optimum: int,
        *,
        known: int | None = None,
        keep: frozenset[int] = frozenset(),
        deadline: Deadline,
    ) -> JointResult | None:
        """JOINT(``selection``, ``robot_bound``, ``human_optimum``), ``human_optimum`` being
        the *proven* optimum of ``human + selection``; ``known``: the robot cost of a joint
        plan of that human cost, if one is known.  A core of "no joint plan" contains
        ``keep``.  ``None`` when FD cannot answer (costs that could overflow FD's sums, FD
        failing or out of time): the caller's search answers instead."""
        assert self.family is not None, "cores need the family"
        t0 = time.perf_counter()
        sel = frozenset(selection)
        human = self.family.specialize(sel)
        try:
            got = self._decide([human], robot_bound, [human_optimum], known, deadline)
            if got is None:
                return None
            plan, rc, k, m = got
            if plan is not None:
                return JointResult(
                    Status.PLAN, plan, rc, human_optimum, None, sel, True, _WHY, 0, self.runs,
                    time.perf_counter() - t0,
                )  # fmt: skip
            core = self._core(sel, k, human_optimum, m, frozenset(keep), deadline)
            return JointResult(
                Status.INFEASIBLE, None, None, None, frozenset((i, i in sel) for i in core),
                sel, True, _WHY, 0, self.runs, time.perf_counter() - t0,
            )  # fmt: skip
        finally:
            self.time_s += time.perf_counter() - t0

    def several(
        self,
        humans: Sequence[GroundTask],
        robot_bound: int | None,
        optima: Sequence[int],
        *,
        deadline: Deadline,
    ) -> tuple[tuple[PlanStep, ...], int] | None | bool:
        """One plan for the robot (cost ``<= robot_bound``) and every human task ``i`` at its
        *proven* optimum ``optima[i]``, of least robot cost: ``(plan, robot cost)``, ``False``
        when there is none, ``None`` when FD cannot answer."""
        t0 = time.perf_counter()
        try:
            got = self._decide(list(humans), robot_bound, list(optima), None, deadline)
            if got is None:
                return None
            plan, rc, _, _ = got
            return False if plan is None else (plan, rc)
        finally:
            self.time_s += time.perf_counter() - t0

    def _weight(self, limit: int | None, humans: list[GroundTask]) -> int | None:
        """``M`` for the robot cost limit ``K`` (1 for no limit, where the robot cost gets
        weight 0); ``None`` if FD's sums could overflow."""
        m = 1 if limit is None else limit - self.r_lb + 1
        costs = [a.cost for t in (self.robot, *humans) for a in t.actions]
        cost = (m * len(humans) + 1) * max(costs, default=0)
        if m < 1 or fd_cost_problem(cost, len(self.robot.actions)) is not None:
            return None
        return m

    def _optimum(self, humans: list[GroundTask], m: int, robot_weight: int, deadline: Deadline):
        """FD's optimum of the product of the robot task and ``humans`` under cost ``m * (sum
        of human costs) + robot_weight * robot``: ``(plan, f)``, ``(None, None)`` when it has
        no plan, or ``None`` when FD did not answer."""
        if all(t.goal <= t.init for t in (self.robot, *humans)):
            return (), 0  # the empty plan; some planners refuse such tasks
        sas, names = product_sas([(self.robot, robot_weight), *((h, m) for h in humans)])
        self.runs += 1
        try:
            r = fd_plan(None, None, search=self.search, deadline=deadline, sas_text=sas)
        except PlannerError:
            return None
        if r.status == Status.UNSOLVABLE:
            return None, None
        if r.status != Status.OPTIMAL or r.plan is None or r.cost is None:
            return None
        if r.cost >= FD_INT_LIMIT:
            return None
        return tuple(names[s[0]] for s in r.plan), r.cost

    def _decide(self, humans, robot_bound, optima, known, deadline):
        """``(plan, robot cost, K, M)`` with the robot-cheapest plan at every human optimum
        within ``K``, or ``(None, None, K, M)`` when there is none (``K`` None: at no robot
        cost); ``None`` when FD cannot answer."""
        c = sum(optima)
        k = min((x for x in (robot_bound, known) if x is not None), default=None)
        if k is None:
            # no robot limit yet: the least sum of human costs of any joint plan first (robot
            # weight 0); above the optima there is none, at them its plan gives the limit
            got = self._optimum(humans, 1, 0, deadline)
            if got is None:
                return None
            plan, f = got
            if plan is None or f > c:
                return None, None, None, 1
            k = ground_plan_cost(self.robot, plan)
            assert k is not None, "FD's product plan is no robot plan"
        m = self._weight(k, humans)
        if m is None:
            return None
        got = self._optimum(humans, m, 1, deadline)
        if got is None:
            return None
        plan, f = got
        if plan is None or f > m * c + k:
            return None, None, k, m
        rc = ground_plan_cost(self.robot, plan)
        assert rc is not None and rc <= k, "FD's product plan is no robot plan within K"
        for h, opt in zip(humans, optima, strict=True):
            assert ground_plan_cost(h, plan) == opt, "FD's product plan is not human-optimal"
        return plan, rc, k, m

    def _core(self, sel, k: int | None, c: int, m: int, keep: frozenset[int], deadline):
        """Updates fixing which rules out every joint plan within ``k`` (None: any robot
        cost) and ``c``: deletion over the updates outside ``keep`` (all at once first, then
        one at a time, at most ``joint_fd_core_trials`` FD runs), each trial by the
        abstraction's optimum under the weights the call used."""
        assert self.family is not None
        everything = frozenset(range(self.family.n_updates))
        weight, threshold = (0, m * c) if k is None else (1, m * c + k)

        def ruled_out(fixed: frozenset[int]) -> bool:
            if deadline.expired():
                return False
            human = abstract_task(self.family, sel, fixed)
            got = self._optimum([human], m, weight, deadline)
            return got is not None and (got[0] is None or got[1] > threshold)

        candidates = sorted(everything - keep)
        trials = self.core_trials
        if not candidates or trials <= 0:
            return everything
        trials -= 1
        if ruled_out(keep):
            return keep
        fixed = everything
        for i in candidates:
            if trials <= 0:
                break
            trials -= 1
            if ruled_out(fixed - {i}):
                fixed = fixed - {i}
        return fixed


_WHY = "proven by Fast Downward on the product task"
