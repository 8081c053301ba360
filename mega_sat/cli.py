"""``mega-sat`` command line.

Every command that reads a model family takes the four PDDL files as ``--robot-domain
--robot-problem --human-domain [--human-problem]`` or ``--task DIR`` (see ``docs/cli.md``).
User errors print one ``error: ...`` line on stderr and exit non-zero (2 bad input, 3 an
unsolvable problem, 4 a planner failure); a traceback means a bug in mega-sat.
"""

from __future__ import annotations

import functools
import json
import sys
import time
from pathlib import Path

import click

from mega_sat.errors import MegaSatError, UsageError

ENGINE = click.Choice(["sat", "astar"])
PLANNER = click.Choice(["builtin", "sat", "fd"])
HITTING = click.Choice(["rc2", "ilp"])


def _friendly(fn):
    """Turn MegaSatError into one line + exit code; keep tracebacks for real bugs."""

    @functools.wraps(fn)
    def wrapper(*args, **kwargs):
        try:
            return fn(*args, **kwargs)
        except MegaSatError as e:
            click.echo(str(e), err=True)
            sys.exit(e.exit_code)

    return wrapper


def task_options(fn):
    """The four model files, or ``--task DIR``."""
    opts = [
        click.option(
            "--task",
            "task_dir",
            type=click.Path(),
            default=None,
            help="Folder with robot-problem.pddl [human-problem.pddl]; the domains "
            "are found there or in its parent.",
        ),
        click.option("--robot-domain", type=click.Path(), default=None),
        click.option("--robot-problem", type=click.Path(), default=None),
        click.option("--human-domain", type=click.Path(), default=None),
        click.option(
            "--human-problem",
            type=click.Path(),
            default=None,
            help="Defaults to the robot problem.",
        ),
        click.option("-v", "--verbose", is_flag=True, help="Report grounding sizes and stats."),
    ]
    for o in reversed(opts):
        fn = o(fn)
    return fn


def _load(task_dir, robot_domain, robot_problem, human_domain, human_problem):
    from mega_sat.loading import load_task, resolve_task_dir

    if task_dir:
        if any((robot_domain, robot_problem, human_domain, human_problem)):
            raise UsageError("give either --task DIR or the model files, not both")
        paths = resolve_task_dir(task_dir)
        return load_task(
            paths["robot_domain"],
            paths["robot_problem"],
            paths["human_domain"],
            paths.get("human_problem"),
        )
    missing = [
        n
        for n, v in (
            ("--robot-domain", robot_domain),
            ("--robot-problem", robot_problem),
            ("--human-domain", human_domain),
        )
        if not v
    ]
    if missing:
        raise UsageError(f"missing {', '.join(missing)} (or give --task DIR)")
    return load_task(robot_domain, robot_problem, human_domain, human_problem)


def _task_from(kw):
    return _load(
        kw.pop("task_dir"),
        kw.pop("robot_domain"),
        kw.pop("robot_problem"),
        kw.pop("human_domain"),
        kw.pop("human_problem"),
    )


def _verbose_family(solver, verbose: bool) -> None:
    if verbose:
        t0 = time.perf_counter()
        fam = solver.family
        click.echo(f"; grounded {fam.describe()} in {time.perf_counter() - t0:.3f}s", err=True)


@click.group(context_settings={"help_option_names": ["-h", "--help"]})
@click.version_option(package_name="mega-sat")
def main():
    """mega-sat: exact MEGA (explicability vs. explanations) with SAT and ILP."""
    _show_warnings_as_lines()


def _show_warnings_as_lines() -> None:
    """Print mega-sat's warnings (PDDLWarning) as one ``warning: ...`` line on stderr."""
    import warnings

    from mega_sat.pddl_reader import PDDLWarning

    default = warnings.showwarning

    def show(message, category, filename, lineno, file=None, line=None):
        if issubclass(category, PDDLWarning):
            click.echo(f"warning: {message}", err=True)
        else:
            default(message, category, filename, lineno, file, line)

    warnings.showwarning = show


# --------------------------------------------------------------------------- diff / apply


@main.command()
@task_options
@click.option("--json", "as_json", is_flag=True, help="Print JSON.")
@_friendly
def diff(as_json, verbose, **kw):
    """Print the model difference Delta, one update per line."""
    task = _task_from(kw)
    if as_json:
        click.echo(
            json.dumps(
                {"model_difference": [u.name for u in task.delta], "size": len(task.delta)},
                indent=2,
            )
        )
        return
    for u in task.delta:
        click.echo(u.name)
    if verbose:
        click.echo(f"; |Delta| = {len(task.delta)}", err=True)


def _read_explanation(task, path):
    if path is None:
        return frozenset()
    p = Path(path)
    if not p.is_file():
        raise UsageError("explanation file not found", path=str(path))
    return task.selection_from_names(p.read_text().splitlines(), path=str(path))


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
@_friendly
def apply(explanation, out_dir, force, verbose, **kw):
    """Write the updated human model human + E as PDDL."""
    from mega_sat.pddl_writer import write_model

    task = _task_from(kw)
    sel = _read_explanation(task, explanation)
    d, p = write_model(task.updated_model(sel), out_dir, overwrite=force)
    click.echo(f"wrote {d}\nwrote {p}")


# --------------------------------------------------------------------------- plan / validate


def _single_or_family(domain, problem, kw, model, explanation):
    """A single model from --domain/--problem, or a member of a family."""
    from mega_sat.loading import load_task

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
@click.option("--planner", type=PLANNER, default="builtin", show_default=True)
@click.option("--out", "out", type=click.Path(), default=None, help="Write the plan file.")
@click.option("--force", is_flag=True, help="Overwrite --out.")
@click.option("--json", "as_json", is_flag=True)
@_friendly
def plan(domain, problem, model, explanation, planner, out, force, as_json, verbose, **kw):
    """Optimal plan of one model (IPC plan format)."""
    from mega_sat.errors import PlannerError, UnsolvableError
    from mega_sat.grounding import ground
    from mega_sat.node_planner import NodePlanner
    from mega_sat.planio import format_plan, write_plan

    task, sel = _single_or_family(domain, problem, kw, model, explanation)
    fam = ground(task)
    if verbose:
        click.echo(f"; ground task: {fam.describe()}", err=True)
    r = NodePlanner(task, fam, planner).optimal(sel)
    where = problem or (
        task.sources.get("robot_problem")
        if sel == task.all_updates
        else task.sources.get("human_problem")
    )
    if r.status == "unsolvable":
        raise UnsolvableError("the problem has no plan (proven by " + planner + ")", path=where)
    if r.status != "optimal":
        raise PlannerError(f"no optimal plan found: {r.reason or r.status}", path=where)
    if as_json:
        from mega_sat.family import step_str

        click.echo(
            json.dumps(
                {
                    "plan": [step_str(s) for s in r.plan],
                    "cost": r.cost,
                    "planner": planner,
                    "exact": r.exact,
                    "time_s": round(r.time_s, 6),
                },
                indent=2,
            )
        )
    else:
        click.echo(format_plan(r.plan, r.cost), nl=False)
        if not r.exact:
            click.echo(f"; not proven optimal: {r.reason}")
    if out:
        write_plan(out, r.plan, r.cost, overwrite=force)


@main.command()
@click.option("--plan", "plan_file", type=click.Path(), required=True)
@click.option("--domain", type=click.Path(), default=None)
@click.option("--problem", type=click.Path(), default=None)
@task_options
@click.option("--model", type=click.Choice(["robot", "human"]), default="robot")
@click.option("--explanation", type=click.Path(), default=None)
@click.option("--json", "as_json", is_flag=True)
@_friendly
def validate(plan_file, domain, problem, model, explanation, as_json, verbose, **kw):
    """Simulate a plan file in one model: its cost, or the first failing step."""
    from mega_sat.planio import read_plan
    from mega_sat.simulate import simulate

    task, sel = _single_or_family(domain, problem, kw, model, explanation)
    steps = read_plan(plan_file)
    m = task.robot if sel == task.all_updates else task.updated_model(sel)
    sim = simulate(m, steps)
    if as_json:
        click.echo(
            json.dumps(
                {
                    "valid": sim.valid,
                    "cost": sim.cost,
                    "failed_step": sim.failed_step,
                    "reason": sim.reason,
                },
                indent=2,
            )
        )
    elif sim.valid:
        click.echo(f"valid: {len(steps)} steps, cost {sim.cost}")
    else:
        click.echo(f"invalid: {sim.reason}")
    sys.exit(0 if sim.valid else 1)


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
@click.option("--force", is_flag=True)
@_friendly
def encode(kind, explanation, robot_bound, human_bound, out_dir, force, verbose, **kw):
    """Export the OPT or JOINT formula as DIMACS CNF/WCNF with a variable map."""
    from mega_sat.cnf_export import export
    from mega_sat.grounding import ground

    task = _task_from(kw)
    sel = _read_explanation(task, explanation)
    fam = ground(task)
    out = Path(out_dir)
    if out.exists() and any(out.iterdir()) and not force:
        raise UsageError("output folder is not empty (use --force to overwrite)", path=out_dir)
    for name, v in (("--robot-bound", robot_bound), ("--human-bound", human_bound)):
        if v is not None and v < 0:
            raise UsageError(f"{name} must be >= 0, got {v}")
    try:
        files = export(
            fam,
            sel,
            kind=kind,
            out_dir=out,
            robot_bound=robot_bound,
            human_bound=human_bound,
            update_names=[u.name for u in task.delta],
        )
    except ValueError as e:
        raise UsageError(str(e)) from None
    for name, path in files.items():
        click.echo(f"{name}: {path}")


# --------------------------------------------------------------------------- MEGA


def engine_options(fn):
    opts = [
        click.option("--engine", type=ENGINE, default="sat", show_default=True),
        click.option(
            "--planner",
            type=PLANNER,
            default=None,
            help="Optimal planner for candidate models: per-node planner of astar, "
            "OPT oracle of sat.  [default: builtin for astar; sat for the sat engine, "
            "builtin if some action costs 0]",
        ),
        click.option(
            "--joint",
            type=click.Choice(["portfolio", "sat", "search"]),
            default=None,
            help="How the sat engine answers JOINT: SAT with a conflict budget then "
            "explicit search, SAT only, or search only (all exact).  [default: sat; "
            "portfolio if some action costs 0]",
        ),
        click.option("--hitting-set", type=HITTING, default="rc2", show_default=True),
        click.option(
            "--timeout",
            type=float,
            default=None,
            help="Seconds; the sat engine then returns what it has proven so far.",
        ),
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
        click.option("--force", is_flag=True, help="Overwrite files in --write-model."),
    ]
    for o in reversed(opts):
        fn = o(fn)
    return fn


def _solver(kw):
    """The task and the engine options of ``solve`` / ``frontier`` as one MegaSolver."""
    from mega_sat.api import MegaSolver

    engine_kw = {k: kw.pop(k) for k in ("engine", "planner", "joint", "hitting_set", "timeout")}
    return MegaSolver(_task_from(kw), **engine_kw)


def _point_text(p, c_robot, alpha=None, objective=None) -> list[str]:
    from mega_sat.family import step_str

    lines = [
        f"Plan ({len(p.plan)} steps, robot cost {p.robot_cost}, "
        f"human cost {p.human_cost}, explicability cost {p.robot_cost - c_robot}):"
    ]
    lines += [f"  {step_str(s)}" for s in p.plan]
    if p.explanation:
        lines += [f"Explanation >> {e}" for e in p.explanation]
    else:
        lines.append("Explanation >> (none: the plan is already optimal for the human)")
    if objective is not None:
        lines.append(
            f"|E| = {p.size}, objective = {p.size} + {alpha:g} * "
            f"{p.robot_cost - c_robot} = {objective:g}"
        )
    return lines


def _write_models(solver, points, out_dir, force):
    from mega_sat.pddl_writer import write_model
    from mega_sat.planio import write_plan

    out = Path(out_dir)
    written = []
    for k, p in enumerate(points):
        d = out / f"point-{k}-E{p.size}"
        m = solver.task.updated_model(p.selection)
        written += list(
            write_model(
                m,
                d,
                domain_file="human-domain.pddl",
                problem_file="human-problem.pddl",
                overwrite=force,
            )
        )
        plan_path = d / "plan.ipc"
        write_plan(plan_path, p.plan, p.robot_cost, overwrite=force)
        exp_path = d / "explanation.txt"
        if exp_path.exists() and not force:
            raise UsageError("file exists (use --force to overwrite)", path=str(exp_path))
        exp_path.write_text("".join(e + "\n" for e in p.explanation))
        written += [plan_path, exp_path]
    return written


def _check_and_write(solver, points, do_verify, write_model, force):
    """``--verify`` and ``--write-model`` for the returned pairs; returns the reports."""
    reports = [solver.verify(p) for p in points] if do_verify else []
    if write_model:
        for path in _write_models(solver, points, write_model, force):
            click.echo(f"; wrote {path}", err=True)
    return reports


def _finish(fr, reports, verbose) -> None:
    """Stats on stderr with ``-v``; exit 1 when a verification failed."""
    if verbose:
        click.echo(f"; stats {json.dumps(fr.stats)}", err=True)
    if reports and not all(r.ok for r in reports):
        sys.exit(1)


def _status_line(fr) -> str:
    if fr.exact:
        return "exact: yes (minimal explanations and optimal costs proven)"
    return "exact: no (" + "; ".join(fr.notes) + ")"


@main.command()
@task_options
@click.option(
    "--alpha",
    type=str,
    required=True,
    help="Weight of the robot's extra cost against explanation length (>= 0).",
)
@engine_options
@_friendly
def solve(alpha, as_json, do_verify, write_model, force, verbose, **kw):
    """MEGA: the plan and explanation for one alpha."""
    try:
        a = float(alpha)
    except ValueError:
        raise UsageError(f"--alpha must be a number >= 0, got '{alpha}'") from None
    s = _solver(kw)
    _verbose_family(s, verbose)
    t0 = time.perf_counter()
    sol = s.solve(a)
    elapsed = time.perf_counter() - t0
    reports = _check_and_write(s, [sol.chosen], do_verify, write_model, force)
    fr = sol.frontier
    if as_json:
        d = sol.to_dict()
        d["time_s"] = round(elapsed, 6)
        if do_verify:
            d["verify"] = [r.to_dict() for r in reports]
        click.echo(json.dumps(d, indent=2))
    else:
        for line in _point_text(sol.chosen, fr.robot_optimal_cost, a, sol.objective):
            click.echo(line)
        click.echo(
            f"robot optimal cost {fr.robot_optimal_cost}; |Delta| = "
            f"{len(fr.model_difference)}; engine {fr.engine}; time {elapsed:.3f}s"
        )
        click.echo(_status_line(fr))
        for rep in reports:
            click.echo("verify: " + ("passed" if rep.ok else "FAILED"))
            for line in rep.lines():
                click.echo("  " + line)
    _finish(fr, reports, verbose)


@main.command()
@task_options
@engine_options
@_friendly
def frontier(as_json, do_verify, write_model, force, verbose, **kw):
    """All Pareto-optimal (|E|, robot cost) pairs: one run answers every alpha."""
    s = _solver(kw)
    _verbose_family(s, verbose)
    fr = s.frontier()
    reports = _check_and_write(s, fr.points, do_verify, write_model, force)
    if as_json:
        d = fr.to_dict()
        if do_verify:
            d["verify"] = [r.to_dict() for r in reports]
        click.echo(json.dumps(d, indent=2))
    else:
        click.echo(
            f"robot optimal cost {fr.robot_optimal_cost}; |Delta| = "
            f"{len(fr.model_difference)}; {len(fr.points)} frontier point(s); "
            f"engine {fr.engine}; time {fr.time_s:.3f}s"
        )
        for k, p in enumerate(fr.points):
            click.echo(f"\n[{k}] |E| = {p.size}, robot cost {p.robot_cost}")
            for line in _point_text(p, fr.robot_optimal_cost):
                click.echo(line)
            if reports:
                click.echo("verify: " + ("passed" if reports[k].ok else "FAILED"))
        click.echo("")
        click.echo(_status_line(fr))
        if fr.next_size_lower_bound is not None:
            click.echo(
                f"lower bound on |E| for the next (cheaper) point: {fr.next_size_lower_bound}"
            )
    _finish(fr, reports, verbose)


@main.command()
@task_options
@click.option(
    "--plan",
    "plan_file",
    type=click.Path(),
    default=None,
    help="Plan to explain (default: a robot-optimal plan).",
)
@click.option("--planner", type=PLANNER, default="builtin", show_default=True)
@click.option("--hitting-set", type=HITTING, default="rc2", show_default=True)
@click.option("--timeout", type=float, default=None)
@click.option("--json", "as_json", is_flag=True)
@click.option("--verify", "do_verify", is_flag=True)
@_friendly
def explain(plan_file, planner, hitting_set, timeout, as_json, do_verify, verbose, **kw):
    """MCE: the smallest explanation that makes a plan optimal for the human."""
    from mega_sat.api import MegaSolver
    from mega_sat.family import step_str
    from mega_sat.planio import read_plan

    task = _task_from(kw)
    steps = read_plan(plan_file) if plan_file else None
    s = MegaSolver(task, planner=planner, hitting_set=hitting_set, timeout=timeout)
    _verbose_family(s, verbose)
    ex = s.explain(steps)
    rep = s.verify(ex, producer=planner) if do_verify else None
    if as_json:
        d = ex.to_dict()
        if rep:
            d["verify"] = rep.to_dict()
        click.echo(json.dumps(d, indent=2))
    else:
        click.echo(
            f"Plan ({len(ex.plan)} steps, robot cost {ex.robot_cost}, "
            f"human cost after explanation {ex.human_cost}):"
        )
        for st in ex.plan:
            click.echo(f"  {step_str(st)}")
        for e in ex.explanation:
            click.echo(f"Explanation >> {e}")
        if not ex.explanation:
            click.echo("Explanation >> (none needed)")
        click.echo(
            f"|E| = {len(ex.explanation)}; time {ex.time_s:.3f}s; "
            + ("exact: yes" if ex.exact else "exact: no (" + "; ".join(ex.notes) + ")")
        )
        if rep:
            click.echo("verify: " + ("passed" if rep.ok else "FAILED"))
            for line in rep.lines():
                click.echo("  " + line)
    if rep and not rep.ok:
        sys.exit(1)


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
@click.option("--json", "as_json", is_flag=True)
@_friendly
def verify(explanation, plan_file, checker, as_json, verbose, **kw):
    """Check a plan + explanation pair from files."""
    from mega_sat.grounding import ground
    from mega_sat.planio import read_plan
    from mega_sat.verify import verify_pair

    task = _task_from(kw)
    sel = _read_explanation(task, explanation)
    steps = read_plan(plan_file)
    rep = verify_pair(task, ground(task), sel, steps, producer="sat", checker=checker)
    if as_json:
        click.echo(json.dumps(rep.to_dict(), indent=2))
    else:
        for line in rep.lines():
            click.echo(line)
        click.echo("verify: " + ("passed" if rep.ok else "FAILED"))
    sys.exit(0 if rep.ok else 1)


# --------------------------------------------------------------------------- generate


def _time_budget_option(when: str):
    """``--time-budget`` of the generators (seconds for the whole search over seeded draws)."""
    from mega_sat.generate import DEFAULT_TIME_BUDGET

    return click.option(
        "--time-budget",
        type=click.FloatRange(min=0),
        default=DEFAULT_TIME_BUDGET,
        show_default=True,
        help=f"Seconds to search for a solvable human model {when}.",
    )


@main.command()
@click.option("--robot-domain", type=click.Path(), required=True)
@click.option("--robot-problem", type=click.Path(), required=True)
@click.option("--delta", "k", type=int, required=True, help="Size of the model difference.")
@click.option("--seed", type=int, default=0, show_default=True)
@click.option("--out", "out_dir", type=click.Path(), required=True)
@_time_budget_option("before giving up")
@click.option("--force", is_flag=True)
@_friendly
def generate(robot_domain, robot_problem, k, seed, out_dir, time_budget, force):
    """Derive a human model exactly --delta features away (seeded), as a task folder."""
    from mega_sat.generate import write_instance

    g = write_instance(
        robot_domain, robot_problem, k, seed, out_dir, overwrite=force, time_budget=time_budget
    )
    click.echo(f"wrote {out_dir} (|Delta| = {len(g.updates)}, seed {seed}, {g.attempts} draw(s)):")
    for u in g.updates:
        click.echo(f"  {u.name}")


@main.command("generate-suite")
@click.argument("domains_dir", type=click.Path(), default="domains")
@click.option(
    "--deltas",
    default="2,7,10",
    show_default=True,
    help="Comma-separated sizes of the model difference.",
)
@click.option("--seed", type=int, default=0, show_default=True)
@_time_budget_option("per instance before skipping it")
@click.option("--force", is_flag=True)
@_friendly
def generate_suite(domains_dir, deltas, seed, time_budget, force):
    """Generate DOMAINS_DIR/<name>/delta/<K>/<problem>/ for every shipped problem."""
    from mega_sat.generate import instance_seed, write_instance

    try:
        ks = [int(x) for x in deltas.split(",") if x.strip()]
    except ValueError:
        raise UsageError(f"--deltas must be comma-separated integers, got '{deltas}'") from None
    root = Path(domains_dir)
    doms = sorted(d for d in root.iterdir() if (d / "robot-domain.pddl").is_file())
    if not doms:
        raise UsageError("no domain folders with robot-domain.pddl", path=domains_dir)
    failed = []
    for d in doms:
        for prob in sorted(p for p in d.iterdir() if (p / "robot-problem.pddl").is_file()):
            for k in ks:
                s = instance_seed(seed, d.name, prob.name, k)
                out = d / "delta" / str(k) / prob.name
                try:
                    g = write_instance(
                        d / "robot-domain.pddl",
                        prob / "robot-problem.pddl",
                        k,
                        s,
                        out,
                        overwrite=force,
                        time_budget=time_budget,
                    )
                except MegaSatError as e:
                    failed.append(out)
                    click.echo(f"{out}: skipped: {e.message}", err=True)
                    continue
                click.echo(f"{out}: |Delta| = {len(g.updates)}")
    if failed:
        click.echo(f"{len(failed)} instance(s) not generated", err=True)
        sys.exit(1)


def _register_bench() -> None:
    from mega_sat.benchmark import bench_command

    main.add_command(bench_command, "bench")


_register_bench()


def _register_bench_calls() -> None:
    from mega_sat.oracle_bench import bench_calls_command

    main.add_command(bench_calls_command, "bench-calls")


_register_bench_calls()

if __name__ == "__main__":  # pragma: no cover
    main()
