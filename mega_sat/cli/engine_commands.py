"""Commands that run an engine: ``solve``, ``frontier``, ``explain``, ``verify``."""

from __future__ import annotations

import json
import time

import click

from mega_sat.cli.app import (
    ENGINE,
    HITTING,
    PLANNER,
    _command,
    _options,
    _task_from,
    _verbose_family,
    main,
    options_option,
    quiet_option,
    task_options,
)
from mega_sat.cli.model_commands import _ground_member, _read_explanation
from mega_sat.deadline import TimeLimitReached
from mega_sat.errors import (
    EXIT_FAILED,
    EXIT_OK,
    EXIT_TIMEOUT,
    EXIT_TOOL,
    Interrupted,
    PlannerError,
    UsageError,
)


def update_costs_option(fn):
    """``--update-costs FILE``: a cost per update, so that cost(E) replaces |E|."""
    return click.option(
        "--update-costs",
        "update_costs",
        type=click.Path(),
        default=None,
        metavar="FILE",
        help="Lines 'UPDATE COST' (a positive integer; unlisted updates cost 1): the "
        "explanation cost becomes the sum of the costs instead of |E|.",
    )(fn)


def _read_update_costs(path):
    """The ``--update-costs`` file, read and parsed (names are checked against the task by
    :func:`mega_sat.pddl.update_costs.cost_vector`); ``None`` without the option."""
    if path is None:
        return None
    from mega_sat.pddl.update_costs import load_update_costs

    return load_update_costs(path)


def engine_options(fn):
    opts = [
        click.option("--engine", type=ENGINE, default="sat", show_default=True),
        click.option(
            "--planner",
            type=PLANNER,
            default=None,
            help="Optimal planner for candidate models: per-node planner of astar, "
            "OPT oracle of sat; portfolio = builtin racing sat, the first to decide "
            "answers.  [default: builtin for astar; portfolio for the sat engine, "
            "builtin if some action costs 0, fd from fd_from_actions ground actions]",
        ),
        click.option(
            "--joint",
            type=click.Choice(["portfolio", "sat", "search"]),
            default=None,
            help="How the sat engine answers JOINT: SAT with a conflict budget then "
            "explicit search, SAT (search past joint_sat_conflicts or "
            "joint_sat_action_steps), or search only (all exact).  [default: sat; "
            "portfolio if some action costs 0]",
        ),
        click.option("--hitting-set", type=HITTING, default="rc2", show_default=True),
        update_costs_option,
        options_option,
        click.option("--json", "as_json", is_flag=True, help="Print one JSON object."),
        click.option(
            "--verify", "do_verify", is_flag=True, help="Check every returned pair independently."
        ),
        click.option(
            "--write-model",
            type=click.Path(),
            default=None,
            help="Write human + E (domain, problem) and the plan of every pair.",
        ),
        click.option(
            "--force", is_flag=True, help="Replace an existing --write-model folder as a whole."
        ),
        quiet_option,
    ]
    for o in reversed(opts):
        fn = o(fn)
    return fn


def _output_folder(target, force):
    """``--write-model``'s folder, checked now so that an existing target is refused before
    any solving (None without the option)."""
    from mega_sat.output import OutputFolder

    return None if target is None else OutputFolder(target, force=force)


def _solver(kw, run, write_model=None):
    """The task and the engine options of ``solve`` / ``frontier`` as one MegaSolver (a
    :class:`~mega_sat.engines.multi_human.MultiHumanSolver` for several human models)."""
    from mega_sat.api import MegaSolver
    from mega_sat.model.task import TwoModelTask

    engine_kw = {k: kw.pop(k) for k in ("engine", "planner", "joint", "hitting_set")}
    costs = _read_update_costs(kw.pop("update_costs"))
    options = _options(kw)
    task = _task_from(kw, several=True)
    if not isinstance(task, TwoModelTask):  # several human models: their own engine
        from mega_sat.engines.multi_human import MultiHumanSolver

        if write_model is not None:
            raise UsageError("--write-model takes one human model")
        s = MultiHumanSolver(
            task, deadline=run.deadline, update_costs=costs, options=options, **engine_kw
        )
    else:
        s = MegaSolver(
            task, deadline=run.deadline, update_costs=costs, options=options, **engine_kw
        )
    run.watch(s.progress)
    return s


def _point_text(p, c_robot, alpha=None, objective=None) -> list[str]:
    from mega_sat.model.lifted import step_str

    costs = getattr(p, "human_costs", None)  # several human models: one cost each
    human = f"human cost {p.human_cost}" if not costs else f"human costs {costs}"
    lines = [
        f"Plan ({len(p.plan)} steps, robot cost {p.robot_cost}, "
        f"{human}, explicability cost {p.robot_cost - c_robot}):"
    ]
    lines += [f"  {step_str(s)}" for s in p.plan]
    if p.explanation:
        lines += [f"Explanation >> {e}" for e in p.explanation]
    else:
        lines.append("Explanation >> (none: the plan is already optimal for the human)")
    if objective is not None:
        cost = "" if p.weighted_cost is None else f"cost(E) = {p.weighted_cost}, "
        lines.append(
            f"{cost}|E| = {p.size}, objective = {p.explanation_cost} + {alpha:g} * "
            f"{p.robot_cost - c_robot} = {objective:g}"
        )
    return lines


def _write_models(solver, points, out):
    """Write human + E, the plan and the explanation of every point into ``out`` (an
    :class:`~mega_sat.output.OutputFolder` checked before solving): all of it or nothing."""
    from mega_sat.output import write_file
    from mega_sat.pddl.planio import format_plan
    from mega_sat.pddl.writer import write_model

    written = []
    with out:
        for k, p in enumerate(points):
            name = f"point-{k}-E{p.size}"
            d = out.path / name
            m = solver.task.updated_model(p.selection)
            write_model(m, d, domain_file="human-domain.pddl", problem_file="human-problem.pddl")
            # the footer is the plan's cost in the model beside it (human + E), as VAL on
            # these files reports it; its cost for the robot is a comment above it
            plan_text = format_plan(p.plan, p.human_cost)
            write_file(d / "plan.ipc", f"; robot cost = {p.robot_cost}\n" + plan_text)
            write_file(d / "explanation.txt", "".join(e + "\n" for e in p.explanation))
            written += [
                out.target / name / f
                for f in ("human-domain.pddl", "human-problem.pddl", "plan.ipc", "explanation.txt")
            ]
        out.commit()
    return written


def _check_and_write(run, solver, points, do_verify, write_model, force):
    """``--verify`` and ``--write-model`` for the returned pairs: ``(reports, notes)``.

    After a stop nothing more is computed or written (a note says so); a stop during the
    checks keeps the reports made so far and makes the run's answer incomplete.
    """
    notes: list[str] = []
    reports = []
    if run.stopped is not None:
        skipped = [o for o, on in (("--verify", do_verify), ("--write-model", write_model)) if on]
        if skipped:
            notes.append(f"{' and '.join(skipped)} skipped: the run was stopped")
        return reports, notes
    if do_verify:
        try:
            for p in points:
                reports.append(solver.verify(p))
        except (TimeLimitReached, Interrupted) as stop:
            run.quiet()
            run.stopped = stop
            said = getattr(stop, "headline", stop)  # the count below says what was checked
            notes.append(
                f"{said} during --verify: {len(reports)} of {len(points)} point(s) checked"
                + ("; --write-model skipped" if write_model else "")
            )
            return reports, notes
        except PlannerError as e:
            notes.append(_tool_failed(run, e, f"{len(reports)} of {len(points)} point(s) checked"))
    if write_model and not points:
        # no point to write (a time limit before the first one ends the run with 124 before
        # this; an interrupt there leaves the empty frontier): an empty folder would replace
        # the target (with --force) and say nothing
        click.echo("; --write-model: no frontier point to write, nothing written", err=True)
    elif write_model:
        for path in _write_models(solver, points, write_model):
            click.echo(f"; wrote {path}", err=True)
    return reports, notes


def _plot(run, fr, target, force, title) -> list[str]:
    """``frontier --plot``: the figure of the frontier, or a note why it was not drawn (after a
    stop nothing more is computed or written, as for ``--write-model``)."""
    if target is None:
        return []
    if run.stopped is not None:
        return ["--plot skipped: the run was stopped"]
    try:
        from mega_sat.cli.plotting import write_plot

        click.echo(f"; wrote {write_plot(fr, target, force=force, title=title)}", err=True)
    except (TimeLimitReached, Interrupted) as stop:
        # drawing (matplotlib's import alone takes a second) ran past the limit: the frontier
        # found is still the answer, printed without the figure
        run.quiet()
        run.stopped = stop
        return [f"{stop} while drawing: --plot not written"]
    return []


def _tool_failed(run, e: PlannerError, checked: str) -> str:
    """The note of a ``--verify`` whose planner or VAL failed (it could not read what it was
    given, it crashed): the answer is proven without it and is printed, the exit code is the
    tool's (4)."""
    run.tool_failed = e
    return f"--verify could not finish: {e} ({checked})"


def _with_notes(d: dict, notes: list[str]) -> dict:
    """A result's JSON object with the run's own notes (a stop after the answer was found):
    ``complete`` false, ``exact`` as proven (the answer itself is finished)."""
    if notes:
        d["complete"] = False
        d["notes"] = [*d.get("notes", []), *notes]
    return d


def _finish(run, fr, reports, verbose) -> int:
    """Stats on stderr with ``-v``; the exit code (1 when a verification failed)."""
    if verbose:
        click.echo(f"; stats {json.dumps(fr.stats)}", err=True)
    if reports and not all(r.ok for r in reports):
        return run.exit_code(EXIT_FAILED)
    return run.exit_code(EXIT_TOOL if run.tool_failed else EXIT_OK)


def _status_line(fr) -> str:
    if fr.exact:
        return "exact: yes (minimal explanations and optimal costs proven)"
    return "exact: no (" + "; ".join(fr.notes) + ")"


def _incomplete_lines(run, notes) -> None:
    """The run's own notes (a stop after the answer was found) in text: the answer stays as
    proven, what was requested on top of it is not finished."""
    for note in notes:
        run.echo(f"incomplete: {note}")


def _no_point_in_time(run, fr) -> int:
    """Exit 124 for a frontier the time limit stopped after the robot optimum but before its
    first point: there is no answer to print, and an empty frontier with exit 0 reads as
    success.  The error line says what was proven (the robot optimum, a lower bound on the
    explanation cost); with ``--json`` the timeout object carries the frontier object's keys
    too, its ``frontier`` empty."""
    from mega_sat.results import needs

    run.quiet()  # from here on the run reports: no backstop in the middle of it
    proven = [f"robot optimal cost {fr.robot_optimal_cost}"]
    bound = fr.next_cost_lower_bound
    if bound:  # a bound of 0 holds for every solution: it proves nothing
        proven.append(needs(bound, fr.update_costs is not None))
    message = (
        f"{run.deadline.describe()} reached before the first frontier point was found "
        f"({'; '.join(proven)})"
    )
    return run.fail(EXIT_TIMEOUT, message, "timeout", extra=fr.to_dict())


def _stop_message(run) -> None:
    if isinstance(run.stopped, Interrupted):
        click.echo(f"{run.stopped}: the answer printed is what was proven so far", err=True)


@main.command()
@task_options
@click.option(
    "--alpha",
    type=str,
    required=True,
    help="Weight of the robot's extra cost against explanation length (>= 0).",
)
@engine_options
@_command
def solve(run, alpha, as_json, do_verify, write_model, force, verbose, **kw):
    """MEGA: the plan and explanation for one alpha."""
    from mega_sat.api import _check_alpha

    a = _check_alpha(alpha)  # the text as typed, so the error shows it unchanged
    write_model = _output_folder(write_model, force)
    s = _solver(kw, run, write_model)
    t0 = time.perf_counter()

    def work():
        _verbose_family(s, verbose)
        return s.solve(a)

    try:
        sol = run.compute(work, lambda reason: s.partial_solution(a, reason))
    except TimeLimitReached as stop:
        fr = s.partial_frontier(run.reason(stop))
        if fr is None or fr.points:  # stopped before the robot optimum: nothing proven
            raise
        return _no_point_in_time(run, fr)
    elapsed = time.perf_counter() - t0
    reports, notes = _check_and_write(run, s, [sol.chosen], do_verify, write_model, force)
    fr = sol.frontier
    if as_json:
        d = sol.to_dict()
        d["time_s"] = round(elapsed, 6)
        if do_verify and reports:
            d["verify"] = [r.to_dict() for r in reports]
        run.echo_json(_with_notes(d, notes))
    else:
        for line in _point_text(sol.chosen, fr.robot_optimal_cost, a, sol.objective):
            run.echo(line)
        run.echo(
            f"robot optimal cost {fr.robot_optimal_cost}; |Delta| = "
            f"{len(fr.model_difference)}; engine {fr.engine}; time {elapsed:.3f}s"
        )
        run.echo(_status_line(fr))
        _incomplete_lines(run, notes)
        for rep in reports:
            run.echo("verify: " + ("passed" if rep.ok else "FAILED"))
            for line in rep.lines():
                run.echo("  " + line)
    _stop_message(run)
    return _finish(run, fr, reports, verbose)


@main.command()
@task_options
@engine_options
@click.option(
    "--plot",
    type=click.Path(),
    default=None,
    metavar="FILE",
    help="Draw the frontier (robot cost against |E|, the alphas of each point) as PNG, SVG "
    "or PDF by FILE's suffix; needs matplotlib; an existing FILE only with --force.",
)
@_command
def frontier(run, as_json, do_verify, write_model, force, verbose, plot=None, **kw):
    """All Pareto-optimal (|E|, robot cost) pairs: one run answers every alpha."""
    write_model = _output_folder(write_model, force)
    plot_target = None
    if plot is not None:
        from mega_sat.cli.plotting import check_plot_target

        plot_target = check_plot_target(plot, force=force)  # before solving, not after
    title = str(kw.get("task_dir") or kw.get("robot_problem") or "")
    s = _solver(kw, run, write_model)

    def work():
        _verbose_family(s, verbose)
        return s.frontier()

    fr = run.compute(work, s.partial_frontier)
    if not fr.points and not fr.complete and not isinstance(run.stopped, Interrupted):
        return _no_point_in_time(run, fr)
    reports, notes = _check_and_write(run, s, fr.points, do_verify, write_model, force)
    notes += _plot(run, fr, plot_target, force, title)
    if as_json:
        d = fr.to_dict()
        if do_verify and reports:
            d["verify"] = [r.to_dict() for r in reports]
        run.echo_json(_with_notes(d, notes))
    else:
        run.echo(
            f"robot optimal cost {fr.robot_optimal_cost}; |Delta| = "
            f"{len(fr.model_difference)}; {len(fr.points)} frontier point(s); "
            f"engine {fr.engine}; time {fr.time_s:.3f}s"
        )
        for k, p in enumerate(fr.points):
            cost = "" if p.weighted_cost is None else f"cost(E) = {p.weighted_cost}, "
            run.echo(f"\n[{k}] {cost}|E| = {p.size}, robot cost {p.robot_cost}")
            for line in _point_text(p, fr.robot_optimal_cost):
                run.echo(line)
            if k < len(reports):
                run.echo("verify: " + ("passed" if reports[k].ok else "FAILED"))
            elif do_verify:
                run.echo("verify: not checked")
        run.echo("")
        run.echo(_status_line(fr))
        _incomplete_lines(run, notes)
        if fr.next_size_lower_bound is not None:
            which = "the next (cheaper) point" if fr.points else "any point"
            run.echo(f"lower bound on |E| for {which}: {fr.next_size_lower_bound}")
        elif fr.update_costs is not None and fr.next_cost_lower_bound is not None:
            which = "the next (cheaper) point" if fr.points else "any point"
            run.echo(f"lower bound on cost(E) for {which}: {fr.next_cost_lower_bound}")
    _stop_message(run)
    return _finish(run, fr, reports, verbose)


@main.command()
@task_options
@click.option(
    "--plan",
    "plan_file",
    type=click.Path(),
    default=None,
    help="Plan to explain (default: a robot-optimal plan).",
)
@click.option(
    "--planner",
    type=PLANNER,
    default=None,
    help="Optimal planner for the robot plan and the candidate models.  [default: portfolio, "
    "builtin if some action costs 0, fd from fd_from_actions ground actions]",
)
@click.option("--hitting-set", type=HITTING, default="rc2", show_default=True)
@update_costs_option
@click.option(
    "--mme",
    is_flag=True,
    help="MME instead of MCE (the plan must be robot-optimal).",
)
@click.option("--json", "as_json", is_flag=True)
@click.option("--verify", "do_verify", is_flag=True)
@quiet_option
@options_option
@_command
def explain(
    run, plan_file, planner, hitting_set, update_costs, mme, as_json, do_verify, verbose, **kw
):
    """MCE: the smallest explanation that makes a plan optimal for the human (--mme: MME,
    the smallest that keeps it optimal whatever else the human is told)."""
    from mega_sat.api import MegaSolver
    from mega_sat.model.lifted import step_str
    from mega_sat.pddl.planio import read_plan

    costs = _read_update_costs(update_costs)
    options = _options(kw)
    task = _task_from(kw)
    steps = read_plan(plan_file) if plan_file else None
    if steps is not None:
        from mega_sat.ground.simulate import simulate

        sim = simulate(task.robot, steps)
        if not sim.valid:  # here, where the file is known, rather than in the engine
            raise UsageError(
                f"the plan is not executable in the robot model: {sim.reason}", path=plan_file
            )
    s = MegaSolver(
        task,
        planner=planner,
        hitting_set=hitting_set,
        deadline=run.deadline,
        update_costs=costs,
        options=options,
    )
    run.watch(s.progress)
    _verbose_family(s, verbose)
    ex = s.explain(steps, kind="mme" if mme else "mce")
    rep, notes = None, []
    if do_verify:
        try:
            rep = s.verify(ex, producer=planner)
        except (TimeLimitReached, Interrupted) as stop:
            run.quiet()
            run.stopped = stop
            notes.append(f"{getattr(stop, 'headline', stop)} during --verify: not checked")
        except PlannerError as e:
            notes.append(_tool_failed(run, e, "not checked"))
    if as_json:
        d = ex.to_dict()
        if rep:
            d["verify"] = rep.to_dict()
        run.echo_json(_with_notes(d, notes))
    else:
        run.echo(
            f"Plan ({len(ex.plan)} steps, robot cost {ex.robot_cost}, "
            f"human cost after explanation {ex.human_cost}):"
        )
        for st in ex.plan:
            run.echo(f"  {step_str(st)}")
        for e in ex.explanation:
            run.echo(f"Explanation >> {e}")
        if not ex.explanation:
            run.echo("Explanation >> (none needed)")
        cost = "" if ex.weighted_cost is None else f"cost(E) = {ex.weighted_cost}, "
        run.echo(
            f"{cost}|E| = {len(ex.explanation)}{' (MME)' if mme else ''}; "
            f"time {ex.time_s:.3f}s; "
            + ("exact: yes" if ex.exact else "exact: no (" + "; ".join(ex.notes) + ")")
        )
        _incomplete_lines(run, notes)
        if rep:
            run.echo("verify: " + ("passed" if rep.ok else "FAILED"))
            for line in rep.lines():
                run.echo("  " + line)
    _stop_message(run)
    if rep and not rep.ok:
        return run.exit_code(EXIT_FAILED)
    return run.exit_code(EXIT_TOOL if run.tool_failed else EXIT_OK)


@main.command()
@task_options
@click.option("--explanation", type=click.Path(), required=True)
@click.option("--plan", "plan_file", type=click.Path(), required=True)
@click.option(
    "--checker",
    type=PLANNER,
    default=None,
    help="Planner that re-derives the optimum of human + E (default: fd when "
    "installed, else builtin: not the SAT oracle that answers OPT by default).",
)
@update_costs_option
@click.option("--json", "as_json", is_flag=True)
@options_option
@_command
def verify(run, explanation, plan_file, checker, update_costs, as_json, verbose, **kw):
    """Check a plan + explanation pair from files."""
    from mega_sat.cli.app import timeout_message
    from mega_sat.engines.verify import ChecksCutShort, verify_pair
    from mega_sat.pddl.planio import read_plan
    from mega_sat.pddl.update_costs import cost_vector

    costs = _read_update_costs(update_costs)
    options = _options(kw)
    task = _task_from(kw)
    costs = cost_vector(task, costs)
    sel = _read_explanation(task, explanation)
    steps = read_plan(plan_file)
    member, _, fam = _ground_member(task, sel, run, verbose)
    try:
        rep = verify_pair(
            task,
            fam if member is task else None,
            sel,
            steps,
            producer="sat",
            checker=checker,
            deadline=run.deadline,
            update_costs=costs,
            options=options,
            alone=None if member is task else (member, fam),
        )
    except ChecksCutShort as stop:
        # the checks finished before the limit are part of the answer: in JSON as objects of
        # the complete report, not only inside the error line
        done = {"checks_done": [c.to_dict() for c in stop.checks]}
        return run.fail(EXIT_TIMEOUT, timeout_message(run.deadline, stop), "timeout", done)
    if as_json:
        run.echo_json(rep.to_dict())
    else:
        for line in rep.lines():
            run.echo(line)
        run.echo("verify: " + ("passed" if rep.ok else "FAILED"))
    return EXIT_OK if rep.ok else EXIT_FAILED


# --------------------------------------------------------------------------- generate
