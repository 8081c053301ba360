"""Weighted updates: a positive integer cost per update of the model difference.

With update costs the explanation cost of ``E`` is the sum of its updates' costs instead of
``|E|``; it replaces ``|E|`` in the objective and the frontier (docs/cli.md, "Update costs").
An update without a cost costs 1, so a run without costs is the unweighted problem.

The file format, one update per line::

    # comments start with '#' or ';' (also after the cost)
    remove-has-initial-state-clear_path p1 p8  5

The cost is the last whitespace-separated token of the line; the rest is the update's name as
``mega-sat diff`` prints it (an ``Explanation >>`` prefix, as ``solve`` prints it, is
allowed).  Errors name the file and the line.
"""

from __future__ import annotations

import re
from collections.abc import Mapping
from dataclasses import dataclass
from pathlib import Path

from mega_sat.errors import UsageError
from mega_sat.model.task import explanation_line

MAX_COST = 10**9
"""Costs above this are refused: the CBC hitting-set back end works in floating point, and a
sum of costs it cannot represent exactly would no longer be a proven minimum."""

_INT = re.compile(r"[+-]?[0-9]+")


class UpdateCostError(UsageError):
    """A bad update cost: not an update of Delta, not a positive integer, given twice."""


@dataclass(frozen=True)
class UpdateCosts:
    """Costs by update name, with the line each was given on (``source``: the file, for error
    messages; ``None`` for costs given in code)."""

    costs: tuple[tuple[str, int], ...]
    lines: tuple[int | None, ...] = ()
    source: str | None = None

    def as_dict(self) -> dict[str, int]:
        return dict(self.costs)


def parse_update_costs(text: str, source: str | None = None) -> UpdateCosts:
    """Read the file format above (names are checked against a task by :func:`cost_vector`)."""
    costs: list[tuple[str, int]] = []
    lines: list[int | None] = []
    seen: dict[str, int] = {}
    for lineno, raw in enumerate(text.splitlines(), 1):
        where = f"line {lineno}"
        line = explanation_line(re.split(r"[#;]", raw, maxsplit=1)[0])  # then the cost
        if not line:
            continue
        tokens = line.split()
        if len(tokens) < 2:
            raise UpdateCostError(
                f"expected an update name and its cost, e.g. '{_shown(tokens[0])} 5'",
                path=source,
                where=where,
            )
        name = " ".join(tokens[:-1])
        cost = _check_cost(tokens[-1], name, source, where)
        if name in seen:
            raise UpdateCostError(
                f"'{_shown(name)}' has a cost already (line {seen[name]})",
                path=source,
                where=where,
            )
        seen[name] = lineno
        costs.append((name, cost))
        lines.append(lineno)
    return UpdateCosts(tuple(costs), tuple(lines), source)


def load_update_costs(path: str | Path) -> UpdateCosts:
    """Read an update-costs file (a missing, binary or unreadable file is a one-line error)."""
    from mega_sat.pddl.reader import read_text

    return parse_update_costs(read_text(path, "update costs"), str(path))


def as_update_costs(costs: UpdateCosts | Mapping[str, int]) -> UpdateCosts:
    """Costs given in code (a mapping from update name to cost) in the checked form."""
    if isinstance(costs, UpdateCosts):
        # built in code too: the same checks as a mapping, and no name given twice
        try:
            pairs = [(name, cost) for name, cost in costs.costs]
        except (TypeError, ValueError):
            raise UpdateCostError("UpdateCosts.costs holds (update name, cost) pairs") from None
        seen: set[object] = set()
        for name, _ in pairs:
            if name in seen:
                raise UpdateCostError(f"the cost of '{_shown(str(name))}' is given twice")
            seen.add(name)
        checked = as_update_costs(dict(pairs))
        lines = costs.lines if len(costs.lines) == len(pairs) else ()
        return UpdateCosts(checked.costs, lines, costs.source)
    if not isinstance(costs, Mapping):
        raise UpdateCostError(
            "update costs are a mapping from update name to a positive integer, got "
            f"{type(costs).__name__}"
        )
    out: list[tuple[str, int]] = []
    for name, cost in costs.items():
        if not isinstance(name, str):
            raise UpdateCostError(f"an update name is a str, got {type(name).__name__}")
        if isinstance(cost, bool) or not isinstance(cost, int):
            raise UpdateCostError(
                f"the cost of '{_shown(name)}' must be a positive integer, got {cost!r}"
            )
        out.append((name, _check_cost(str(cost), name, None, None)))
    return UpdateCosts(tuple(out), (None,) * len(out), None)


def cost_vector(task, costs: UpdateCosts | Mapping[str, int] | None) -> tuple[int, ...] | None:
    """The cost of every update of ``task.delta`` (1 where none is given), in Delta's order;
    ``None`` without costs.  A name that is not an update of Delta is an error naming where it
    was given."""
    if costs is None:
        return None
    costs = as_update_costs(costs)
    vec = [1] * len(task.delta)
    lines = costs.lines or (None,) * len(costs.costs)
    for (name, cost), lineno in zip(costs.costs, lines, strict=True):
        i = task.update_index.get(name)
        if i is None:
            raise UpdateCostError(
                f"'{_shown(name)}' is not an update of the model difference (see 'mega-sat diff')",
                path=costs.source,
                where=None if lineno is None else f"line {lineno}",
            )
        vec[i] = cost
    return tuple(vec)


def explanation_cost(selection, costs: tuple[int, ...] | None) -> int:
    """The cost of the selection ``selection`` (indices into Delta): ``|E|`` without costs."""
    if costs is None:
        return len(selection)
    return sum(costs[i] for i in selection)


def _check_cost(token: str, name: str, source: str | None, where: str | None) -> int:
    if not _INT.fullmatch(token):
        raise UpdateCostError(
            f"the cost of '{_shown(name)}' must be a positive integer, got '{_shown(token)}' "
            "(a line is an update name followed by its cost)",
            path=source,
            where=where,
        )
    cost = int(token)
    if cost <= 0:
        raise UpdateCostError(
            f"the cost of '{_shown(name)}' must be a positive integer, got {cost}",
            path=source,
            where=where,
        )
    if cost > MAX_COST:
        raise UpdateCostError(
            f"the cost of '{_shown(name)}' is larger than {MAX_COST}", path=source, where=where
        )
    return cost


def _shown(text: str) -> str:
    return text if text.isprintable() else ascii(text)
