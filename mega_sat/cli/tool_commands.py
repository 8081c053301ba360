"""Tools around the engines: ``generate``, ``generate-suite``, ``batch``, ``mmp``, ``bench``,
``bench-calls``."""

from __future__ import annotations

import time
from pathlib import Path

import click

from mega_sat.cli.app import (
    ENGINE,
    HITTING,
    PLANNER,
    _command,
    _load,
    _options,
    main,
    options_option,
)
from mega_sat.deadline import parse_timeout
from mega_sat.errors import (
    EXIT_FAILED,
    EXIT_OK,
    EXIT_TOOL,
    MegaSatError,
    UsageError,
)


def _time_budget_option(when: str):
    """``--time-budget`` of the generators (seconds for the whole search over seeded draws)."""
    from mega_sat.bench.generate import DEFAULT_TIME_BUDGET

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
@_command
def generate(run, robot_domain, robot_problem, k, seed, out_dir, time_budget, force):
    """Derive a human model exactly --delta features away (seeded), as a task folder."""
    from mega_sat.bench.generate import write_instance

    g = write_instance(
        robot_domain, robot_problem, k, seed, out_dir, overwrite=force, time_budget=time_budget
    )
    run.echo(f"wrote {out_dir} (|Delta| = {len(g.updates)}, seed {seed}, {g.attempts} draw(s)):")
    for u in g.updates:
        run.echo(f"  {u.name}")
    return EXIT_OK


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
@_command
def generate_suite(run, domains_dir, deltas, seed, time_budget, force):
    """Generate DOMAINS_DIR/<name>/delta/<K>/<problem>/ for every shipped problem."""
    from mega_sat.bench import suites

    try:
        ks = [int(x) for x in deltas.split(",") if x.strip()]
    except ValueError:
        raise UsageError(f"--deltas must be comma-separated integers, got '{deltas}'") from None
    root = Path(domains_dir)
    if not suites.domain_dirs(root):
        raise UsageError("no domain folders with robot-domain.pddl", path=domains_dir)
    failed = []
    for draw in suites.generate_suite(root, ks, seed, overwrite=force, time_budget=time_budget):
        if draw.generated is not None:
            run.echo(f"{draw.out}: |Delta| = {len(draw.generated.updates)}", final=False)
        elif isinstance(draw.error, MegaSatError):
            failed.append(draw.out)
            click.echo(f"{draw.out}: skipped: {draw.error.message}", err=True)
        else:  # a bug, not a failed draw: stop as any other command does
            raise draw.error
    if failed:
        click.echo(f"{len(failed)} instance(s) not generated", err=True)
        return EXIT_FAILED
    return EXIT_OK


@main.command()
@click.argument("dirs", nargs=-1, required=True, type=click.Path())
@click.option(
    "--out",
    type=click.Path(),
    required=True,
    help="JSON Lines results, one line per task; a file that exists is resumed.",
)
@click.option("--jobs", type=click.IntRange(min=1), default=1, show_default=True)
@click.option(
    "--scheduler",
    default=None,
    metavar="ADDRESS",
    help="Run the tasks on a Dask cluster (tcp://HOST:PORT of its scheduler).",
)
@click.option(
    "--task-timeout",
    default=None,
    metavar="SECONDS",
    help="Time limit of each task (inf: none).",
)
@click.option(
    "--timeout",
    default=None,
    metavar="SECONDS",
    help="Time limit of the whole batch; written lines stay (inf: none).",
)
@click.option("--engine", type=ENGINE, default="sat", show_default=True)
@click.option("--planner", type=PLANNER, default=None, help="As for frontier.")
@click.option(
    "--joint",
    type=click.Choice(["portfolio", "sat", "search"]),
    default=None,
    help="As for frontier.",
)
@click.option("--hitting-set", type=HITTING, default="rc2", show_default=True)
@click.option("--verify", "do_verify", is_flag=True, help="Verify every point (frontier --verify).")
@click.option("--force", is_flag=True, help="Start --out afresh instead of resuming it.")
@click.option("--json", "as_json", is_flag=True, help="Print the summary as JSON.")
@options_option
@_command
def batch(run, dirs, out, jobs, scheduler, task_timeout, as_json, force, **kw):
    """frontier on many task folders, one JSON line per task, resumable."""
    from mega_sat.cli.batch import frontier_options, run_batch

    limit = parse_timeout(task_timeout, name="--task-timeout")
    options = frontier_options(kw["engine"], kw["planner"], kw["hitting_set"], kw["do_verify"])
    if kw["joint"] is not None:
        options += ("--joint", kw["joint"])
    pairs = kw.pop("option_pairs", ())
    _options({"option_pairs": pairs})  # a bad pair stops the batch before any task runs
    for pair in pairs:
        options += ("--option", pair)

    def progress(line, summary):
        r = line["result"]
        what = r.get("error", "")
        if "frontier" in r:
            what = f"{len(r['frontier'])} point(s)" + ("" if r["complete"] else ", incomplete")
        n = summary.already_done + summary.written
        click.echo(
            f"[{n}/{summary.tasks}] {line['task']}: exit {line['exit_code']}, {what}, "
            f"{line['wall_s']:.1f}s",
            err=True,
        )

    summary = run_batch(
        dirs,
        out,
        options=options,
        task_timeout=limit,
        jobs=jobs,
        scheduler=scheduler,
        force=force,
        deadline=run.deadline,
        on_line=progress,
    )
    for task, error in summary.failed:
        click.echo(f"error: {task}: not run to the end ({error}); run again to retry", err=True)
    if as_json:
        run.echo_json(summary.to_dict())
    else:
        run.echo(
            f"{out}: {summary.written} task(s) written now, {summary.already_done} already there, "
            f"{len(summary.failed)} failed, of {summary.tasks}"
        )
        if summary.stopped:
            run.echo(f"incomplete: {summary.stopped}; run again to resume")
    if summary.interrupt_exit_code is not None:
        return summary.interrupt_exit_code
    return EXIT_TOOL if summary.failed else EXIT_OK


@main.command(
    epilog="Usage >> mega-sat mmp -s EE -a 0.1 -m robot-domain.pddl -n human-domain.pddl "
    "-p robot-problem.pddl -q human-problem.pddl"
)
@click.option(
    "-s",
    "--search",
    type=click.Choice(["EE", "ME", "MCE"], case_sensitive=False),
    required=True,
    help="EE: MEGA at --alpha; ME: the MCE of the plan; MCE: the original's monotonic "
    "search (the MME of the plan).",
)
@click.option("-m", "--model", type=click.Path(), required=True, help="Robot domain.")
@click.option("-n", "--nmodel", type=click.Path(), required=True, help="Human domain.")
@click.option("-p", "--problem", type=click.Path(), required=True, help="Robot problem.")
@click.option("-q", "--hproblem", type=click.Path(), default=None, help="Human problem.")
@click.option(
    "-f", "--plan_file", "plan_file", type=click.Path(), default=None, help="ME/MCE: plan."
)
@click.option("-a", "--alpha", default=None, help="EE: the weight of extra robot cost.")
@click.option("-t", "--tmodel", type=click.Path(), default=None, help="Accepted; not needed.")
@click.option("-r", "--tproblem", type=click.Path(), default=None, help="Accepted; not needed.")
@click.option("--approx", is_flag=True, help="Accepted; no effect (answers are exact).")
@click.option("--heuristic", is_flag=True, help="Accepted; no effect.")
@click.option("--ground", is_flag=True, help="Accepted; no effect (updates are lifted).")
@click.option(
    "--timeout",
    default=None,
    metavar="SECONDS",
    help="Time limit for the whole run (inf: none).",
)
@click.option("--force", is_flag=True, help="Replace exp.dat / final_plan.sol of another tool.")
@_command
def mmp(run, search, model, nmodel, problem, hproblem, plan_file, alpha, force, **flags):
    """Drop-in for the original MEGA code's Explainer.py command line."""
    from mega_sat.api import MegaSolver, _check_alpha
    from mega_sat.cli.mmp import IGNORED_FLAGS, answer, check_outputs, write_outputs
    from mega_sat.pddl.planio import read_plan

    for name, note in IGNORED_FLAGS.items():
        if flags.get(name):
            click.echo(f"mega-sat mmp: {note}", err=True)
    search = search.upper()
    if search == "EE" and plan_file:
        click.echo(
            "mega-sat mmp: -f/--plan_file is not used by -s EE (MEGA picks the plan)", err=True
        )
    if search != "EE" and alpha is not None:
        click.echo(f"mega-sat mmp: -a/--alpha is not used by -s {search}", err=True)
    a = _check_alpha(alpha) if alpha is not None and search == "EE" else None
    paths = check_outputs(Path.cwd(), force)
    task = _load(None, model, problem, nmodel, hproblem)
    steps = read_plan(plan_file) if plan_file and search != "EE" else None
    t0 = time.perf_counter()
    ans = answer(MegaSolver(task, deadline=run.deadline), search, a, steps)
    write_outputs(ans, paths)
    for line in ans.explanation_lines():
        run.echo(line)
    click.echo(
        f"mega-sat mmp: {ans.summary}; {time.perf_counter() - t0:.3f}s; "
        f"wrote {paths[0].name} and {paths[1].name}",
        err=True,
    )
    return EXIT_OK


def _register_bench() -> None:
    from mega_sat.bench.harness import bench_command

    main.add_command(bench_command, "bench")


_register_bench()


def _register_bench_calls() -> None:
    from mega_sat.bench.oracle_calls import bench_calls_command

    main.add_command(bench_calls_command, "bench-calls")


_register_bench_calls()

if __name__ == "__main__":  # pragma: no cover
    main()
