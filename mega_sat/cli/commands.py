"""``mega-sat`` command line.

Every command that reads a model family takes the four PDDL files as ``--robot-domain
--robot-problem --human-domain [--human-problem]`` or ``--task DIR`` (see ``docs/cli.md``),
and ``--timeout``, one time limit for the whole run.  Exit codes are one table
(:data:`mega_sat.errors.EXIT_CODES`): user errors print one ``error: ...`` line on stderr; with
``--json`` stdout always carries exactly one JSON object, errors included; a traceback means a
bug in mega-sat.

A run is stopped by its time limit (cooperatively by every step, and by a SIGALRM backstop
shortly after the deadline, for steps without their own checks) or by SIGINT/SIGTERM (a handler
raising :class:`~mega_sat.errors.Interrupted`).  Either way what was proven so far is printed,
marked incomplete; child processes end with the exceptions that unwind through them.

``solve``, ``frontier`` and ``explain`` show the engine's :class:`~mega_sat.engines.progress.Progress`
live on stderr (a terminal only, not with ``--quiet``); the line is cleared as soon as the run
starts reporting (:meth:`_Run.quiet`), so it never mixes with the answer.
"""

from __future__ import annotations

import contextlib
import functools
import json
import os
import signal
import sys
import threading
import time
from pathlib import Path

import click

from mega_sat.deadline import NO_DEADLINE, Deadline, TimeLimitReached, parse_timeout, slack
from mega_sat.engines.progress import LiveProgress, progress_wanted
from mega_sat.errors import (
    EXIT_FAILED,
    EXIT_OK,
    EXIT_OUTPUT,
    EXIT_SIGINT,
    EXIT_TIMEOUT,
    EXIT_TOOL,
    EXIT_USAGE,
    Interrupted,
    MegaSatError,
    StdoutError,
    UsageError,
    is_pysat_interrupt,
    restore_sigint,
)

ENGINE = click.Choice(["sat", "astar"])
PLANNER = click.Choice(["builtin", "sat", "fd"])
HITTING = click.Choice(["rc2", "ilp"])

BACKSTOP_SHARE = 0.1
"""The backstop timer fires this share of the allowed overrun (max(1 s, 5 %) of the limit)
after the deadline, leaving the rest for a C call still running when it fires (a sort, a
conversion of a large array, a SAT conflict chunk), unwinding and printing what was proven."""

_as_program = False  # set by _Main.main when run as the ``mega-sat`` program (not in tests)


def _process_age() -> float:
    """Seconds since this process started (Linux ``/proc``; 0 elsewhere), so that a time limit
    also covers the interpreter's start-up and imports."""
    try:
        with open("/proc/self/stat") as f:
            start_ticks = int(f.read().rsplit(")", 1)[1].split()[19])
        with open("/proc/uptime") as f:
            uptime = float(f.read().split()[0])
        return max(0.0, uptime - start_ticks / os.sysconf("SC_CLK_TCK"))
    except (OSError, ValueError, IndexError):
        return 0.0


class _Run:
    """One command's run: its deadline, the handlers that stop it (SIGINT/SIGTERM, and the
    SIGALRM backstop of the deadline), its stdout, and how it ends.

    The handlers raise at most once: after the first stop (and once the answer is being
    printed) later signals are ignored, so the report of what was proven comes out whole.
    """

    def __init__(self, as_json: bool):
        self.as_json = as_json
        self.deadline: Deadline = NO_DEADLINE
        self.stopped: BaseException | None = None  # a stop after which a partial answer follows
        self.printed = False
        self.live = None  # a LiveProgress when progress is wanted (see _command)
        self._quiet = False
        self._saved: dict[int, object] = {}

    # ------------------------------------------------------------------ stops
    def _on_signal(self, signum, frame) -> None:
        if not self._quiet:
            self.quiet()
            raise Interrupted(signum)

    def _on_alarm(self, signum, frame) -> None:
        if self._quiet:
            return
        if not self.deadline.expired():  # early (another clock): wait for the rest
            signal.setitimer(signal.ITIMER_REAL, max(self.deadline.remaining() or 0.0, 0.001))
            return
        self.quiet()
        raise TimeLimitReached(self.deadline.seconds, forced=True)

    def __enter__(self) -> _Run:
        if threading.current_thread() is not threading.main_thread():
            return self
        for sig in (signal.SIGINT, signal.SIGTERM):
            previous = signal.getsignal(sig)
            if previous is signal.SIG_IGN:  # e.g. a background job of a shell: stay immune
                continue
            self._saved[sig] = previous
            signal.signal(sig, self._on_signal)
        left = self.deadline.remaining()
        if left is not None:
            self._saved[signal.SIGALRM] = signal.signal(signal.SIGALRM, self._on_alarm)
            backstop = BACKSTOP_SHARE * slack(self.deadline.seconds or 0.0)
            signal.setitimer(signal.ITIMER_REAL, max(left + backstop, 0.001))
        return self

    def __exit__(self, *exc) -> None:
        self.quiet()
        for sig, handler in self._saved.items():
            signal.signal(sig, handler)
        self._saved.clear()

    def quiet(self) -> None:
        """No more stops from here on (the run is reporting), and no more progress display."""
        self._quiet = True
        if signal.SIGALRM in self._saved:
            signal.setitimer(signal.ITIMER_REAL, 0)
        if self.live is not None:
            self.live.stop()

    def watch(self, progress) -> None:
        """Show ``progress`` (a :class:`~mega_sat.engines.progress.Progress`) live on stderr, when the
        run shows progress at all (a terminal, no ``--quiet``)."""
        if self.live is not None and not self._quiet:
            self.live.watch(progress)
            self.live.start()

    @staticmethod
    def reason(stop: BaseException) -> str:
        """Why a partial answer is partial, e.g. "time limit 5.0s reached: frontier
        incomplete" (the words of the engine's own time-limit note)."""
        return f"{stop}: frontier incomplete"

    def compute(self, work, partial=None):
        """``work()``; if a time limit or an interrupt stops it, ``partial(reason)`` (what was
        proven), remembered in :attr:`stopped`; with no partial answer the stop goes on up."""
        try:
            return work()
        except Exception as e:
            if not is_pysat_interrupt(e):  # a Ctrl-C that python-sat caught (e.g. in RC2)
                raise
            restore_sigint()
            stop: BaseException = Interrupted(signal.SIGINT)
        except (TimeLimitReached, Interrupted) as e:
            stop = e
        self.quiet()
        got = None if partial is None else partial(self.reason(stop))
        if got is None:
            raise stop
        self.stopped = stop
        return got

    def exit_code(self, code: int = EXIT_OK) -> int:
        """``code``, or the interrupt's code when a partial answer followed an interrupt."""
        if isinstance(self.stopped, Interrupted):
            return self.stopped.exit_code
        return code

    # ----------------------------------------------------------------- output
    def echo(self, text: str = "", nl: bool = True, *, final: bool = True) -> None:
        """Write to stdout; a write that fails (full disk, closed pipe) is a :class:`StdoutError`.
        Writing the answer (``final``) ends the stops, so it comes out whole."""
        if final:
            self.quiet()
        try:
            click.echo(text, nl=nl)
        except OSError as e:
            _silence_stdout()
            raise StdoutError(f"cannot write to standard output: {e.strerror or e}") from None
        self.printed = True

    def echo_json(self, obj: dict) -> None:
        self.echo(json.dumps(obj, indent=2))

    def fail(self, code: int, message: str, status: str | None = None) -> int:
        """One ``error:`` line on stderr and, with ``--json`` and nothing printed yet, one JSON
        object on stdout; returns the exit code."""
        self.quiet()
        text = f"error: {message}"  # library messages carry no prefix (mega_sat.errors)
        click.echo(text, err=True)
        if self.as_json and not self.printed:
            obj: dict = {}
            if status is not None:
                obj = {"complete": False, "status": status}
            obj.update(error=message, exit_code=code)
            try:
                self.echo_json(obj)
            except StdoutError as e:
                click.echo(f"error: {e}", err=True)
                return EXIT_OUTPUT
        return code


def _silence_stdout() -> None:
    """Point fd 1 at /dev/null after a failed write, so the interpreter's final flush of the
    unwritten text does not print a second error."""
    with contextlib.suppress(OSError, ValueError, AttributeError):
        fd = os.open(os.devnull, os.O_WRONLY)
        os.dup2(fd, sys.stdout.fileno())
        os.close(fd)


def _exit_now(code: int) -> None:
    """End a stopped run at once: what was proven is printed, children are gone, and tearing
    down a large grounding object by object can take longer than the time limit allows."""
    for stream in (sys.stdout, sys.stderr):
        with contextlib.suppress(OSError, ValueError, AttributeError):
            stream.flush()
    os._exit(code)


def _from_click_echo(e: OSError) -> bool:
    """Whether ``e`` was raised by a write of ``click.echo`` (the commands' own writes go
    through :meth:`_Run.echo`, which reports them itself)."""
    import traceback

    frames = traceback.extract_tb(e.__traceback__)
    return bool(frames) and frames[-1].name == "echo" and "click" in frames[-1].filename


def _command(fn):
    """Run a command inside a :class:`_Run`: ``--timeout`` becomes its deadline, stops and
    :class:`MegaSatError` become one line and the exit code of :data:`EXIT_CODES`, and the
    command gets the run as ``run`` (it returns its exit code)."""

    @functools.wraps(fn)
    def wrapper(*args, **kwargs):
        run = _Run(bool(kwargs.get("as_json")))
        timeout = kwargs.pop("timeout", None)
        quiet = kwargs.pop("quiet", False)
        code = EXIT_OK
        try:
            if sys.stdout is None:
                raise StdoutError("cannot write to standard output: it is closed")
            age = _process_age() if _as_program else 0.0
            run.deadline = Deadline.after(parse_timeout(timeout, name="--timeout"), elapsed=age)
            if progress_wanted(quiet):
                ctx = click.get_current_context(silent=True)
                run.live = LiveProgress(
                    ctx.info_name if ctx is not None else fn.__name__,
                    run.deadline,
                    started=time.perf_counter() - age,
                )
            with run:
                try:
                    run.deadline.check()
                    code = fn(*args, run=run, **kwargs) or EXIT_OK
                except MegaSatError as e:
                    code = run.fail(e.exit_code, str(e))
                except TimeLimitReached:
                    code = run.fail(
                        EXIT_TIMEOUT,
                        f"{run.deadline.describe()} reached before anything could be reported",
                        "timeout",
                    )
                except Interrupted as e:
                    code = run.fail(
                        e.exit_code, f"{e} before anything could be reported", "interrupted"
                    )
                except MemoryError as e:
                    e.__traceback__ = None  # drop the frames that hold the large structures
                    code = run.fail(
                        EXIT_USAGE,
                        "out of memory: the task needs more memory than this process may use "
                        "(-v prints the grounding's size; a smaller model, or the astar engine, "
                        "may fit)",
                    )
                except Exception as e:
                    if not is_pysat_interrupt(e):
                        raise
                    restore_sigint()
                    code = run.fail(
                        EXIT_SIGINT,
                        "interrupted by SIGINT before anything could be reported",
                        "interrupted",
                    )
        except MegaSatError as e:  # before the run started: bad --timeout, closed stdout
            code = run.fail(e.exit_code, str(e))
        if _as_program and (run.stopped is not None or run.deadline.expired() or code > 100):
            _exit_now(code)
        sys.exit(code)

    return wrapper


class _Main(click.Group):
    """The ``mega-sat`` group: click's usage errors follow the same rules as the commands'
    errors (with ``--json``, one JSON object on stdout too), and an interrupt before a
    command's own handlers are in place exits 130 without a traceback."""

    def main(self, args=None, prog_name=None, complete_var=None, standalone_mode=True, **extra):
        global _as_program
        _as_program = args is None
        argv = sys.argv[1:] if args is None else [str(a) for a in args]
        if not standalone_mode:
            return super().main(argv, prog_name, complete_var, False, **extra)
        run = _Run("--json" in argv)
        if sys.stdout is None:  # started with fd 1 closed: every answer would vanish
            sys.exit(run.fail(EXIT_OUTPUT, "cannot write to standard output: it is closed"))
        try:
            rv = super().main(argv, prog_name, complete_var, False, **extra)
        except click.ClickException as e:
            message = e.format_message()
            ctx = getattr(e, "ctx", None)
            if isinstance(e, click.UsageError) and ctx is not None:
                message += f" (see '{ctx.command_path} --help')"
            sys.exit(run.fail(e.exit_code, message))
        except OSError as e:
            if not _from_click_echo(e):
                raise
            # click's own output (--help, --version) to a full disk or a closed pipe
            _silence_stdout()
            sys.exit(run.fail(EXIT_OUTPUT, f"cannot write to standard output: {e.strerror or e}"))
        except click.Abort as e:
            if isinstance(e.__cause__, KeyboardInterrupt):
                sys.exit(run.fail(EXIT_SIGINT, "interrupted by SIGINT", "interrupted"))
            click.echo("Aborted!", err=True)
            sys.exit(EXIT_FAILED)
        sys.exit(rv if isinstance(rv, int) else EXIT_OK)


def task_options(fn):
    """The four model files, or ``--task DIR``, and the run's ``--timeout``."""
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
        click.option(
            "--human-domain",
            type=click.Path(),
            multiple=True,
            help="Repeat (with --human-problem, paired in order) for several human models "
            "(solve, frontier).",
        ),
        click.option(
            "--human-problem",
            type=click.Path(),
            multiple=True,
            help="Defaults to the robot problem.",
        ),
        click.option("-v", "--verbose", is_flag=True, help="Report grounding sizes and stats."),
        click.option(
            "--timeout",
            type=str,
            default=None,
            metavar="SECONDS",
            help="Time limit for the whole run, then report what is proven (inf: none).",
        ),
    ]
    for o in reversed(opts):
        fn = o(fn)
    return fn


def options_option(fn):
    """``--option KEY=VALUE`` (repeatable): a tuning knob of :class:`mega_sat.options.Options`."""
    return click.option(
        "--option",
        "option_pairs",
        multiple=True,
        metavar="KEY=VALUE",
        help="Set a tuning knob (repeatable; the knobs and their defaults are listed in "
        "docs/cli.md, 'Tuning options').  Answers do not change, only how fast they come.",
    )(fn)


def _options(kw):
    """The ``--option`` pairs of a command (removed from ``kw``) as one Options."""
    from mega_sat.options import Options

    return Options().with_pairs(kw.pop("option_pairs", ()))


def _load(task_dir, robot_domain, robot_problem, human_domain, human_problem, several=False):
    from mega_sat.pddl.loading import load_task, resolve_task_dir
    from mega_sat.pddl.multi_task import load_cli_task

    # the options repeat (several human models); other callers pass one path or None
    human_domain, human_problem = (
        (x,) if isinstance(x, str | Path) else tuple(x or ()) for x in (human_domain, human_problem)
    )
    task = load_cli_task(
        task_dir, robot_domain, robot_problem, human_domain, human_problem, several=several
    )
    if task is not None:
        return task
    human_domain = human_domain[0] if human_domain else None
    human_problem = human_problem[0] if human_problem else None

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


def _task_from(kw, several=False):
    return _load(
        kw.pop("task_dir"),
        kw.pop("robot_domain"),
        kw.pop("robot_problem"),
        kw.pop("human_domain"),
        kw.pop("human_problem"),
        several,
    )


def _verbose_family(solver, verbose: bool) -> None:
    if verbose:
        t0 = time.perf_counter()
        fam = solver.family
        click.echo(
            f"; |Delta| = {len(solver.task.delta)}; grounded {fam.describe()} in "
            f"{time.perf_counter() - t0:.3f}s",
            err=True,
        )


@click.group(cls=_Main, context_settings={"help_option_names": ["-h", "--help"]})
@click.version_option(package_name="mega-sat")
def main():
    """mega-sat: exact MEGA (explicability vs. explanations) with SAT and ILP."""
    _show_warnings_as_lines()


def _show_warnings_as_lines() -> None:
    """Print mega-sat's warnings (PDDLWarning) as one ``warning: ...`` line on stderr."""
    import warnings

    from mega_sat.pddl.reader import PDDLWarning

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
    d, p = write_model(task.updated_model(sel), out_dir, overwrite=force)
    run.echo(f"wrote {d}\nwrote {p}")
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
    fam = _ground(task, run, verbose)
    r = NodePlanner(task, fam, planner, deadline=run.deadline, options=options).optimal(sel)
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


quiet_option = click.option(
    "--quiet",
    is_flag=True,
    help="No live progress on stderr (otherwise shown on a terminal after 1 s).",
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
            write_file(d / "plan.ipc", format_plan(p.plan, p.robot_cost))
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
            notes.append(
                f"{stop} during --verify: {len(reports)} of {len(points)} point(s) checked"
                + ("; --write-model skipped" if write_model else "")
            )
            return reports, notes
    if write_model:
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
    from mega_sat.cli.plotting import write_plot

    click.echo(f"; wrote {write_plot(fr, target, force=force, title=title)}", err=True)
    return []


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
    return run.exit_code(EXIT_OK)


def _status_line(fr) -> str:
    if fr.exact:
        return "exact: yes (minimal explanations and optimal costs proven)"
    return "exact: no (" + "; ".join(fr.notes) + ")"


def _incomplete_lines(run, notes) -> None:
    """The run's own notes (a stop after the answer was found) in text: the answer stays as
    proven, what was requested on top of it is not finished."""
    for note in notes:
        run.echo(f"incomplete: {note}")


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

    sol = run.compute(work, lambda reason: s.partial_solution(a, reason))
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
@click.option("--planner", type=PLANNER, default="builtin", show_default=True)
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
            notes.append(f"{stop} during --verify: not checked")
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
    return run.exit_code(EXIT_FAILED if rep and not rep.ok else EXIT_OK)


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
    from mega_sat.engines.verify import verify_pair
    from mega_sat.pddl.planio import read_plan
    from mega_sat.pddl.update_costs import cost_vector

    costs = _read_update_costs(update_costs)
    options = _options(kw)
    task = _task_from(kw)
    costs = cost_vector(task, costs)
    sel = _read_explanation(task, explanation)
    steps = read_plan(plan_file)
    fam = _ground(task, run, verbose)
    rep = verify_pair(
        task,
        fam,
        sel,
        steps,
        producer="sat",
        checker=checker,
        deadline=run.deadline,
        update_costs=costs,
        options=options,
    )
    if as_json:
        run.echo_json(rep.to_dict())
    else:
        for line in rep.lines():
            run.echo(line)
        run.echo("verify: " + ("passed" if rep.ok else "FAILED"))
    return EXIT_OK if rep.ok else EXIT_FAILED


# --------------------------------------------------------------------------- generate


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
