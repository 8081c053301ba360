"""The ``sat`` engine: the whole MEGA frontier by a hitting-set loop over SAT oracles.

Loop (encodings/hitting-set.md), from the explicable end toward the robot-optimal end::

    K = inf; learned = []
    E = cheapest selection satisfying learned          (hitting set: RC2 or CBC)
    JOINT(E, K, U) at the cost U of a known plan pi_U of human + E, if any:
                    -> a core: learned += NOT(E restricted to core ∪ support(pi_U)); next E
    c*, pi* = OPT(E)                                    (optimal human cost of human + E)
    JOINT(E, K, c*) -> a plan pi: new frontier point; stop if robot-optimal; K = cost(pi) - 1
                    -> a core:    learned += NOT(E restricted to core ∪ support(pi*))

``support(pi*)`` is the causal support of :func:`mega_sat.engines.support.causal_support`: only the
updates whose flip could make ``pi*`` fail or cost more.

Each success is the smallest cost(E) (``|E|``, or the sum of the update costs when they are
given) that admits a solution with robot cost <= K, because learned clauses only ever remove
selections that provably have no such solution (argument in ``encodings/hitting-set.md``);
the clauses stay valid as K decreases, so they are kept.
"""

from __future__ import annotations

import time

from mega_sat.analysis.joint_pairs import JointPairs
from mega_sat.analysis.monotone import drop_relaxing, drop_restricting
from mega_sat.deadline import Deadline, TimeLimitReached
from mega_sat.engines.counterexample_loop import (
    HandOver,
    counterexample_frontier,
    use_counterexample_loop,
)
from mega_sat.engines.hitting_set import make_hitting_set
from mega_sat.engines.progress import Progress, lower_bound_note
from mega_sat.engines.support import (
    Ic3Streak,
    causal_support,
    exclusion_clause,
    unsolvable_core,
)
from mega_sat.ground.family import GroundFamily, GuardLit
from mega_sat.ground.simulate import ground_plan_cost
from mega_sat.model.task import TwoModelTask
from mega_sat.options import DEFAULT, Options
from mega_sat.pddl.update_costs import explanation_cost
from mega_sat.planners.tiered_opt import Bounds, NodeBudget, TieredOpt
from mega_sat.results import Frontier, FrontierPoint, pareto_filter
from mega_sat.sat.invariant_core import InvariantCores
from mega_sat.search.answers import JointResult
from mega_sat.search.astar import bounded_search
from mega_sat.search.joint import JointSearcher, search_joint
from mega_sat.status import Status


def default_planner(engine: str, family: GroundFamily, options: Options = DEFAULT) -> str:
    """``builtin`` for ``astar`` (the paper's per-node planner) and for tasks with zero-cost
    actions; ``fd`` for families of at least ``options.fd_from_actions`` ground actions when
    Fast Downward is installed; else ``portfolio``: explicit search and the SAT OPT oracle in
    turns.  Neither side of the race wins everywhere (SAT by an order of magnitude on some
    shipped instances, explicit search by as much on others, bench/README.md), and the race
    costs at most a small factor over the better one, as long as one of them can decide the
    models; on large ground families neither may, where FD's C++ search does."""
    if engine != "sat" or family.min_cost <= 0:
        return "builtin"
    if options.fd_from_actions and len(family.actions) >= options.fd_from_actions:
        from mega_sat.planners.fast_downward import family_cost_problem, fd_available

        if fd_available() and family_cost_problem(family) is None:
            return "fd"
    return "portfolio"


def default_joint(family: GroundFamily) -> str:
    """``sat``, or ``portfolio`` (SAT within a conflict budget, then the explicit search) for
    tasks with zero-cost actions, where bounded horizons prove nothing."""
    return "portfolio" if family.min_cost <= 0 else "sat"


def sat_frontier(
    task: TwoModelTask,
    family: GroundFamily,
    *,
    oracles=None,
    planner: str | None = None,
    hitting_set: str = "rc2",
    solver: str = "cadical195",
    timeout: float | None = None,
    joint: str | None = None,
    joint_conflict_budget: int | None = None,
    deadline: Deadline | None = None,
    progress: Progress | None = None,
    update_costs: tuple[int, ...] | None = None,
    options: Options = DEFAULT,
) -> Frontier:
    """Compute the Pareto frontier of MEGA solutions with the hitting-set loop.

    ``planner`` answers OPT (the optimal cost of a candidate model): ``builtin`` (explicit
    A* with LM-cut, exact by admissibility; falls back to the SAT OPT oracle if it gives up),
    ``sat`` (the SAT OPT oracle, exact by the horizon argument) or ``fd``; ``None``:
    :func:`default_planner`.

    ``joint`` answers JOINT, the check that gives cores: ``sat`` (the SAT oracle alone),
    ``search`` (the explicit product search of :mod:`mega_sat.search.joint`, whose cores are
    proven on abstractions) or ``portfolio`` (the SAT oracle with ``joint_conflict_budget``
    conflicts per call, adaptive when None (see :class:`_Budget`), then the search if it is
    undecided).  All three are exact.  ``None``: :func:`default_joint`.

    OPT goes through :class:`mega_sat.planners.tiered_opt.TieredOpt` (cheap proofs first,
    ``planner`` last).  Unsolvable candidate models are generalised by relaxed, pair and
    may-reachability proofs (:func:`mega_sat.engines.support.unsolvable_core`).
    ``options`` holds every tuning knob (:class:`mega_sat.options.Options`).

    ``oracles``: live SAT oracles of ``family``, which the caller has given the same
    ``deadline``; without them the loop makes its own.

    ``deadline`` (or ``timeout`` seconds from now) makes the loop anytime: at the deadline it
    returns the points proven so far, marked incomplete, with a lower bound on cost(E) of the
    next point; before the robot optimum is known it raises :class:`TimeLimitReached` (nothing
    to report).  ``progress`` receives every proven fact as it is proven, for a caller whose run
    is stopped from outside (an interrupt, the CLI's backstop timer).

    ``update_costs``: a positive integer cost per update of ``task.delta``; the explanation
    cost is then their sum instead of |E| (the hitting set minimises it), and the frontier is
    over (cost(E), robot cost).
    """
    planner = default_planner("sat", family, options) if planner is None else planner
    joint = default_joint(family) if joint is None else joint
    if joint not in JOINT_METHODS:
        from mega_sat.errors import UsageError

        raise UsageError(f"unknown JOINT method {joint!r} (choose from {', '.join(JOINT_METHODS)})")
    from mega_sat.planners.node_planner import NodePlanner, require_robot_plan
    from mega_sat.sat.oracles import OracleInterrupted, SatOracles

    t0 = time.perf_counter()
    if deadline is None:
        deadline = Deadline.after(timeout)
    progress = progress if progress is not None else Progress()
    progress.start("sat", tuple(u.name for u in task.delta), update_costs)
    orc = oracles if oracles is not None else SatOracles(family, solver=solver, options=options)
    earlier_deadline = orc.deadline
    if deadline.limited:
        orc.deadline = deadline  # interrupts a SAT call still running at the deadline
    # every planner call runs within the deadline; one it cuts short raises TimeLimitReached
    opt_planner = NodePlanner(
        task, family, planner, oracles=orc, deadline=deadline, options=options
    )
    tiered = TieredOpt(family, opt_planner, options=options)
    notes = progress.notes
    exact = True
    sat_opt = None  # the SAT OPT oracle, for the models the explicit planners leave undecided

    def opt_of(sel, searched_only: bool = False):
        nonlocal sat_opt
        r = tiered.optimal(sel, searched_only=searched_only)
        if not r.status.decided and planner not in ("sat", "portfolio"):
            if sat_opt is None:
                sat_opt = NodePlanner(
                    task, family, "sat", oracles=orc, deadline=deadline, options=options
                )
            r = sat_opt.optimal(sel)
        return r

    if planner == "fd" and options.fd_first_candidate_ahead:
        # E = {} comes first (or soon): FD can prove its optimum alongside the robot's
        tiered.fd_ahead.append(frozenset())
    try:
        robot = opt_of(family.robot_selection)
        require_robot_plan(task, robot)
    except (OracleInterrupted, TimeLimitReached) as e:
        opt_planner.discard()
        orc.deadline = earlier_deadline
        if isinstance(e, TimeLimitReached) or not deadline.expired():
            raise
        raise TimeLimitReached(deadline.seconds) from None  # nothing proven to report
    except BaseException:
        opt_planner.discard()
        raise
    finally:
        tiered.fd_ahead.clear()
    if not robot.exact:
        exact = False
        notes.append(f"robot optimum not proven: {robot.reason}")
    c_robot = robot.cost
    robot_lb = c_robot if robot.exact else None  # a proven lower bound on any robot plan
    progress.robot_optimal_cost = c_robot

    hs = make_hitting_set(hitting_set, len(task.delta), deadline=deadline, costs=update_costs)

    def cost_of(sel) -> int:
        return explanation_cost(sel, update_costs)

    weighted = update_costs is not None
    opt_cache: dict[frozenset[int], object] = {}
    points: list[FrontierPoint] = []
    bound: int | None = None  # K: robot cost must be <= K (None: unbounded)
    complete = False
    lower_bound = None
    stats = {
        "iterations": 0,
        "opt_calls": 0,
        "joint_calls": 0,
        "learned": 0,
        "learned_literals": 0,
        "unsolvable_models": 0,
        "unsolvable_core_cut_short": 0,
        "joint_searches": 0,
        "joint_before_opt_cores": 0,
        "joint_before_opt_plans": 0,
        "explanation_landmarks": 0,
        "joint_cores_without_plan": 0,
        "invariant_cores": 0,
        "plan_below_robot_by_search": 0,
        "joint_by_fd": 0,
        "loop": "hitting set",
    }
    budget = _Budget(joint_conflict_budget, options)
    _searcher = []
    _by_fd: list = []  # [JointByFd or None], made at the first call that could use it

    def searcher() -> JointSearcher:
        if not _searcher:
            _searcher.append(JointSearcher(family.specialize(family.robot_selection)))
        return _searcher[0]

    def by_fd():
        """Fast Downward on the product task, for the calls the paired-state search would
        answer (None: not installed, switched off, or no proven robot optimum)."""
        if not _by_fd:
            made = None
            if options.joint_fd and robot_lb is not None:
                from mega_sat.planners.fast_downward import family_cost_problem, fd_available
                from mega_sat.planners.joint_fd import JointByFd

                if fd_available() and family_cost_problem(family) is None:
                    made = JointByFd(searcher().robot, robot_lb, family=family, options=options)
            _by_fd.append(made)
        return _by_fd[0]

    def time_out():
        nonlocal lower_bound, complete
        try:
            nxt = hs.minimum()
        except TimeLimitReached as e:  # CBC (--hitting-set ilp) has no time left either
            if e.forced:
                raise
            lower_bound = progress.lower_bound or 0
        else:
            lower_bound = None if nxt is None else cost_of(nxt)
            complete = nxt is None
        if not complete:
            note = lower_bound_note(lower_bound, bool(points), weighted)
            notes.append(
                f"time limit {deadline.seconds}s reached: frontier incomplete"
                + (f"; {note}" if note else "")
            )

    first_joint = options.joint_before_opt and joint != "search"
    joint_seconds = [0.0]  # the last JOINT call's SAT time, for the portfolio's budget

    def joint_of(sel, human_bound, plan, human_lower_bound, cap=None) -> JointResult | None:
        """JOINT(sel, K, human_bound) by the SAT oracle (None for ``--joint search``), with
        ``plan`` (a plan of ``human + sel`` within ``human_bound``) as a hint."""
        if joint == "search":
            return None
        # under --joint sat a call SAT has not settled after joint_sat_conflicts goes to the
        # paired-state search (a long horizon's optimality proof can take SAT minutes); under
        # either SAT method so does one whose encoding would be past joint_sat_action_steps
        # (conflicts are dear on a million clauses, and python-sat's CaDiCaL has no
        # propagation budget to see that)
        own = budget.conflicts if joint == "portfolio" else options.joint_sat_conflicts or None
        steps = options.joint_sat_action_steps
        caps = [c for c in (own, cap) if c is not None]
        t_sat = time.perf_counter()
        res = orc.joint(
            sel,
            bound,
            human_bound,
            hints=(plan,),
            robot_lower_bound=robot_lb,
            human_lower_bound=human_lower_bound,
            conflict_budget=min(caps) if caps else None,
            max_action_steps=steps or None,
        )
        joint_seconds[0] = time.perf_counter() - t_sat
        stats["joint_calls"] += 1
        return res

    most = options.plan_below_robot_max_updates
    small = most > 0 and len(task.delta) <= most  # 0: never, not even without updates
    below_nodes = NodeBudget(options.plan_below_robot_nodes if small else 0)
    # with Fast Downward, an FD call can answer instead (faster on small tasks, bench/README.md)
    below_sat = options.plan_below_robot_conflicts
    if planner == "fd" and not options.plan_below_robot_with_fd:
        below_sat = 0

    def plan_below_robot(sel, known: Bounds) -> Bounds:
        """``known`` with a plan of ``human + sel`` cheaper than the robot optimum, when one
        is found and no action costs this model's human less than the robot: JOINT at its
        cost then rules ``sel`` out without SAT and without OPT (encodings/hitting-set.md).
        A search pruned at the robot optimum tries first (its plan is the optimum, so the
        lower bound is its cost; a search that runs out of states proves the robot optimum
        a lower bound), then one SAT call."""
        budget = below_sat
        if (
            budget <= 0
            or robot_lb is None
            or known.lower >= robot_lb
            or (known.upper is not None and known.upper < robot_lb)
            or orc.joint_oracle.human_dominance_core([(i, i in sel) for i in all_updates]) is None
        ):
            return known
        if below_nodes.nodes > 0:
            status, plan, cost = bounded_search(
                family.specialize(sel), robot_lb - 1, below_nodes.now
            )
            below_nodes.record(status != Status.LIMIT)
            if status == Status.OPTIMAL:  # the model's optimum, proven by A*
                stats["plan_below_robot_by_search"] += 1
                return Bounds(cost, plan, cost)
            if status == Status.INFEASIBLE:  # no plan below the robot optimum
                stats["plan_below_robot_by_search"] += 1
                return Bounds(robot_lb, known.plan, known.upper)
        got = orc.plan_within(
            sel, robot_lb - 1, budget, max_action_steps=options.joint_sat_action_steps or None
        )
        return known if got is None else Bounds(known.lower, got[0], got[1])

    def learn_core(sel, res, plan) -> None:
        """Learn NOT(sel on core ∪ causal support of ``plan``), ``plan`` a plan of
        ``human + sel`` whose cost was JOINT's human bound (encodings/hitting-set.md)."""
        _learn(hs, core_clause(sel, res, plan), stats)

    def core_clause(sel, res, plan) -> tuple[GuardLit, ...]:
        nonlocal exact
        if not res.exact:
            exact = False
            notes.append(f"JOINT not exact (|E|={len(sel)}): {res.reason}")
        if res.core is None:  # a search that records no core: exclude sel alone
            return exclusion_clause(sel, all_updates)
        # "no joint plan within the bounds" survives moves to sub-models, "plan runs within
        # the human bound" moves to super-models: each side drops the other's literals
        on = {i for i, _ in drop_relaxing(res.core, restricting)}
        if pairs is not None and pairs.no_joint_plan(sel, frozenset(on)):
            # no joint plan at any bound where sel's core holds: the plan's support (which
            # only keeps the human bound valid) is not needed
            stats["joint_cores_without_plan"] += 1
            return exclusion_clause(sel, on)
        on |= {i for i, _ in drop_restricting(causal_support(family, sel, plan), restricting)}
        return exclusion_clause(sel, on)

    def joint_alone(sel, opt):
        """JOINT of one model at the horizon of its own optimum, for a model of the
        counterexample loop whose plans may be longer than its formula's: the solution
        ``((plan, robot cost, human cost), None)``, or ``(None, clause)`` with the clause
        that excludes the model."""
        nonlocal exact
        res = orc.joint(
            sel,
            None,
            opt.cost,
            hints=(opt.plan,),
            robot_lower_bound=robot_lb,
            human_lower_bound=opt.cost if opt.exact else None,
        )
        stats["joint_calls"] += 1
        if not res.status.decided:  # a search that gave up proves nothing
            exact = False
            notes.append(f"JOINT undecided (|E|={len(sel)}): {res.reason}")
            return None, exclusion_clause(sel, all_updates)
        if res.plan is None:
            return None, core_clause(sel, res, opt.plan)
        if not res.exact:
            exact = False
            notes.append(f"JOINT not exact (|E|={len(sel)}): {res.reason}")
        return (tuple(res.plan), res.robot_cost, res.human_cost), None

    all_updates = range(len(task.delta))
    restricting = orc.restricting
    progress.stats = stats
    pairs = JointPairs(family) if options.joint_pair_proofs else None
    inv_cores: InvariantCores | None = None  # built at the first IC3 invariant
    ic3_streak = Ic3Streak(options.unsolvable_core_ic3_misses)  # shared by the run's cores

    def unsolvable_clause(sel, opt) -> tuple[GuardLit, ...]:
        """The exclusion of a model OPT found no plan for (or did not decide): no solution
        can use it, nor any model agreeing with it on a core that keeps it unsolvable."""
        nonlocal exact, inv_cores
        on = None
        if opt.status == Status.UNSOLVABLE:
            stats["unsolvable_models"] += 1
            # the core's searches only shrink the exclusion, so they stop at the
            # deadline: a smaller core is not worth running past the time limit
            cubes = orc.take_invariant(sel)
            if cubes is not None:
                # IC3's invariant, checked with the updates free one at a time
                if inv_cores is None:
                    inv_cores = InvariantCores(family)
                on = inv_cores.core(sel, cubes)
                stats["invariant_cores"] += on is not None
            if on is None:
                short: list[int] = []
                on = unsolvable_core(
                    family,
                    sel,
                    state_limit=options.unsolvable_core_states,
                    work_limit=options.unsolvable_core_work,
                    trial_limit=options.unsolvable_core_trial_states,
                    trial_growth=options.unsolvable_core_trial_growth,
                    deadline=deadline,
                    cut_short=short,
                    ic3_queries=options.unsolvable_core_ic3_queries,
                    ic3_streak=ic3_streak,
                )
                stats["unsolvable_core_cut_short"] += sum(short)
        else:
            exact = False
            notes.append(f"OPT undecided for a model with |E|={len(sel)}: {opt.reason}")
        on = all_updates if on is None else on
        if opt.status == Status.UNSOLVABLE:  # "no plan" holds in every sub-model
            on = {i for i, _ in drop_relaxing(((i, i in sel) for i in on), restricting)}
        return exclusion_clause(sel, on)

    landmarks: list[int] = []

    def run_counterexample_loop() -> bool:
        """The frontier by the counterexample loop; False if it hands the task back."""
        nonlocal complete, exact, lower_bound

        def make_point(sel, plan, rc, hc) -> FrontierPoint:
            tiered.remember(tuple(plan))
            return FrontierPoint(tuple(task.names(sel)), sel, tuple(plan), rc, hc, None)

        stats["loop"] = "counterexamples"
        shown = len(progress.points)
        try:
            r = counterexample_frontier(
                orc,
                c_robot=c_robot,
                opt_of=opt_of,
                unsolvable_clause=unsolvable_clause,
                joint_alone=joint_alone,
                landmarks=landmarks,
                pairs=pairs,
                make_point=make_point,
                deadline=deadline,
                progress=progress,
                stats=stats,
                notes=notes,
                solver=solver,
                options=options,
            )
        except HandOver as e:
            # the hitting-set loop starts afresh and reports its own points
            del progress.points[shown:]
            notes.append(f"counterexample loop handed over to the hitting-set loop: {e}")
            stats["loop"] = "hitting set"
            return False
        except (OracleInterrupted, TimeLimitReached) as e:
            if getattr(e, "forced", False):
                raise
            r = None
        if r is None or not r.complete:
            lower_bound = progress.lower_bound or 0
            note = lower_bound_note(lower_bound, bool(progress.points), weighted)
            notes.append(
                f"time limit {deadline.seconds}s reached: frontier incomplete"
                + (f"; {note}" if note else "")
            )
        else:
            complete = True
            exact = exact and r.exact
        points.extend(progress.points[len(points) :])
        return True

    try:
        # updates every solution needs, proven once: each a unit clause.  A robot plan that
        # runs in the human model is a joint plan of E = {}: then there are none to prove.
        if pairs is not None and (
            robot.plan is None or ground_plan_cost(family.specialize(()), robot.plan) is None
        ):
            for i in sorted(pairs.landmarks(deadline)):
                stats["explanation_landmarks"] += 1
                landmarks.append(i)
                _learn(hs, ((i, True),), stats)
        # --hitting-set ilp and --joint search ask for the hitting-set loop's own parts
        by_counterexamples = (
            hitting_set == "rc2"
            and joint != "search"
            and use_counterexample_loop(orc, options, weighted)
        )
        if by_counterexamples:
            by_counterexamples = run_counterexample_loop()
        while not by_counterexamples:
            if deadline.expired():
                time_out()
                break
            try:
                sel = hs.minimum()
            except TimeLimitReached as e:
                if e.forced:
                    raise
                time_out()
                break
            if sel is None:
                complete = True
                break
            if stats["iterations"]:
                opt_planner.discard()  # runs started ahead for a model the loop has passed
            # every selection cheaper than sel is excluded by clauses that hold for any
            # robot-cost bound <= K, so a solution cheaper than the last point costs cost(sel)
            progress.lower_bound = cost_of(sel)
            progress.step(len(sel))
            stats["iterations"] += 1
            try:
                opt = opt_cache.get(sel)
                early = None  # JOINT's answer before OPT, when it needs no OPT
                pending = None  # a joint plan at a known plan's cost; needs c* = that cost
                if opt is None and first_joint:
                    known = tiered.bounds(sel)
                    if not isinstance(known, Bounds):
                        opt = known
                    else:
                        known = plan_below_robot(sel, known)
                        if known.plan is not None:
                            r = joint_of(
                                sel,
                                known.upper,
                                known.plan,
                                known.lower,
                                cap=options.joint_before_opt_conflicts,
                            )
                            if r is not None and joint == "portfolio" and not r.exact:
                                r = None  # no proof: OPT, then the portfolio's search, answer
                            if r is not None and r.status.decided and r.plan is None:
                                # no joint plan within a known plan's cost: no OPT needed
                                stats["joint_before_opt_cores"] += 1
                                learn_core(sel, r, known.plan)
                                continue
                            if r is not None and r.status.decided:
                                if r.human_cost <= known.lower:  # c* proven by LM-cut
                                    stats["joint_before_opt_plans"] += 1
                                    early = r
                                else:
                                    pending = (r, known.upper)
                        if early is None:
                            opt = opt_of(sel, searched_only=True)
                elif opt is None:
                    opt = opt_of(sel)
                if opt is not None and sel not in opt_cache:
                    opt_cache[sel] = opt
                    stats["opt_calls"] += 1
            except (OracleInterrupted, TimeLimitReached) as e:
                if getattr(e, "forced", False):
                    raise  # stopped between any two bytecodes: the caller reports progress
                time_out()
                break
            if opt is not None and opt.status != Status.OPTIMAL:
                # no plan (or none found): no solution can use this model; exclude it
                _learn(hs, unsolvable_clause(sel, opt), stats)
                continue
            if opt is not None and not opt.exact:
                exact = False
                notes.append(f"OPT not proven optimal (|E|={len(sel)}): {opt.reason}")
            if pending is not None and opt.cost == pending[1]:
                # the joint plan's human cost is <= the known plan's, which OPT proved optimal
                stats["joint_before_opt_plans"] += 1
                early = pending[0]
            try:
                res = early
                if res is None:
                    # pi* is a witness if the robot can run it within K; c_robot and (when
                    # costs allow) c* are proven lower bounds that spare the final UNSAT call
                    res = joint_of(sel, opt.cost, opt.plan, opt.cost if opt.exact else None)
                # the portfolio's search also answers when SAT's answer is no proof (zero-cost
                # actions: its horizon does not bound plan length), so nothing unproven is
                # learned or reported
                if (
                    res is None
                    or not res.status.decided
                    or (joint == "portfolio" and not res.exact)
                ):
                    stats["joint_searches"] += 1
                    stats["joint_calls"] += res is None  # else counted with its SAT attempt
                    t_search = time.perf_counter()
                    ts = causal_support(family, sel, opt.plan)
                    keep = frozenset(i for i, _ in ts)
                    fd = by_fd() if opt.exact else None
                    # a search past joint_fd_after_work goes to FD, and back to the search
                    # (without a limit) if FD cannot answer
                    limit = fd.search_nodes if fd is not None else None
                    got = search_joint(
                        searcher(), family, sel, bound, opt.cost, keep=keep, deadline=deadline,
                        node_limit=limit,
                    )  # fmt: skip
                    if got is not None and got.status == Status.LIMIT and fd is not None:
                        # joint plans of human cost c* known so far: pi* if the robot can
                        # run it, and SAT's witness (its human cost is <= c*, so = c*)
                        known = [ground_plan_cost(searcher().robot, opt.plan)]
                        if res is not None and res.plan is not None:
                            known.append(res.robot_cost)
                        known = min((x for x in known if x is not None), default=None)
                        got = fd.joint(
                            sel, bound, opt.cost, known=known, keep=keep, deadline=deadline
                        )
                        stats["joint_by_fd"] += got is not None
                        if got is None:
                            got = search_joint(
                                searcher(), family, sel, bound, opt.cost, keep=keep,
                                deadline=deadline,
                            )  # fmt: skip
                    res = got
                    if res is None:
                        raise OracleInterrupted
                    budget.update(joint_seconds[0], time.perf_counter() - t_search)
            except (OracleInterrupted, TimeLimitReached) as e:
                if getattr(e, "forced", False):
                    raise
                time_out()
                break
            if res.plan is None:
                learn_core(sel, res, opt.plan)
                continue
            if not res.exact:
                exact = False
                notes.append(f"JOINT not exact (|E|={len(sel)}): {res.reason}")
            tiered.remember(tuple(res.plan))
            points.append(
                FrontierPoint(
                    tuple(task.names(sel)),
                    sel,
                    tuple(res.plan),
                    res.robot_cost,
                    res.human_cost,
                    cost_of(sel) if weighted else None,
                )
            )
            progress.points.append(points[-1])
            if res.robot_cost <= c_robot:
                complete = True
                break
            bound = res.robot_cost - 1
    finally:
        opt_planner.discard()
        hs.close()
        if inv_cores is not None:
            inv_cores.close()
        if deadline.limited:
            orc.deadline = earlier_deadline
    pts = pareto_filter(points)
    fd_used = _by_fd[0] if _by_fd else None
    return Frontier(
        engine="sat",
        robot_optimal_cost=c_robot,
        model_difference=tuple(u.name for u in task.delta),
        points=pts,
        exact=exact and complete,
        complete=complete,
        notes=tuple(dict.fromkeys(notes)),
        next_size_lower_bound=None if weighted else lower_bound,
        time_s=time.perf_counter() - t0,
        stats={
            **stats,
            "opt_planner": planner,
            "opt_time_s": round(tiered.time_s, 6),
            "opt_planner_time_s": round(opt_planner.time_s, 6),
            **tiered.stats,
            "hitting_set": hitting_set,
            "joint": joint,
            "joint_conflict_budget_final": budget.conflicts,
            "joint_fd_runs": fd_used.runs if fd_used else 0,
            "joint_fd_time_s": round(fd_used.time_s, 6) if fd_used else 0.0,
            "hitting_set_calls": hs.calls,
            **orc.stats.as_dict(),
        },
        update_costs=update_costs,
        next_cost_lower_bound=lower_bound,
    )


JOINT_METHODS = ("portfolio", "sat", "search")


class _Budget:
    """The portfolio's SAT conflict budget per JOINT call.

    Fixed when given; otherwise it starts at ``options.portfolio_conflicts`` and adapts to the
    task: after a call where SAT ran out and the explicit search answered, the budget halves
    when the search took less time than the wasted SAT attempt and doubles otherwise (within
    ``portfolio_min_conflicts`` to ``portfolio_max_conflicts``).  Either way every answer is
    exact; only which oracle gives it changes.
    """

    def __init__(self, fixed: int | None, options: Options = DEFAULT):
        self.adaptive = fixed is None
        self.conflicts = options.portfolio_conflicts if fixed is None else fixed
        self.low, self.high = options.portfolio_min_conflicts, options.portfolio_max_conflicts

    def update(self, sat_s: float, search_s: float) -> None:
        if not self.adaptive:
            return
        if search_s < sat_s:
            self.conflicts = max(self.low, self.conflicts // 2)
        else:
            self.conflicts = min(self.high, self.conflicts * 2)


def _learn(hs, clause, stats) -> None:
    hs.add(clause)
    stats["learned"] += 1
    stats["learned_literals"] += len(clause)
