"""Which instances make up each benchmark suite, which runs each instance gets, and the one loop
that generates the Delta-k instances of the paper and scaling grids.

Suites (``mega-sat bench --suite``):

* ``paper``   — every ``domains/<name>/delta/<K>/<pN>`` at Delta = 2, 7, 10, both engines;
* ``scaling`` — the same at Delta = 15, 20, 30;
* ``sweep``   — one ``sat`` frontier per base problem ``domains/<name>/<pN>``, re-scored for
  every alpha of :data:`ALPHA_GRID`;
* ``smoke``   — one small base problem, both engines;
* ``missing-schemas`` — ``domains/missing-schemas/<name>/<pN>``, both engines, the ``sat``
  engine in its default configuration;
* ``all``     — paper + scaling + sweep.
"""

from __future__ import annotations

import fnmatch
import time
from collections.abc import Iterable, Iterator, Sequence
from dataclasses import dataclass
from pathlib import Path
from typing import Any

from mega_sat.bench.common import problem_key
from mega_sat.bench.generate import (
    DEFAULT_TIME_BUDGET,
    Generated,
    instance_seed,
    write_instance,
)

SUITES = ("paper", "scaling", "sweep", "smoke", "missing-schemas", "all")
PAPER_DELTAS = (2, 7, 10)
SCALING_DELTAS = (15, 20, 30)
ALPHA_GRID = (0, 0.05, 0.1, 0.2, 0.3, 0.5, 0.75, 1, 1.5, 2, 3, 5, 10)
DEFAULT_LIMITS = {
    "paper": 300.0,
    "scaling": 60.0,
    "sweep": 300.0,
    "smoke": 60.0,
    "missing-schemas": 60.0,
}
# the folder under the domains root that holds the missing-schemas suite's domains; it has no
# robot-domain.pddl itself, so the other suites' discovery (and generate-suite) skip it
MISSING_SCHEMAS_DIR = "missing-schemas"
# what the missing-schemas suite is read against: every frontier exact within this many
# seconds, and the median frontier time within this multiple of one FD call on the robot model
MISSING_SCHEMAS_TARGET_S = 10.0
MISSING_SCHEMAS_TARGET_RATIO = 20.0
SMOKE_INSTANCE = ("usar-fetch", "p1")
ENGINES = ("astar", "sat")


# --------------------------------------------------------------------------- instances


@dataclass(frozen=True)
class Instance:
    """One task folder in one suite; ``delta`` is None for base problems."""

    suite: str
    domain: str
    problem: str
    delta: int | None
    task_dir: str

    @property
    def label(self) -> str:
        d = "" if self.delta is None else f"/delta{self.delta}"
        return f"{self.domain}{d}/{self.problem}"


def is_task_dir(p: Path) -> bool:
    """A folder ``--task`` accepts (it holds ``robot-problem.pddl``)."""
    return (p / "robot-problem.pddl").is_file()


def domain_dirs(root: Path) -> list[Path]:
    """The domain folders under ``root``: those with a ``robot-domain.pddl``."""
    return sorted(d for d in root.iterdir() if (d / "robot-domain.pddl").is_file())


def _problem_dirs(d: Path) -> list[Path]:
    return sorted(p for p in d.iterdir() if is_task_dir(p))


def matches(domain: str, problem: str, only: Sequence[str], delta: int | None = None) -> bool:
    """``--only`` patterns (fnmatch) match the domain name, ``domain/problem`` or, for a
    generated instance, ``domain/delta/K/problem``."""
    if not only:
        return True
    names = [domain, f"{domain}/{problem}"]
    if delta is not None:
        names.append(f"{domain}/delta/{delta}/{problem}")
    return any(fnmatch.fnmatch(n, o) for n in names for o in only)


def suite_deltas(suite: str) -> tuple[int, ...]:
    """The Delta sizes a suite's generated instances have (none for base problems)."""
    return {
        "paper": PAPER_DELTAS,
        "scaling": SCALING_DELTAS,
        "all": PAPER_DELTAS + SCALING_DELTAS,
    }.get(suite, ())


def discover(root: Path, suite: str, only: Sequence[str] = ()) -> list[Instance]:
    """The instances of one suite found on disk (generated Delta-k folders only)."""
    out: list[Instance] = []
    if suite == "missing-schemas":
        base = root / MISSING_SCHEMAS_DIR
        for d in domain_dirs(base) if base.is_dir() else []:
            for p in sorted(_problem_dirs(d), key=lambda p: problem_key(p.name)):
                if matches(d.name, p.name, only):
                    out.append(Instance(suite, d.name, p.name, None, str(p)))
        return out
    for d in domain_dirs(root):
        if suite in ("sweep", "smoke"):
            for p in _problem_dirs(d):
                if matches(d.name, p.name, only):
                    out.append(Instance(suite, d.name, p.name, None, str(p)))
            continue
        for k in PAPER_DELTAS if suite == "paper" else SCALING_DELTAS:
            kd = d / "delta" / str(k)
            if not kd.is_dir():
                continue
            for p in _problem_dirs(kd):
                if matches(d.name, p.name, only, k):
                    out.append(Instance(suite, d.name, p.name, k, str(p)))
    if suite == "smoke":
        want = [i for i in out if (i.domain, i.problem) == SMOKE_INSTANCE]
        out = want or out[:1]
    return out


def expected_but_missing(root: Path, suite: str, only: Sequence[str] = ()) -> list[Instance]:
    """Delta-k instances the grid calls for whose folder is absent (not generated / failed)."""
    if suite not in ("paper", "scaling"):
        return []
    missing = []
    for d in domain_dirs(root):
        for p in _problem_dirs(d):
            for k in suite_deltas(suite):
                target = d / "delta" / str(k) / p.name
                if matches(d.name, p.name, only, k) and not is_task_dir(target):
                    missing.append(Instance(suite, d.name, p.name, k, str(target)))
    return missing


# --------------------------------------------------------------------------- runs


@dataclass(frozen=True)
class Job:
    """One engine run on one instance (:func:`mega_sat.bench.runner.run_job`)."""

    instance: Instance
    engine: str
    planner: str | None
    time_limit: float
    alphas: tuple[float, ...] = ()


def plan_jobs(
    root: Path, suite: str, only: Sequence[str], time_limit: float | None, baseline: str
) -> list[Job]:
    """Every run of a suite: ``time_limit`` (else the suite's default) per run, ``baseline``
    the planner of the astar baseline."""
    suites = ("paper", "scaling", "sweep") if suite == "all" else (suite,)
    jobs: list[Job] = []
    for s in suites:
        limit = time_limit if time_limit is not None else DEFAULT_LIMITS[s]
        for inst in discover(root, s, only):
            if s == "sweep":
                jobs.append(Job(inst, "sat", None, limit, tuple(ALPHA_GRID)))
            elif s == "missing-schemas":
                # the baseline as in the paper grid; the sat engine as a user runs it
                jobs.append(Job(inst, "astar", baseline, limit))
                jobs.append(Job(inst, "sat", None, limit))
            else:
                # same kind of optimal planner on candidate models for both engines: the
                # baseline's per-node planner is the sat engine's OPT planner (JOINT is SAT)
                jobs.append(Job(inst, "astar", baseline, limit))
                jobs.append(Job(inst, "sat", baseline, limit))
    return jobs


# --------------------------------------------------------------------------- generation


@dataclass(frozen=True)
class Draw:
    """One instance :func:`generate_suite` tried to write.

    ``entry`` is its line in ``results.json`` → ``generation``: ``domain``, ``problem``,
    ``delta``, ``status`` (``ok`` with ``attempts``, or ``failed`` with ``error``) and
    ``seconds``.  ``generated`` is the written human model and its updates, ``error`` the
    exception of a failed draw."""

    out: Path
    entry: dict[str, Any]
    generated: Generated | None = None
    error: Exception | None = None


def generate_suite(
    root: Path,
    deltas: Iterable[int],
    seed: int = 0,
    only: Sequence[str] = (),
    *,
    overwrite: bool = False,
    keep_existing: bool = False,
    time_budget: float = DEFAULT_TIME_BUDGET,
) -> Iterator[Draw]:
    """Write ``<domain>/delta/<K>/<pN>/`` for every base problem under ``root`` and every K of
    ``deltas``, with a seed per instance derived from ``seed``, so the whole grid is
    reproducible from one number.  A draw that fails is reported and the loop goes on, so one
    unsolvable instance does not leave the rest of the grid empty.

    ``keep_existing`` passes over folders that already hold a task, without a :class:`Draw`;
    otherwise an existing folder is a failed draw unless ``overwrite``."""
    ks = list(deltas)
    for d in domain_dirs(root):
        for p in _problem_dirs(d):
            if not matches(d.name, p.name, only):
                continue
            for k in ks:
                out = d / "delta" / str(k) / p.name
                if keep_existing and is_task_dir(out) and (out / "human-domain.pddl").is_file():
                    continue
                t0 = time.perf_counter()
                entry: dict[str, Any] = {"domain": d.name, "problem": p.name, "delta": k}
                g, error = None, None
                try:
                    g = write_instance(
                        d / "robot-domain.pddl",
                        p / "robot-problem.pddl",
                        k,
                        instance_seed(seed, d.name, p.name, k),
                        out,
                        overwrite=overwrite,
                        time_budget=time_budget,
                    )
                    entry.update(status="ok", attempts=g.attempts)
                except Exception as e:  # noqa: BLE001 - reported in the Draw, by design
                    error = e
                    entry.update(status="failed", error=f"{type(e).__name__}: {e}")
                entry["seconds"] = round(time.perf_counter() - t0, 3)
                yield Draw(out, entry, g, error)


def generate_missing(
    root: Path, deltas: Iterable[int], seed: int = 0, only: Sequence[str] = ()
) -> list[dict[str, Any]]:
    """``mega-sat bench --generate``: :func:`generate_suite` over the absent folders only (the
    same per-instance seeds as ``mega-sat generate-suite``); one entry per attempt."""
    return [draw.entry for draw in generate_suite(root, deltas, seed, only, keep_existing=True)]


__all__ = [
    "ALPHA_GRID",
    "DEFAULT_LIMITS",
    "ENGINES",
    "MISSING_SCHEMAS_DIR",
    "MISSING_SCHEMAS_TARGET_RATIO",
    "MISSING_SCHEMAS_TARGET_S",
    "PAPER_DELTAS",
    "SCALING_DELTAS",
    "SMOKE_INSTANCE",
    "SUITES",
    "Draw",
    "Instance",
    "Job",
    "discover",
    "domain_dirs",
    "expected_but_missing",
    "generate_missing",
    "generate_suite",
    "is_task_dir",
    "matches",
    "plan_jobs",
    "suite_deltas",
]
