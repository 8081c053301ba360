"""``mega-sat batch``: the frontier of many task folders, one JSON line per task.

Each task runs as its own ``mega-sat frontier --json`` process with its own time limit, on a
local thread pool or on the workers of a Dask cluster (:mod:`mega_sat.executor`).  The PDDL
texts travel with the task, so workers need mega-sat installed but no shared file system.
The caller appends each line to the results file as soon as the task ends, with an ``fsync``,
so a stop (a dead worker, Ctrl-C, a time limit, a crash of the caller) loses nothing already
written, and a second run with the same file skips every task it already holds.
"""

from __future__ import annotations

import json
import os
import signal
import socket
import subprocess
import sys
import tempfile
import threading
import time
from collections.abc import Iterable, Sequence
from dataclasses import dataclass
from pathlib import Path
from typing import Any

from mega_sat.errors import EXIT_TIMEOUT, UsageError
from mega_sat.output import OutputError, write_file
from mega_sat.pddl.loading import TASK_FILES, resolve_task_dir
from mega_sat.pddl.multi_task import HUMAN_DIR, human_dirs, resolve_multi_task_dir

GRACE_S = 10.0
"""How long past its own time limit a task's process may run before it is killed (the process
stops itself within max(1 s, 5 %) of the limit; this only catches one that hangs)."""

_FLAGS = {
    "robot_domain": "--robot-domain",
    "robot_problem": "--robot-problem",
    "human_domain": "--human-domain",
    "human_problem": "--human-problem",
}


@dataclass(frozen=True)
class BatchTask:
    """One task folder, with the texts of its files: ``files`` holds ``(flag, path, text)``
    in the order ``frontier`` takes them (``--robot-domain``, ``--robot-problem``, then one
    ``--human-domain``/``--human-problem`` pair per human model)."""

    name: str
    files: tuple[tuple[str, str, str], ...]


def find_task_dirs(paths: Iterable[str | Path]) -> list[Path]:
    """Every task folder named by ``paths``: a task folder itself, or each task folder below
    a folder (sorted).  A path that is neither is an error naming it."""
    found: list[Path] = []
    for p in map(Path, paths):
        if not p.exists():
            raise UsageError("not found", path=str(p))
        if not p.is_dir():
            raise UsageError("is not a folder (batch takes task folders)", path=str(p))
        if (p / TASK_FILES["robot_problem"]).is_file():
            found.append(p)
            continue
        below = sorted(
            q.parent
            for q in p.rglob(TASK_FILES["robot_problem"])
            if not (HUMAN_DIR.fullmatch(q.parent.name) and human_dirs(q.parent.parent))
        )  # a human-K folder is part of its task, even one holding a robot problem
        if not below:
            raise UsageError(f"no task folder ({TASK_FILES['robot_problem']}) below", path=str(p))
        found += below
    return list(dict.fromkeys(found))


def read_task(d: Path) -> BatchTask:
    """The files of task folder ``d``, one human model or several (``human-K/`` folders)."""
    if human_dirs(d):
        multi = resolve_multi_task_dir(d)
        named = [
            ("--robot-domain", multi["robot_domain"]),
            ("--robot-problem", multi["robot_problem"]),
        ]
        for domain, problem in multi["humans"]:
            named += [("--human-domain", domain), ("--human-problem", problem)]
    else:
        one = resolve_task_dir(d)
        named = [(_FLAGS[role], one[role]) for role in _FLAGS]
    files = []
    for flag, path in named:
        try:
            text = Path(path).read_text(encoding="utf-8")
        except (OSError, UnicodeDecodeError) as e:
            raise UsageError(
                f"cannot read: {getattr(e, 'strerror', None) or e}", path=str(path)
            ) from None
        files.append((flag, str(path), text))
    return BatchTask(str(d), tuple(files))


# ------------------------------------------------------------------------------- results file
def read_done(out: Path) -> tuple[set[str], list[str]]:
    """The tasks a results file already holds, and its good lines.  A last line cut short (a
    crash while writing it) does not count; any other line that is not a task's JSON object is
    an error naming the line."""
    if not out.exists():
        return set(), []
    if out.is_dir():
        raise UsageError("is a folder, expected a results file", path=str(out))
    try:
        text = out.read_text(encoding="utf-8")
    except (OSError, UnicodeDecodeError) as e:
        raise UsageError(
            f"cannot read: {getattr(e, 'strerror', None) or e}", path=str(out)
        ) from None
    lines = text.split("\n")
    done: set[str] = set()
    good: list[str] = []
    for n, line in enumerate(lines, 1):
        if not line.strip():
            continue
        try:
            obj = json.loads(line)
            ok = isinstance(obj, dict) and isinstance(obj.get("task"), str)
        except json.JSONDecodeError:
            ok = False
        if not ok:
            if n == len(lines):  # no newline after it: the write was cut short
                continue
            raise UsageError(
                "not a line of mega-sat batch results (use --force to start the file afresh)",
                path=str(out),
                where=f"line {n}",
            )
        done.add(obj["task"])
        good.append(line)
    return done, good


class ResultsFile:
    """Appends one line per task, each written whole and synced before the next."""

    def __init__(self, out: Path, good_lines: Sequence[str], *, restart: bool):
        self.path = out
        text = out.read_text(encoding="utf-8") if out.exists() else ""
        if restart or (
            text.rstrip("\n") != "\n".join(good_lines)
            # a last line complete but without its newline: the next line would be glued to it
            or (text and not text.endswith("\n"))
        ):
            # a fresh start, or a cut-short last line to drop: rewrite atomically first
            write_file(out, "".join(line + "\n" for line in good_lines), force=True)
        try:
            self._f = open(out, "a", encoding="utf-8")  # noqa: SIM115 - closed by close()
        except OSError as e:
            raise OutputError(f"cannot write file: {e.strerror or e}", path=str(out)) from None

    def append(self, obj: dict[str, Any]) -> None:
        self._f.write(json.dumps(obj, separators=(",", ":")) + "\n")
        self._f.flush()
        os.fsync(self._f.fileno())

    def close(self) -> None:
        self._f.close()


# --------------------------------------------------------------------------------- one task
_children: set[subprocess.Popen] = set()
_children_lock = threading.Lock()


def stop_children() -> None:
    """End the task processes this process started (local runs), e.g. after Ctrl-C."""
    with _children_lock:
        for p in list(_children):
            if p.poll() is None:
                try:
                    os.killpg(p.pid, signal.SIGTERM)
                except OSError:
                    p.terminate()


def run_task(task: BatchTask, options: Sequence[str], timeout: float | None) -> dict[str, Any]:
    """Run ``mega-sat frontier --json`` on ``task`` in a process of its own; the result line.

    Runs wherever the executor sends it (this process or a Dask worker): the texts are written
    into a temporary folder, and its paths are replaced by the task's own in the output."""
    t0 = time.perf_counter()
    with tempfile.TemporaryDirectory(prefix="mega-sat-batch-") as tmp:
        cmd = [sys.executable, "-m", "mega_sat.cli.commands", "frontier", "--json"]
        local = []
        for i, (flag, path, text) in enumerate(task.files):
            p = Path(tmp) / f"{i}-{Path(path).name}"  # two human models may share a name
            p.write_text(text, encoding="utf-8")
            local.append((str(p), path))
            cmd += [flag, str(p)]
        cmd += list(options)
        if timeout is not None:
            cmd += ["--timeout", repr(timeout)]
        proc = subprocess.Popen(
            cmd,
            stdout=subprocess.PIPE,
            stderr=subprocess.PIPE,
            text=True,
            start_new_session=True,  # a terminal's Ctrl-C reaches the caller, which ends us
        )
        with _children_lock:
            _children.add(proc)
        try:
            out, err = proc.communicate(timeout=None if timeout is None else timeout + GRACE_S)
        except subprocess.TimeoutExpired:
            os.killpg(proc.pid, signal.SIGKILL)
            out, err = proc.communicate()
            out = json.dumps({"error": f"killed {GRACE_S:g} s after its time limit"})
            proc.returncode = EXIT_TIMEOUT
        finally:
            with _children_lock:
                _children.discard(proc)
        for p, users in local:  # messages name the user's files, not the copies
            out = out.replace(json.dumps(p)[1:-1], json.dumps(users)[1:-1])
    try:
        result = json.loads(out)
    except json.JSONDecodeError:
        last = (err.strip().splitlines() or ["no output"])[-1]
        result = {"error": f"no JSON from the task's process: {last}"}
    return {
        "task": task.name,
        "exit_code": proc.returncode,
        "wall_s": round(time.perf_counter() - t0, 3),
        "host": socket.gethostname(),
        "result": result,
    }


def frontier_options(
    engine: str, planner: str | None, hitting_set: str, verify: bool
) -> tuple[str, ...]:
    """The ``frontier`` options every task of a batch gets."""
    opts = ["--engine", engine, "--hitting-set", hitting_set]
    if planner is not None:
        opts += ["--planner", planner]
    if verify:
        opts.append("--verify")
    return tuple(opts)


# ------------------------------------------------------------------------------ whole batch
@dataclass
class BatchSummary:
    """What a batch run did: tasks found, already in the file, written now, and failed
    (not written, so that the next run retries them)."""

    out: str
    tasks: int
    already_done: int
    written: int = 0
    failed: list[tuple[str, str]] | None = None
    stopped: str | None = None  # why the batch stopped early (time limit, interrupt)
    interrupt_exit_code: int | None = None  # 130 / 143 when a signal stopped it

    @property
    def complete(self) -> bool:
        return (
            self.stopped is None
            and not self.failed
            and (self.already_done + self.written == self.tasks)
        )

    def to_dict(self) -> dict[str, Any]:
        return {
            "out": self.out,
            "tasks": self.tasks,
            "already_done": self.already_done,
            "written": self.written,
            "failed": [{"task": t, "error": e} for t, e in self.failed or ()],
            "complete": self.complete,
            "stopped": self.stopped,
        }


def run_batch(
    dirs: Sequence[str | Path],
    out: str | Path,
    *,
    options: Sequence[str] = (),
    task_timeout: float | None = None,
    jobs: int = 1,
    scheduler: Any = None,
    force: bool = False,
    deadline: Any = None,
    on_line: Any = None,
) -> BatchSummary:
    """Run ``frontier`` on every task of ``dirs`` not yet in ``out`` and append their lines.

    ``on_line(line, summary)`` is called after each line is written (progress).  A time limit
    (``deadline``) or an interrupt ends the batch with what is written so far; the reason is
    in ``summary.stopped``."""
    from mega_sat.deadline import TimeLimitReached
    from mega_sat.errors import Interrupted
    from mega_sat.executor import completed
    from mega_sat.output import check_target

    out = Path(out)
    task_dirs = find_task_dirs(dirs)
    check_target(out, force=True)  # its folder exists and is writable; the file is resumed
    done, good = read_done(out) if not force else (set(), [])
    todo = [d for d in task_dirs if str(d) not in done]
    summary = BatchSummary(str(out), len(task_dirs), len(task_dirs) - len(todo), failed=[])
    tasks = [read_task(d) for d in todo]  # unreadable files are found before anything runs
    results = ResultsFile(out, good, restart=force)
    outcomes = completed(
        run_task, [(t, tuple(options), task_timeout) for t in tasks], jobs=jobs, scheduler=scheduler
    )
    try:
        for o in outcomes:
            if o.error is not None:
                summary.failed.append((tasks[o.index].name, f"{type(o.error).__name__}: {o.error}"))
            else:
                results.append(o.value)
                summary.written += 1
                if on_line is not None:
                    on_line(o.value, summary)
            if deadline is not None:
                deadline.check()
    except TimeLimitReached as e:
        summary.stopped = str(e)
    except Interrupted as e:
        summary.stopped = str(e)
        summary.interrupt_exit_code = e.exit_code
    finally:
        outcomes.close()
        stop_children()
        results.close()
    return summary
