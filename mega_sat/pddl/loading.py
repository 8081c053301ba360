"""Load a two-model task from PDDL files, strings, or a ``--task DIR`` directory.

The file paths travel with the task (``TwoModelTask.sources``) so that a later message, e.g. a
:class:`~mega_sat.errors.ModelMismatchError` about an arity, names the files involved.
"""

from __future__ import annotations

import re
from pathlib import Path

from mega_sat.errors import ModelMismatchError, PDDLError, UsageError
from mega_sat.model.lifted import Model
from mega_sat.model.task import TwoModelTask
from mega_sat.pddl.reader import PDDLWarning, parse_model, read_text

TASK_FILES = {
    "robot_domain": "robot-domain.pddl",
    "robot_problem": "robot-problem.pddl",
    "human_domain": "human-domain.pddl",
    "human_problem": "human-problem.pddl",
}
"""The file names ``--task DIR`` looks for, by role."""


def load_task(
    robot_domain: str | Path,
    robot_problem: str | Path,
    human_domain: str | Path,
    human_problem: str | Path | None = None,
) -> TwoModelTask:
    """Read the four files (the human problem defaults to the robot problem) into a task."""
    _check_args(
        "load_task",
        "a file path",
        (str, Path),
        robot_domain=robot_domain,
        robot_problem=robot_problem,
        human_domain=human_domain,
        human_problem=human_problem,
    )
    for role, p in (
        ("robot_domain", robot_domain),
        ("robot_problem", robot_problem),
        ("human_domain", human_domain),
        ("human_problem", human_problem),
    ):
        if p == role:
            raise UsageError(
                f"load_task: got the name '{role}' instead of a path (pass the dict of "
                "resolve_task_dir as load_task(**paths), or use load_task_dir)"
            )
        if isinstance(p, str) and ("(" in p or "\n" in p):
            raise UsageError(
                f"load_task: {role} looks like PDDL text, not a file path "
                "(use load_task_from_strings for PDDL texts)"
            )
    paths = {
        "robot_domain": str(robot_domain),
        "robot_problem": str(robot_problem),
        "human_domain": str(human_domain),
        "human_problem": str(human_problem if human_problem is not None else robot_problem),
    }
    texts = {role: read_text(p, role.replace("_", " ")) for role, p in paths.items()}
    return task_from_texts(texts, paths)


def load_task_from_strings(
    robot_domain: str,
    robot_problem: str,
    human_domain: str,
    human_problem: str | None = None,
) -> TwoModelTask:
    """Like :func:`load_task` for PDDL texts; messages name them 'robot domain' and so on."""
    _check_args(
        "load_task_from_strings",
        "PDDL text (a str)",
        (str,),
        robot_domain=robot_domain,
        robot_problem=robot_problem,
        human_domain=human_domain,
        human_problem=human_problem,
    )
    texts = {
        "robot_domain": robot_domain,
        "robot_problem": robot_problem,
        "human_domain": human_domain,
        "human_problem": human_problem if human_problem is not None else robot_problem,
    }
    names = {role: role.replace("_", " ") for role in texts}
    return task_from_texts(texts, names)


def _check_args(fn: str, expected: str, types: tuple[type, ...], **args: object) -> None:
    """A clear error for an argument of the wrong type (the human problem may be None)."""
    for role, value in args.items():
        if value is None and role == "human_problem":
            continue
        if not isinstance(value, types):
            raise UsageError(f"{fn}: {role} must be {expected}, got {type(value).__name__}")


def task_from_texts(texts: dict[str, str], names: dict[str, str]) -> TwoModelTask:
    """The task of four PDDL texts; ``names`` says how messages name each of them."""
    robot = parse_model(
        texts["robot_domain"],
        texts["robot_problem"],
        domain_path=names["robot_domain"],
        problem_path=names["robot_problem"],
    )
    try:
        human = parse_model(
            texts["human_domain"],
            texts["human_problem"],
            domain_path=names["human_domain"],
            problem_path=names["human_problem"],
            borrowed_problem=texts["human_problem"] == texts["robot_problem"],
        )
    except PDDLError as e:
        if e.path != names["human_problem"] or names["human_problem"] != names["robot_problem"]:
            raise
        # the robot problem read as the human's (no human problem given): say so, since the
        # same file was just read without fault as the robot's
        raise PDDLError(
            f"{e.message} (read as the human problem, with {names['human_domain']}: give "
            "the human's own problem if it differs)",
            path=e.path,
            where=e.where,
        ) from None
    _warn_permuted_parameters(robot, human, names)
    try:
        return TwoModelTask.from_models(robot, human, sources=dict(names))
    except ModelMismatchError as e:
        role, kind, key = e.anchor or (None, None, ())
        line = _line_of(texts.get(role, ""), kind, key) if role else None
        if line is None:
            raise
        raise ModelMismatchError(e.message, path=names[role], where=f"line {line}") from None


def line_in_file(path: str | None, kind: str, key: tuple[str, ...]) -> int | None:
    """:func:`_line_of` for a PDDL file named by a model's ``sources`` entry; None when there
    is no such file (a model read from strings) or the place is not found.  For errors found
    after loading, such as in grounding, whose input no longer carries the text."""
    if path is None or not Path(path).is_file():
        return None
    try:
        text = Path(path).read_text(encoding="utf-8", errors="replace")
    except OSError:
        return None
    return _line_of(text, kind, key)


def _line_of(text: str, kind: str, key: tuple[str, ...]) -> int | None:
    """The line where ``text`` (PDDL) declares the action, predicate or function ``key``,
    gives the cost function value ``key``, declares the object ``key`` or opens ``:init``
    (``kind``: action, predicate, function, value, object or init); None if not found."""
    from mega_sat.pddl.sexpr import normalise_text

    text = normalise_text(text)
    start = 0
    if kind == "action":
        pattern = r"\(\s*:action\s+" + re.escape(key[0]) + r"(?=[\s()])"
    elif kind in ("predicate", "function"):
        start = max(text.find(f":{kind}s"), 0)
        pattern = r"\(\s*" + re.escape(key[0]) + r"(?=[\s()])"
    elif kind == "object":
        start = text.find(":objects")
        if start < 0:
            return None
        pattern = r"(?<![^\s()])" + re.escape(key[0].lower()) + r"(?=[\s()])"
    elif kind == "init":
        pattern = r"\(\s*:init(?=[\s()])"
    else:
        pattern = r"\(\s*=\s*\(\s*" + r"\s+".join(map(re.escape, key)) + r"\s*\)"
    m = re.compile(pattern).search(text, start)
    return None if m is None else text.count("\n", 0, m.start()) + 1


def _warn_permuted_parameters(robot: Model, human: Model, names: dict[str, str]) -> None:
    """A warning for a shared action whose parameter types the human's domain lists in another
    order: parameters are matched by position, so the types and every atom that mentions them
    become differences, which is rarely what the author meant."""
    import warnings

    for name in sorted(set(robot.schemas) & set(human.schemas)):
        rt, ht = robot.schemas[name].param_types(), human.schemas[name].param_types()
        if len(rt) == len(ht) and rt != ht and sorted(rt) == sorted(ht):
            warnings.warn(
                PDDLWarning(
                    f"{names['human_domain']}: action '{name}' has parameters of the types "
                    f"({' '.join(t or 'object' for t in ht)}) where {names['robot_domain']} has "
                    f"({' '.join(t or 'object' for t in rt)}): parameters are matched by "
                    "position, so their types and the atoms that use them differ"
                ),
                stacklevel=2,
            )


def load_task_dir(d: str | Path) -> TwoModelTask:
    """The task of a ``--task DIR`` folder (see :func:`resolve_task_dir`)."""
    return load_task(**resolve_task_dir(d))


def resolve_task_dir(d: str | Path) -> dict[str, Path]:
    """The four files of a ``--task DIR`` directory, keyed like :func:`load_task`'s arguments.

    ``DIR`` holds ``robot-problem.pddl`` and optionally ``human-problem.pddl`` (default: the
    robot problem); the two domain files are looked for in ``DIR`` and then in its parent, so
    several problems can share one pair of domains.
    """
    from mega_sat.pddl.reader import as_path

    task_dir = as_path(d, "task folder")
    if not task_dir.is_dir():
        raise UsageError(
            "is not a folder (--task takes a task folder)"
            if task_dir.exists()
            else "task directory not found",
            path=str(task_dir),
        )
    if any(c.is_dir() and re.fullmatch(r"human-\d+", c.name) for c in task_dir.iterdir()):
        # several human models: loading one of them here would silently drop the others
        raise UsageError(
            "the task directory holds human-K folders (several human models): load it with "
            "mega_sat.pddl.multi_task.load_multi_task_dir; of the commands, only 'solve' and "
            "'frontier' take several human models",
            path=str(d),
        )
    out: dict[str, Path] = {}
    robot_problem = task_dir / TASK_FILES["robot_problem"]
    if not robot_problem.is_file():
        raise UsageError(f"no {TASK_FILES['robot_problem']} in the task directory", path=str(d))
    out["robot_problem"] = robot_problem
    for role in ("robot_domain", "human_domain"):
        candidates = [task_dir / TASK_FILES[role], task_dir.parent / TASK_FILES[role]]
        found = next((c for c in candidates if c.is_file()), None)
        if found is None:
            raise UsageError(
                f"no {TASK_FILES[role]} in the task directory or its parent "
                f"(looked for {candidates[0]} and {candidates[1]})",
                path=str(d),
            )
        out[role] = found
    human_problem = task_dir / TASK_FILES["human_problem"]
    out["human_problem"] = human_problem if human_problem.is_file() else robot_problem
    return {role: out[role] for role in TASK_FILES}
