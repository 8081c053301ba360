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
from mega_sat.family import PlanStep, step_str

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


def read_plan(path: str | Path) -> tuple[PlanStep, ...]:
    """Read a plan file; a missing or unreadable file is a :class:`PDDLError` naming it."""
    from mega_sat.pddl_reader import read_text

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
    from mega_sat.pddl_writer import write_text

    return write_text(Path(path), format_plan(plan, cost), overwrite=overwrite)
