"""Commands on models and plans: ``diff``, ``apply``, ``plan``, ``validate``, ``encode``."""

from __future__ import annotations

import time
from pathlib import Path

import click

from mega_sat.cli.app import (
    PLANNER,
    _command,
    _options,
    _task_from,
    main,
    options_option,
    task_options,
)
from mega_sat.errors import (
    EXIT_FAILED,
    EXIT_OK,
    UsageError,
)


@main.command()
@task_options
@click.option("--json", "as_json", is_flag=True, help="Print JSON.")
@_command
def diff(run, as_json, verbose, **kw):
    """Print the model difference Delta, one update per line."""
    task = _task_from(kw)
    run.deadline.check()
    if as_json:
        run.echo_json({"model_difference": [u.name for u in task.delta], "size": len(task.delta)})
        return EXIT_OK
    for u in task.delta:
        run.echo(u.name)
    if verbose:
        _ground(task, run, verbose)
    return EXIT_OK


def _read_explanation(task, path):
    if path is None:
        return frozenset()
    from mega_sat.pddl.reader import read_text

    # read_text names the problem: missing, a folder, not UTF-8 text, unreadable
    return task.selection_from_names(read_text(path, "explanation").splitlines(), path=str(path))


@main.command()
@task_options
@click.option(
    "--explanation",
    "explanation",
    type=click.Path(),
    required=True,
    help="File of add-.../remove-... lines (as printed by diff/solve).",
)
@click.option(
    "--out",
    "out_dir",
    type=click.Path(),
    required=True,
    help="Folder for domain.pddl and problem.pddl of human + E.",
)
@click.option("--force", is_flag=True, help="Overwrite existing files.")
@_command
def apply(run, explanation, out_dir, force, verbose, **kw):
    """Write the updated human model human + E as PDDL."""
    from mega_sat.pddl.writer import write_model

    task = _task_from(kw)
    sel = _read_explanation(task, explanation)
    if verbose:
        _ground(task, run, verbose)
    run.deadline.check()
    model = task.updated_model(sel)
    d, p = write_model(model, out_dir, overwrite=force)
    run.echo(f"wrote {d}\nwrote {p}")
    unwritten = sorted({task.delta[i].feature.action for i in sel} - set(model.schemas))
    unwritten = [a for a in unwritten if a in task.robot.schemas]
    if unwritten:
        # a component of a schema human + E lacks changes no plan, and PDDL has no place for it
        n = sum(1 for i in sel if task.delta[i].feature.action in unwritten)
        click.echo(
            f"; {n} update(s) of the explanation belong to action(s) human + E lacks "
            f"({', '.join(unwritten)}): they change no plan and have no place in PDDL, so "
            "'diff' against the written model lists them again",
            err=True,
        )
    return EXIT_OK


# --------------------------------------------------------------------------- plan / validate


def _single_or_family(domain, problem, kw, model, explanation):
    """A single model from --domain/--problem, or a member of a family."""
    from mega_sat.pddl.loading import load_task

    if domain or problem:
        if not (domain and problem):
            raise UsageError("--domain and --problem go together")
        if any(
            kw.get(k)
            for k in ("task_dir", "robot_domain", "robot_problem", "human_domain", "human_problem")
        ):
            raise UsageError("give either --domain/--problem or a model family, not both")
        task = load_task(domain, problem, domain, problem)
        return task, frozenset()
    task = _task_from(kw)
    if model == "robot":
        if explanation:
            raise UsageError("--explanation applies to the human model, not --model robot")
        return task, task.all_updates
    return task, _read_explanation(task, explanation)


def _ground(task, run, verbose=False):
    """The ground family of ``task``, within the run's time limit; with ``-v`` its sizes on
    stderr (every command reports them, so a user sees what a model grounds to)."""
    from mega_sat.ground.grounding import ground

    run.deadline.check()
    t0 = time.perf_counter()
    fam = ground(task, deadline=run.deadline if run.deadline.limited else None)
    run.deadline.check()
    if verbose:
        click.echo(
            f"; |Delta| = {len(task.delta)}; grounded {fam.describe()} in "
            f"{time.perf_counter() - t0:.3f}s",
            err=True,
        )
    return fam


def _ground_member(task, sel, run, verbose=False):
    """``(task, sel, family)`` for a command about the one model ``sel`` of ``task``: the
    family of every ``human + E`` as usual, or that model grounded alone when the family
    cannot be compiled (then ``sel`` is the new family's one member, ``frozenset()``)."""
    from mega_sat.errors import FamilyNotCompiled
    from mega_sat.ground.grounding import ground_member

    try:
        return task, sel, _ground(task, run, verbose)
    except FamilyNotCompiled:
        run.deadline.check()
        member, fam = ground_member(task, sel)
        if verbose:
            click.echo(
                f"; the model alone (the family cannot be compiled): {fam.describe()}", err=True
            )
        return member, frozenset(), fam


@main.command()
@click.option("--domain", type=click.Path(), default=None)
@click.option("--problem", type=click.Path(), default=None)
@task_options
@click.option(
    "--model",
    type=click.Choice(["robot", "human"]),
    default="robot",
    help="Family member to plan for (with the family options).",
)
@click.option(
    "--explanation",
    type=click.Path(),
    default=None,
    help="Plan for human + E (with --model human).",
)
@click.option(
    "--planner",
    type=PLANNER,
    default=None,
    help="Optimal planner.  [default: portfolio, builtin if some action costs 0, fd from "
    "fd_from_actions ground actions]",
)
@click.option("--out", "out", type=click.Path(), default=None, help="Write the plan file.")
@click.option("--force", is_flag=True, help="Overwrite --out.")
@click.option("--json", "as_json", is_flag=True)
@options_option
@_command
def plan(run, domain, problem, model, explanation, planner, out, force, as_json, verbose, **kw):
    """Optimal plan of one model (IPC plan format)."""
    from mega_sat.errors import PlannerError, UnsolvableError
    from mega_sat.output import check_target
    from mega_sat.pddl.planio import format_plan, write_plan
    from mega_sat.planners.node_planner import NodePlanner

    options = _options(kw)
    if out:
        check_target(out, force=force)  # before planning, not after
    task, sel = _single_or_family(domain, problem, kw, model, explanation)
    where = problem or (
        task.sources.get("robot_problem")
        if sel == task.all_updates
        else task.sources.get("human_problem")
    )
    task, sel, fam = _ground_member(task, sel, run, verbose)
    if planner is None:  # the library's default, as for the frontier's models
        from mega_sat.engines.sat_loop import default_planner

        planner = default_planner("sat", fam, options)
    r = NodePlanner(task, fam, planner, deadline=run.deadline, options=options).optimal(sel)
    if r.status == "unsolvable":
        raise UnsolvableError("the problem has no plan (proven by " + planner + ")", path=where)
    if r.status != "optimal":
        raise PlannerError(f"no optimal plan found: {r.reason or r.status}", path=where)
    if as_json:
        from mega_sat.model.lifted import step_str

        run.echo_json(
            {
                "plan": [step_str(s) for s in r.plan],
                "cost": r.cost,
                "planner": planner,
                "exact": r.exact,
                "time_s": round(r.time_s, 6),
            }
        )
    else:
        run.echo(format_plan(r.plan, r.cost), nl=False)
        if not r.exact:
            run.echo(f"; not proven optimal: {r.reason}")
    if out:
        write_plan(out, r.plan, r.cost, overwrite=force)
    return EXIT_OK


@main.command()
@click.option("--plan", "plan_file", type=click.Path(), required=True)
@click.option("--domain", type=click.Path(), default=None)
@click.option("--problem", type=click.Path(), default=None)
@task_options
@click.option("--model", type=click.Choice(["robot", "human"]), default="robot")
@click.option("--explanation", type=click.Path(), default=None)
@click.option("--json", "as_json", is_flag=True)
@_command
def validate(run, plan_file, domain, problem, model, explanation, as_json, verbose, **kw):
    """Simulate a plan file in one model: its cost, or the first failing step."""
    from mega_sat.ground.simulate import simulate
    from mega_sat.pddl.planio import read_plan

    task, sel = _single_or_family(domain, problem, kw, model, explanation)
    steps = read_plan(plan_file)
    if verbose:
        _ground(task, run, verbose)
    m = task.robot if sel == task.all_updates else task.updated_model(sel)
    run.deadline.check()
    sim = simulate(m, steps)
    if as_json:
        run.echo_json(
            {
                "valid": sim.valid,
                "cost": sim.cost,
                "failed_step": sim.failed_step,
                "reason": sim.reason,
            }
        )
    elif sim.valid:
        run.echo(f"valid: {len(steps)} steps, cost {sim.cost}")
    else:
        run.echo(f"invalid: {sim.reason}")
    return EXIT_OK if sim.valid else EXIT_FAILED


# --------------------------------------------------------------------------- encode


@main.command()
@task_options
@click.option("--kind", type=click.Choice(["opt", "joint"]), default="opt", show_default=True)
@click.option(
    "--explanation",
    type=click.Path(),
    default=None,
    help="Candidate E (default: empty, the human model).",
)
@click.option("--robot-bound", type=int, default=None, help="JOINT: robot cost <= K.")
@click.option(
    "--human-bound",
    type=int,
    default=None,
    help="Cost bound (OPT: human cost <= c; JOINT: human cost <= c).",
)
@click.option("--out", "out_dir", type=click.Path(), required=True)
@click.option("--force", is_flag=True, help="Replace an existing --out folder as a whole.")
@_command
def encode(run, kind, explanation, robot_bound, human_bound, out_dir, force, verbose, **kw):
    """Export the OPT or JOINT formula as DIMACS CNF/WCNF with a variable map."""
    from mega_sat.output import OutputError, OutputFolder
    from mega_sat.sat.cnf_export import export

    out = OutputFolder(out_dir, force=force)  # refused now, not after grounding and solving
    for name, v in (("--robot-bound", robot_bound), ("--human-bound", human_bound)):
        if v is not None and v < 0:
            raise UsageError(f"{name} must be >= 0, got {v}")
    if kind == "opt" and robot_bound is not None:  # refused before grounding, as export does
        raise UsageError("--robot-bound bounds JOINT's robot plan: give it with --kind joint")
    task = _task_from(kw)
    sel = _read_explanation(task, explanation)
    fam = _ground(task, run, verbose)
    with out:
        try:
            files = export(
                fam,
                sel,
                kind=kind,
                out_dir=out.path,
                robot_bound=robot_bound,
                human_bound=human_bound,
                update_names=[u.name for u in task.delta],
            )
        except ValueError as e:
            raise UsageError(str(e)) from None
        except OSError as e:
            raise OutputError(f"cannot write file: {e.strerror or e}", path=out_dir) from None
        out.commit()
    for name, path in files.items():
        run.echo(f"{name}: {out.target / Path(path).name}")
    return EXIT_OK


# --------------------------------------------------------------------------- MEGA
