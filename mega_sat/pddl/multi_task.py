"""Several human models of one robot: the task, the union of the model differences, loading.

Each human model ``human_i`` forms its own :class:`~mega_sat.model.task.TwoModelTask` with the robot
model, with its own model difference ``Delta_i``.  An explanation ``E`` draws from the union
``Delta`` of the ``Delta_i`` (an update is identified by its name: the feature and whether the
robot has it, so the same update means the same change in every human model).  Applied to
``human_i`` it changes only what ``human_i`` disagrees on: ``human_i + E`` is
``human_i + (E restricted to Delta_i)``; an update ``human_i`` already agrees with is a no-op.

A ``--task DIR`` folder holds several human models as ``human-1/``, ``human-2/``, ... folders
(:func:`resolve_multi_task_dir`).
"""

from __future__ import annotations

import re
from collections.abc import Iterable, Sequence
from dataclasses import dataclass
from functools import cached_property
from pathlib import Path

from mega_sat.errors import UsageError
from mega_sat.model.features import KIND_ORDER, Update
from mega_sat.model.lifted import Model, has_equality, with_equality
from mega_sat.model.task import Selection, TwoModelTask, explanation_line
from mega_sat.pddl.loading import TASK_FILES, load_task

HUMAN_DIR = re.compile(r"human-(\d+)")
"""The name of a human model's folder inside a task folder."""


def _update_key(u: Update) -> tuple:
    """The canonical order of Delta (as :func:`mega_sat.model.features.model_difference` sorts)."""
    return (KIND_ORDER[u.feature.kind], not u.robot_has, u.feature.action, u.feature.atom)


def _items_of(values: object, kind: type, what: str, each: str) -> list:
    """``values`` as a list whose items are all ``kind``, or one UsageError naming the first
    that is not (a library user's slip, not an AttributeError from inside)."""
    if isinstance(values, str | bytes) or not isinstance(values, Iterable):
        raise UsageError(f"{what} takes a list of {kind.__name__}, got {values!r}")
    items = list(values)
    for k, v in enumerate(items, 1):
        if not isinstance(v, kind):
            raise UsageError(f"{each} {k} is not a {kind.__name__}: {type(v).__name__}")
    return items


@dataclass(frozen=True)
class MultiHumanTask:
    """The robot model, one :class:`TwoModelTask` per human model, and the union ``delta``.

    Selections are frozensets of indices into ``delta``; :meth:`project` maps one to the
    selection of one human model's own task.
    """

    tasks: tuple[TwoModelTask, ...]
    delta: tuple[Update, ...]

    @classmethod
    def from_tasks(cls, tasks: Sequence[TwoModelTask]) -> MultiHumanTask:
        """Several two-model tasks of one robot model (checked) as one task."""
        tasks = tuple(_items_of(tasks, TwoModelTask, "from_tasks", "task"))
        if len(tasks) < 2:
            raise UsageError(f"several human models need at least 2 tasks, got {len(tasks)}")
        if any(has_equality(t.robot) for t in tasks):
            # a pair that uses equality gives its robot (= o o) over that pair's objects: every
            # pair holds it over all objects, so that their robot models agree
            objects = frozenset().union(*(t.robot.objects | t.human.objects for t in tasks))
            tasks = tuple(
                TwoModelTask.from_models(
                    with_equality(t.robot, objects), with_equality(t.human, objects), t.sources
                )
                for t in tasks
            )
        for k, t in enumerate(tasks[1:], 2):
            if t.robot != tasks[0].robot:
                raise UsageError(
                    f"human model {k} is paired with another robot model than human model 1"
                )
        union: dict[str, Update] = {}
        for t in tasks:
            for u in t.delta:
                union.setdefault(u.name, u)
        return cls(tasks, tuple(sorted(union.values(), key=_update_key)))

    @classmethod
    def from_models(
        cls,
        robot: Model,
        humans: Sequence[Model],
        sources: Sequence[dict[str, str]] | None = None,
    ) -> MultiHumanTask:
        """The task of a robot model and several human models (``sources``: file names per
        human model, for messages, as in :meth:`TwoModelTask.from_models`)."""
        if not isinstance(robot, Model):
            raise UsageError(f"from_models takes the robot's Model, got {type(robot).__name__}")
        humans = _items_of(humans, Model, "from_models", "human model")
        srcs = list(sources) if sources is not None else [{} for _ in humans]
        if len(srcs) != len(humans):
            raise UsageError(
                f"sources names {len(srcs)} human model(s), but {len(humans)} are given"
            )
        return cls.from_tasks(
            [TwoModelTask.from_models(robot, h, s) for h, s in zip(humans, srcs, strict=True)]
        )

    @property
    def robot(self) -> Model:
        return self.tasks[0].robot

    @property
    def humans(self) -> tuple[Model, ...]:
        return tuple(t.human for t in self.tasks)

    @property
    def sources(self) -> dict[str, str]:
        """The robot's files and the first human model's (as a one-human task names them)."""
        return self.tasks[0].sources

    @cached_property
    def all_updates(self) -> Selection:
        return frozenset(range(len(self.delta)))

    @cached_property
    def update_index(self) -> dict[str, int]:
        return {u.name: i for i, u in enumerate(self.delta)}

    @cached_property
    def _maps(self) -> tuple[tuple[int | None, ...], ...]:
        """Per human model: union index -> index into that model's own Delta (None: no-op)."""
        out = []
        for t in self.tasks:
            own = t.update_index
            out.append(tuple(own.get(u.name) for u in self.delta))
        return tuple(out)

    def project(self, selection: Iterable[int], i: int) -> Selection:
        """``E`` restricted to ``Delta_i``, as a selection of human model ``i``'s own task."""
        m = self._maps[i]
        return frozenset(m[j] for j in selection if m[j] is not None)

    def human_label(self, i: int) -> str:
        """How messages name human model ``i`` (0-based): its files, or its number."""
        s = self.tasks[i].sources
        files = [s[r] for r in ("human_domain", "human_problem") if r in s]
        return f"human model {i + 1}" + (f" ({', '.join(files)})" if files else "")

    def names(self, selection: Iterable[int]) -> list[str]:
        return [self.delta[i].name for i in sorted(self.check_selection(selection))]

    def check_selection(self, selection: Iterable[int]) -> Selection:
        if isinstance(selection, str | bytes) or not isinstance(selection, Iterable):
            raise UsageError(
                f"a selection is a set of update indices, got {type(selection).__name__}"
            )
        out = set()
        for i in selection:
            if isinstance(i, bool) or not isinstance(i, int) or not 0 <= i < len(self.delta):
                raise UsageError(
                    f"update index {i!r} is not an index of Delta (it has {len(self.delta)})"
                )
            out.add(i)
        return frozenset(out)

    def selection_from_names(self, names: Iterable[str], *, path: str | None = None) -> Selection:
        """Update names (``add-...``/``remove-...`` lines) as a selection of the union."""
        if isinstance(names, str):
            names = names.splitlines()
        out = set()
        for lineno, raw in enumerate(names, 1):
            line = explanation_line(str(raw))
            if not line:
                continue
            if line not in self.update_index:
                raise UsageError(
                    f"'{line}' is not an update of any human model's model difference",
                    path=path,
                    where=f"line {lineno}",
                )
            out.add(self.update_index[line])
        return frozenset(out)

    def updated_model(self, selection: Iterable[int], i: int) -> Model:
        """``human_i + E``."""
        sel = self.check_selection(selection)
        return self.tasks[i].updated_model(self.project(sel, i))


def load_multi_task(
    robot_domain: str | Path,
    robot_problem: str | Path,
    humans: Sequence[tuple[str | Path, str | Path | None]],
) -> MultiHumanTask | TwoModelTask:
    """The task of a robot model and the human models ``humans`` (pairs of domain and problem
    file; a problem ``None`` defaults to the robot problem).  One pair gives the ordinary
    :class:`TwoModelTask`, so one human model always takes the one-human path."""
    if isinstance(humans, str | Path) or not humans:
        raise UsageError("load_multi_task: humans must be a non-empty list of (domain, problem)")
    tasks = []
    for k, pair in enumerate(humans, 1):
        if not isinstance(pair, tuple | list) or len(pair) != 2:
            raise UsageError(f"load_multi_task: human model {k} is not a (domain, problem) pair")
        tasks.append(load_task(robot_domain, robot_problem, pair[0], pair[1]))
    return tasks[0] if len(tasks) == 1 else MultiHumanTask.from_tasks(tasks)


def pair_cli_files(
    human_domains: Sequence[str], human_problems: Sequence[str]
) -> list[tuple[str, str | None]]:
    """Pair repeated ``--human-domain``/``--human-problem`` options in order.

    One ``--human-domain`` with several ``--human-problem`` shares the domain; several domains
    need as many problems (or none: each human problem is then the robot problem)."""
    nd, np_ = len(human_domains), len(human_problems)
    if nd == 1:
        return [(human_domains[0], p) for p in human_problems] or [(human_domains[0], None)]
    if np_ == 0:
        return [(d, None) for d in human_domains]
    if nd != np_:
        raise UsageError(
            f"{nd} --human-domain and {np_} --human-problem options: give one "
            "--human-problem per --human-domain (paired in order), or one --human-domain "
            "shared by every --human-problem"
        )
    return list(zip(human_domains, human_problems, strict=True))


def human_dirs(task_dir: str | Path) -> list[Path]:
    """The ``human-K`` folders of a task folder, in order of K (empty: none)."""
    d = Path(task_dir)
    if not d.is_dir():
        return []
    found: dict[int, Path] = {}
    for c in sorted(d.iterdir()):
        m = HUMAN_DIR.fullmatch(c.name)
        if m and c.is_dir():
            k = int(m.group(1))
            if k in found:  # human-1 and human-01: which one is meant is a guess
                raise UsageError(
                    f"{found[k].name}/ and {c.name}/ both number human model {k}", path=str(d)
                )
            found[k] = c
    return [found[k] for k in sorted(found)]


def resolve_multi_task_dir(task_dir: str | Path) -> dict:
    """The files of a task folder with ``human-1/``, ``human-2/``, ... folders.

    ``DIR`` holds ``robot-problem.pddl``; ``robot-domain.pddl`` is looked for in ``DIR`` and
    then its parent.  Each ``human-K/`` holds ``human-problem.pddl``; its
    ``human-domain.pddl`` is looked for in ``human-K/``, then ``DIR``, then ``DIR``'s parent
    (so human models that share a domain name it once).  The folders are numbered 1, 2, ...
    without gaps.  Returns ``robot_domain``, ``robot_problem`` and ``humans`` (a list of
    ``(domain, problem)``)."""
    from mega_sat.pddl.reader import as_path

    d = as_path(task_dir, "task folder")
    if not d.is_dir():
        raise UsageError(
            "is not a folder (--task takes a task folder)"
            if d.exists()
            else "task directory not found",
            path=str(d),
        )
    dirs = human_dirs(d)
    if not dirs:
        raise UsageError("no human-1/, human-2/, ... folders in the task directory", path=str(d))
    for k, h in enumerate(dirs, 1):
        if h.name != f"human-{k}":
            raise UsageError(
                f"the human model folders are numbered 1, 2, ... without gaps: expected "
                f"human-{k}, found {h.name}",
                path=str(d),
            )
    if (d / TASK_FILES["human_problem"]).is_file():
        raise UsageError(
            f"both {TASK_FILES['human_problem']} and human-K folders: put each human "
            "model's problem in its own human-K folder",
            path=str(d),
        )
    robot_problem = d / TASK_FILES["robot_problem"]
    if not robot_problem.is_file():
        raise UsageError(f"no {TASK_FILES['robot_problem']} in the task directory", path=str(d))
    robot_domain = _first_file(
        TASK_FILES["robot_domain"], [d, d.parent], str(d), "the task directory or its parent"
    )
    humans = []
    for h in dirs:
        problem = h / TASK_FILES["human_problem"]
        if not problem.is_file():
            raise UsageError(f"no {TASK_FILES['human_problem']} in {h.name}/", path=str(h))
        domain = _first_file(
            TASK_FILES["human_domain"],
            [h, d, d.parent],
            str(h),
            f"{h.name}/, the task directory or its parent",
        )
        humans.append((domain, problem))
    return {"robot_domain": robot_domain, "robot_problem": robot_problem, "humans": humans}


def _first_file(name: str, folders: list[Path], path: str, where: str) -> Path:
    for f in folders:
        if (f / name).is_file():
            return f / name
    raise UsageError(f"no {name} in {where}", path=path)


def load_multi_task_dir(task_dir: str | Path) -> MultiHumanTask | TwoModelTask:
    """The task of a folder with ``human-K/`` folders (see :func:`resolve_multi_task_dir`);
    a single ``human-1/`` gives the ordinary :class:`TwoModelTask`."""
    paths = resolve_multi_task_dir(task_dir)
    return load_multi_task(paths["robot_domain"], paths["robot_problem"], paths["humans"])


def load_cli_task(
    task_dir: str | None,
    robot_domain: str | None,
    robot_problem: str | None,
    human_domains: Sequence[str],
    human_problems: Sequence[str],
    *,
    several: bool,
) -> MultiHumanTask | TwoModelTask | None:
    """The task of the CLI's options when they name several human models (repeated
    ``--human-domain``/``--human-problem``, or ``human-K`` folders), else ``None`` (the
    one-human loader takes over).  ``several``: whether the command accepts several; if not,
    several human models are a :class:`UsageError`."""
    if task_dir:
        if not human_dirs(task_dir):
            return None
        if any((robot_domain, robot_problem, human_domains, human_problems)):
            raise UsageError("give either --task DIR or the model files, not both")
        task = load_multi_task_dir(task_dir)
    else:
        if len(human_domains) <= 1 and len(human_problems) <= 1:
            return None
        if not (robot_domain and robot_problem and human_domains):
            missing = [
                n
                for n, v in (
                    ("--robot-domain", robot_domain),
                    ("--robot-problem", robot_problem),
                    ("--human-domain", human_domains),
                )
                if not v
            ]
            raise UsageError(f"missing {', '.join(missing)} (or give --task DIR)")
        pairs = pair_cli_files(human_domains, human_problems)
        task = load_multi_task(robot_domain, robot_problem, pairs)
    if isinstance(task, MultiHumanTask) and not several:
        raise UsageError(
            f"{len(task.tasks)} human models given: only 'solve' and 'frontier' take several "
            "human models"
        )
    return task
