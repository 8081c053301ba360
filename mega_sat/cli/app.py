"""What every ``mega-sat`` command shares: the run (time limit, signals, exit codes, output),
the option groups that read a task, and the ``main`` group the commands register with.

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
    EXIT_USAGE,
    Interrupted,
    MegaSatError,
    PlannerError,
    StdoutError,
    UsageError,
    is_pysat_interrupt,
    restore_sigint,
)

ENGINE = click.Choice(["sat", "astar"])
PLANNER = click.Choice(["builtin", "sat", "fd", "portfolio"])
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
        self.tool_failed: PlannerError | None = None  # a checker that failed after the answer
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

    def fail(
        self, code: int, message: str, status: str | None = None, extra: dict | None = None
    ) -> int:
        """One ``error:`` line on stderr and, with ``--json`` and nothing printed yet, one JSON
        object on stdout (``extra``: what was proven before a stop, keys after ``exit_code``);
        returns the exit code."""
        self.quiet()
        text = f"error: {message}"  # library messages carry no prefix (mega_sat.errors)
        click.echo(text, err=True)
        if self.as_json and not self.printed:
            obj: dict = {}
            if status is not None:
                obj = {"complete": False, "status": status}
            obj.update(error=message, exit_code=code)
            obj.update({k: v for k, v in (extra or {}).items() if k not in obj})
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


def timeout_message(deadline: Deadline, stop: TimeLimitReached) -> str:
    """The error line of a run the time limit ended without an answer: nothing to report, or
    part of one (``stop.partial``), with what was proven (``stop.detail``)."""
    when = "before the answer was complete"
    if not stop.partial:
        when = "before anything could be reported"
    detail = f"; {stop.detail}" if stop.detail else ""
    return f"{deadline.describe()} reached {when}{detail}"


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
                except TimeLimitReached as e:
                    code = run.fail(EXIT_TIMEOUT, timeout_message(run.deadline, e), "timeout")
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


quiet_option = click.option(
    "--quiet",
    is_flag=True,
    help="No live progress on stderr (otherwise shown on a terminal after 1 s).",
)
