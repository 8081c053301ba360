"""Plans in the IPC format: one ``(action arg ...)`` per line, ``;`` comments.

The reader is tolerant of what planners actually print (Fast Downward's ``; cost = ...`` footer,
``0: (a b) [1]`` timestamps and durations of temporal-style output, any case) and strict about
everything else: a line it cannot read is an error naming the file and line, never a silently
dropped step.
"""

from __future__ import annotations

import re
from collections.abc import Iterable
from pathlib import Path

from mega_sat.errors import PDDLError
from mega_sat.model.lifted import PlanStep, step_str

_STEP_RE = re.compile(
    r"""^(?:\d+(?:\.\d+)?\s*:\s*)?        # optional timestamp '0:' or '0.001:'
        \(\s*([^\s()]+(?:\s+[^\s()]+)*)\s*\)  # (action arg ...)
        \s*(?:\[\s*\d+(?:\.\d+)?\s*\])?$      # optional duration '[1]'
    """,
    re.VERBOSE,
)


def parse_plan(text: str, *, path: str = "<plan>") -> tuple[PlanStep, ...]:
    """Parse a plan; a malformed line is a :class:`PDDLError` with path and line number."""
    steps: list[PlanStep] = []
    text = text.removeprefix("\ufeff")  # a byte-order mark, as editors on Windows write it
    for lineno, raw in enumerate(text.splitlines(), 1):
        line = raw.split(";", 1)[0].strip()
        if not line:
            continue
        m = _STEP_RE.match(line)
        if m is None:
            shown = line if len(line) <= 60 else line[:57] + "..."
            raise PDDLError(
                f"expected one '(action arg ...)' per line, got '{shown}'",
                path=path,
                where=f"line {lineno}",
            )
        steps.append(tuple(m.group(1).lower().split()))
    return tuple(steps)


def as_plan(plan: object, *, what: str = "plan") -> tuple[PlanStep, ...]:
    """A plan given through the library API, in any of the forms a user writes one: IPC text
    (``"(move p1 p6)\n(take_picture p6)"``), a sequence of step strings (``"(move p1 p6)"``
    or ``"move p1 p6"``) or of tuples (``("MOVE", "P1", "P6")``); names in any case, as the
    CLI reads them.  Anything else is a :class:`UsageError` saying what was expected."""
    from mega_sat.errors import UsageError

    if isinstance(plan, str):
        return parse_plan(plan, path=what)
    if isinstance(plan, bytes) or not isinstance(plan, Iterable):
        raise UsageError(
            f"{what} must be a sequence of steps such as ('move', 'p1', 'p6') or "
            f"'(move p1 p6)', got {type(plan).__name__}"
        )
    steps: list[PlanStep] = []
    for k, step in enumerate(plan, 1):
        if isinstance(step, str):
            text = step.strip()
            if not text.startswith("("):
                text = f"({text})"
            parsed = parse_plan(text, path=f"{what} step {k}")
            if len(parsed) != 1:
                raise UsageError(f"{what} step {k}: expected one step, got {step!r}")
            steps.append(parsed[0])
        elif isinstance(step, tuple | list) and step and all(isinstance(x, str) for x in step):
            if any(not x.strip() or any(c.isspace() or c in "()" for c in x) for x in step):
                raise UsageError(f"{what} step {k}: malformed name in {tuple(step)!r}")
            steps.append(tuple(x.lower() for x in step))
        else:
            raise UsageError(
                f"{what} step {k}: expected a tuple of names such as ('move', 'p1', 'p6') "
                f"or a string '(move p1 p6)', got {step!r}"
            )
    return tuple(steps)


def read_plan(path: str | Path) -> tuple[PlanStep, ...]:
    """Read a plan file; a missing or unreadable file is a :class:`PDDLError` naming it."""
    from mega_sat.pddl.reader import read_text

    return parse_plan(read_text(path, "plan"), path=str(path))


def format_plan(plan: Iterable[PlanStep], cost: int | None = None) -> str:
    """The IPC text of ``plan``, with Fast Downward's cost footer when ``cost`` is given."""
    lines = [step_str(s) for s in plan]
    if cost is not None:
        lines.append(f"; cost = {cost} (general cost)")
    return "".join(line + "\n" for line in lines)


def write_plan(
    path: str | Path, plan: Iterable[PlanStep], cost: int | None = None, overwrite: bool = False
) -> Path:
    """Write ``plan`` to ``path``; an existing file is a UsageError unless ``overwrite``."""
    from mega_sat.pddl.writer import write_text

    return write_text(Path(path), format_plan(plan, cost), overwrite=overwrite)
