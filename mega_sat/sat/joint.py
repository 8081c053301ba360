"""The JOINT oracle: the cheapest robot plan that also runs in ``human + E`` within both cost
bounds, or a core of selector literals ruling every such plan out (``encodings/joint-and-cores.md``).

The JOINT solver holds the human and the robot copy sharing the action variables.  A plan found
within the bounds is improved by asking for robot cost ``<= rc - 1`` until UNSAT (or a lower
bound is met); an UNSAT answer gives the solver's core, shrunk by :mod:`mega_sat.sat.cores`.
When the horizon that makes the answer a proof is above the cap, the explicit paired-state
search of :mod:`mega_sat.search.joint` answers instead.  A call whose formula would be past
the caller's ``max_action_steps`` (ground actions times horizon) is ``LIMIT`` before any SAT
call, for the caller's own search to answer.
"""

from __future__ import annotations

import time
from collections.abc import Iterable, Sequence
from dataclasses import replace
from functools import cached_property
from typing import TYPE_CHECKING

from mega_sat.analysis.extra_cost import extra_cost_bound, family_relaxation, relaxed_bounds
from mega_sat.ground.family import GroundTask, GuardLit, holds
from mega_sat.ground.simulate import ground_plan_cost
from mega_sat.model.lifted import PlanStep
from mega_sat.sat.cores import CoreShrinker
from mega_sat.sat.encoding import HUMAN, ROBOT
from mega_sat.sat.solving import OracleInterrupted
from mega_sat.sat.stats import bump
from mega_sat.search.answers import JointResult
from mega_sat.search.joint import JointSearcher, search_joint
from mega_sat.search.lowered_cost import extra_cost_exact
from mega_sat.status import Status

if TYPE_CHECKING:
    from mega_sat.sat.oracles import SatOracles


class JointOracle:
    """JOINT on the JOINT solver of ``orc``."""

    def __init__(self, orc: SatOracles):
        self.orc = orc
        self.options = orc.options
        self.stats = orc.stats
        self.cores = CoreShrinker(orc)
        family = orc.family
        # JOINT horizon when zero-cost actions make cost bounds useless for plan length
        self._zero_cost_horizon = min(self.options.horizon_cap, 2 * len(family.atoms) + 1)
        self._robot_lb: int | None = None
        self._searcher: JointSearcher | None = None  # for JOINT past the horizon cap
        self._dominance: dict[frozenset[int], bool] = {}
        # per-copy minimum action costs for the horizon: the robot copy always runs in the
        # robot model; the human copy's must hold for every selection (cores generalize)
        robot = orc.task(family.robot_selection)
        self.c_min_robot = min((a.cost for a in robot.actions), default=orc.c_min)

    # the extra costs are computed at the first JOINT call that needs a horizon: many tasks
    # are answered by a plan the loop already has

    @cached_property
    def extra_robot(self) -> int:
        """Cost the robot's cheapest plan must spend above N * c_min (tightens the horizon)."""
        robot = self.orc.task(self.orc.family.robot_selection)
        return extra_cost_exact(robot, self.c_min_robot, self.options.extra_node_limit)

    @cached_property
    def extra_human(self) -> int:
        """The same for the human copy, valid for every selection."""
        return extra_cost_bound(family_relaxation(self.orc.family), self.orc.c_min)

    def horizon(self, robot_bound: int | None, human_bound: int) -> tuple[int, bool, str]:
        """Steps that every joint plan within the bounds fits in: ``min`` over the copies of
        ``floor((bound - extra) / c_min of that copy)`` (robot copy: the robot model's
        cheapest action; human copy: the family's, valid for every selection), capped."""
        orc = self.orc
        cap = self.options.horizon_cap
        need = []
        if robot_bound is not None and self.c_min_robot > 0:
            need.append((robot_bound - self.extra_robot) // self.c_min_robot)
        if orc.c_min > 0:
            need.append((human_bound - self.extra_human) // orc.c_min)
        if not need:
            bmin = human_bound if robot_bound is None else min(robot_bound, human_bound)
            return orc.horizon(bmin, at_least=self._zero_cost_horizon)
        h = max(min(need), 0)
        if h > cap:
            return cap, False, f"horizon cap {cap} < {h} steps needed for the joint bounds"
        return h, True, ""

    def answer(
        self,
        lits: Iterable[GuardLit],
        robot_bound: int | None,
        human_bound: int,
        *,
        sel: frozenset[int] | None = None,
        hints: Iterable[Sequence[PlanStep]] = (),
        robot_lower_bound: int | None = None,
        plan_lower_bound: int = 0,
        human_optimum: int | None = None,
        conflict_budget: int | None = None,
        max_action_steps: int | None = None,
    ) -> JointResult:
        """JOINT under the selector literals ``lits`` (``sel``: the full selection they assign,
        if they do); see :meth:`mega_sat.sat.oracles.SatOracles.joint`."""
        orc = self.orc
        lits = list(dict.fromkeys(lits))
        if (
            robot_bound is not None
            and human_optimum is not None
            and max(self.robot_lower_bound(), robot_lower_bound or 0) <= robot_bound < human_optimum
            and self.always_dominates
        ):
            return self.cores.by_dominance(lits, robot_bound, conflict_budget)
        t0 = time.perf_counter()
        enc, solving = orc.joint_enc, orc.solving
        solver = solving.joint_solver
        calls = 0
        h, exact, reason = self.horizon(robot_bound, human_bound)
        rlb = max(self.robot_lower_bound(), robot_lower_bound or 0)
        lb = max(rlb, plan_lower_bound)

        def done(status, plan=None, rc=None, hc=None, core=None, sel=None, why="") -> JointResult:
            return JointResult(
                status,
                plan,
                rc,
                hc,
                core,
                sel,
                (exact or bool(why)) and status.decided,
                why or reason or "proven by SAT",
                h,
                calls,
                orc.finish("joint", t0),
            )

        if human_bound < 0 or (robot_bound is not None and robot_bound < 0):
            h = 0
            return done(Status.INFEASIBLE, core=frozenset(), why="negative bound")
        if robot_bound is not None and robot_bound < rlb:
            return done(
                Status.INFEASIBLE,
                core=frozenset(),
                why=f"robot cost bound {robot_bound} < robot lower bound {rlb}",
            )
        if human_bound < rlb:
            core = self.human_dominance_core(lits)
            if core is not None:
                self.stats.joint_by_human_dominance = bump(self.stats.joint_by_human_dominance)
                return done(
                    Status.INFEASIBLE,
                    core=core,
                    why=f"human cost bound {human_bound} < robot lower bound {rlb}, and no "
                    "action costs the human less than the robot",
                )
        if not exact and orc.c_min > 0 and sel is not None:
            if max_action_steps:
                # as past the size limit: the caller's explicit search answers, and hands a
                # long search to Fast Downward on the product task, which this one cannot
                return done(Status.LIMIT, why=f"{reason}: no SAT call")
            return self._by_search(sel, robot_bound, human_bound, reason, t0)
        sel_lits = enc.lits_assumptions(lits)
        robot_task = orc.task(orc.family.robot_selection)
        best = None if sel is None else self._best_hint(hints, sel, robot_bound, human_bound, h)
        action_steps = len(orc.family.actions) * h
        if max_action_steps and action_steps > max_action_steps and (best is None or best[1] > lb):
            # SAT would be needed, on an encoding too big for cheap conflicts: the caller's
            # explicit search answers instead
            why = f"{action_steps} action steps > {max_action_steps}: no SAT call"
            if best is None:
                return done(Status.LIMIT, why=why)
            return done(Status.LIMIT, *best, sel=sel, why=why)
        if best is None:
            base = (
                enc.cost_assumptions(HUMAN, human_bound, h)
                + enc.cost_assumptions(ROBOT, robot_bound, h)
                + orc.goal_assumptions(enc, h)
            )
            calls += 1
            ok = solving.solve(solver, base + sel_lits, budget=conflict_budget)
            if ok is None:
                return done(Status.LIMIT, why=f"conflict budget {conflict_budget} ran out")
            if not ok:
                core, core_calls = self.cores.minimize(base, sel_lits, solver.get_core() or [])
                calls += core_calls
                return done(Status.INFEASIBLE, core=core)
            plan, rc, hc, sel = self._decode(solver.get_model(), h, robot_task)
        else:
            plan, rc, hc = best
            self.stats.joint_hint_used = bump(self.stats.joint_hint_used)
        assert hc <= human_bound and (robot_bound is None or rc <= robot_bound)
        while True:
            if rc <= lb:
                why = (
                    "meets the robot lower bound"
                    if rc <= rlb
                    else "meets the human lower bound (robot costs dominate)"
                )
                return done(Status.PLAN, plan, rc, hc, sel=sel, why=why)
            # robot cost <= rc - 1 also bounds the plan length; the horizon may shrink
            h2 = min(self.horizon(rc - 1, human_bound)[0], h)
            calls += 1
            ok = solving.solve(
                solver,
                enc.cost_assumptions(HUMAN, human_bound, h2)
                + enc.cost_assumptions(ROBOT, rc - 1, h2)
                + orc.goal_assumptions(enc, h2)
                + sel_lits,
                budget=conflict_budget,
            )
            if ok is None:
                why = f"conflict budget {conflict_budget} ran out"
                return done(Status.LIMIT, plan, rc, hc, sel=sel, why=why)
            if not ok:
                return done(Status.PLAN, plan, rc, hc, sel=sel)
            h = h2
            plan, rc, hc, sel = self._decode(solver.get_model(), h, robot_task)
            assert robot_bound is None or rc <= robot_bound

    def _by_search(
        self,
        sel: frozenset[int],
        robot_bound: int | None,
        human_bound: int,
        reason: str,
        t0: float,
    ) -> JointResult:
        """JOINT by the explicit paired-state search (:func:`mega_sat.search.joint.search_joint`,
        cores proven on abstractions) when the horizon that would make SAT exact is above the
        cap: with large costs over a small cheapest one, ``floor(c / c_min)`` steps can be any
        number, while the search's work does not grow with the cost values."""
        orc = self.orc
        orc.solving.check()
        if self._searcher is None:
            self._searcher = JointSearcher(orc.task(orc.family.robot_selection))
        r = search_joint(
            self._searcher,
            orc.family,
            sel,
            robot_bound,
            human_bound,
            deadline=orc.solving.effective(),
            options=self.options,
        )
        if r is None:
            raise OracleInterrupted("deadline reached")  # proves nothing
        self.stats.joint_by_search = bump(self.stats.joint_by_search)
        return replace(r, reason=f"{reason}; {r.reason}", time_s=orc.finish("joint", t0))

    def _decode(self, model, h: int, robot_task: GroundTask):
        orc = self.orc
        enc = orc.joint_enc
        sel = enc.decode_selection(model)
        plan = enc.decode_plan(model, h)
        rc = ground_plan_cost(robot_task, plan)
        hc = ground_plan_cost(orc.task(sel), plan)
        assert rc is not None and hc is not None, "decoded joint plan invalid: encoding bug"
        return plan, rc, hc, sel

    def _best_hint(self, hints, sel, robot_bound, human_bound, h):
        """The hint plan of least robot cost that is a JOINT witness, or ``None``."""
        orc = self.orc
        best = None
        robot_task, task = orc.task(orc.family.robot_selection), orc.task(sel)
        for raw in hints:
            if raw is None:
                continue
            plan = tuple(tuple(str(x).lower() for x in step) for step in raw)
            if len(plan) > h:
                continue  # only possible with an inexact horizon; keep answers within it
            rc = ground_plan_cost(robot_task, plan)
            if rc is None or (robot_bound is not None and rc > robot_bound):
                continue
            hc = ground_plan_cost(task, plan)
            if hc is None or hc > human_bound:
                continue
            if best is None or rc < best[1]:
                best = (plan, rc, hc)
        return best

    # ------------------------------------------------------------ lower bounds
    @cached_property
    def always_dominates(self) -> bool:
        """No action the robot model has costs the robot less than in any model of the family
        (then robot cost >= human cost for every joint plan and every selection)."""
        family = self.orc.family
        robot = family.robot_selection
        for a in family.actions:
            if not holds(a.exists, robot):
                continue
            rc = a.cost_in(robot)
            if any(v > rc for _, v in a.cost):
                return False
        return True

    @cached_property
    def _cheaper_for_human(self) -> tuple[tuple[GuardLit, ...], ...]:
        """The guards of every cost case in which an action of the robot model costs the
        human less than it costs the robot."""
        family = self.orc.family
        robot = family.robot_selection
        out = []
        for a in family.actions:
            if holds(a.exists, robot):
                rc = a.cost_in(robot)
                out.extend(guards for guards, v in a.cost if v < rc)
        return tuple(out)

    def human_dominance_core(self, lits: Sequence[GuardLit]) -> frozenset[GuardLit] | None:
        """Literals of ``lits`` under which no action of the robot model costs the human less
        than the robot, or ``None`` if ``lits`` do not ensure that.

        Under them every joint plan's human cost is at least its robot cost, whatever the
        other updates are: each cost case cheaper for the human is ruled out by one literal
        that contradicts one of its guards."""
        assigned = dict(lits)
        core: set[GuardLit] = set()
        for guards in self._cheaper_for_human:
            if any((i, not v) in core for i, v in guards):
                continue
            for i, v in guards:
                if i in assigned and assigned[i] != v:
                    core.add((i, assigned[i]))
                    break
            else:
                return None  # this case can apply in a model agreeing with lits
        return frozenset(core)

    def robot_dominates(self, sel: frozenset[int]) -> bool:
        """Whether no action usable by a joint plan costs less in the robot model than in
        ``human + sel`` (then robot cost >= human cost for every joint plan)."""
        r = self._dominance.get(sel)
        if r is None:
            orc = self.orc
            robot, task = orc.task(orc.family.robot_selection), orc.task(sel)
            hc = {a.index: a.cost for a in task.actions}
            r = all(a.cost >= hc[a.index] for a in robot.actions if a.index in hc)
            self._dominance[sel] = r
        return r

    def robot_lower_bound(self) -> int:
        """A proven lower bound on any robot plan's cost: the robot optimum when already
        computed exactly, else LM-cut of the robot task (saves JOINT's final UNSAT call)."""
        orc = self.orc
        r = orc.opt_oracle.cached(orc.family.robot_selection)
        if r is not None and r.exact and r.status == Status.OPTIMAL:
            return r.cost
        if self._robot_lb is None:
            b = relaxed_bounds(orc.task(orc.family.robot_selection))
            self._robot_lb = b[1] if b is not None else 0
        return self._robot_lb
