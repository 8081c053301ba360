"""``mega-sat mmp``: a drop-in for the command line of the original MEGA code (``Explainer.py``).

The original tool takes its models as ``-m`` (robot domain), ``-n`` (human domain), ``-p`` /
``-q`` (robot / human problem), a search ``-s`` and an ``alpha``; it prints ``Explanation >>``
lines and leaves ``exp.dat`` and ``final_plan.sol`` in the working directory.  Here each search
is answered by mega-sat's exact engines:

* ``EE``: MEGA at ``-a ALPHA`` (the plan and explanation chosen from the frontier);
* ``ME``: the MCE of the ``-f`` plan (default: a robot-optimal plan);
* ``MCE``: the original's monotonic search, i.e. the MME of that plan.

Flags the original needs for its own machinery (templates, approximations, heuristics,
grounding) are accepted, and each says once on stderr what it does here.
"""

from __future__ import annotations

from dataclasses import dataclass
from pathlib import Path

from mega_sat.errors import UsageError
from mega_sat.model.lifted import PlanStep, step_str
from mega_sat.output import check_target, write_file

SEARCHES = ("EE", "ME", "MCE")

IGNORED_FLAGS = {
    "tmodel": "-t/--tmodel is not needed: mega-sat reads the two domains (-m, -n) directly",
    "tproblem": "-r/--tproblem is not needed: mega-sat reads the problems (-p, -q) directly",
    "approx": "--approx has no effect: mega-sat's answers are exact",
    "heuristic": "--heuristic has no effect: mega-sat's search needs no heuristic to be exact",
    "ground": "--ground has no effect: mega-sat's updates are lifted features of the schemas, "
    "each one covering every grounding",
}

EXPLANATION_FILE = "exp.dat"
PLAN_FILE = "final_plan.sol"
PLAN_MARK = "; written by mega-sat mmp"


@dataclass(frozen=True)
class MmpAnswer:
    """What one ``mmp`` run prints and writes."""

    search: str
    explanation: tuple[str, ...]
    plan: tuple[PlanStep, ...]
    robot_cost: int
    robot_optimal_cost: int | None
    exact: bool
    summary: str

    def explanation_lines(self) -> list[str]:
        return [f"Explanation >> {e}" for e in self.explanation]


def _ours(path: Path) -> bool:
    """Whether ``path`` holds an earlier answer of this command (which it may replace)."""
    try:
        text = path.read_text(encoding="utf-8")
    except (OSError, UnicodeDecodeError):
        return False
    if path.name == PLAN_FILE:
        return PLAN_MARK in text
    return all(not line.strip() or line.startswith("Explanation >> ") for line in text.split("\n"))


def check_outputs(folder: Path, force: bool) -> tuple[Path, Path]:
    """``exp.dat`` and ``final_plan.sol`` in ``folder``, checked before any solving: an earlier
    answer of this command is replaced, any other file of those names only with ``force``."""
    paths = (folder / EXPLANATION_FILE, folder / PLAN_FILE)
    for p in paths:
        if p.exists() and not p.is_dir() and not force and not _ours(p):
            raise UsageError(
                "exists and is not an earlier answer of mega-sat mmp (use --force to replace it)",
                path=str(p),
            )
        check_target(p, force=True)
    return paths


def write_outputs(answer: MmpAnswer, paths: tuple[Path, Path]) -> None:
    exp, plan = paths
    lines = answer.explanation_lines()
    write_file(exp, "\n".join(lines) + ("\n" if lines else ""), force=True)
    steps = [step_str(s) for s in answer.plan]
    write_file(
        plan,
        "\n".join([*steps, f"; cost = {answer.robot_cost} (general cost)", PLAN_MARK]) + "\n",
        force=True,
    )


def answer(solver, search: str, alpha: float | None, plan: list[PlanStep] | None) -> MmpAnswer:
    """Run ``search`` with a :class:`mega_sat.api.MegaSolver`."""
    search = search.upper()
    if search == "EE":
        if alpha is None:
            raise UsageError("-s EE needs -a/--alpha (the price of one unit of extra robot cost)")
        sol = solver.solve(alpha)
        p, fr = sol.chosen, sol.frontier
        done = "exact" if fr.exact else "not proven exact: " + "; ".join(fr.notes)
        return MmpAnswer(
            "EE",
            p.explanation,
            p.plan,
            p.robot_cost,
            fr.robot_optimal_cost,
            fr.exact,
            f"EE (MEGA) at alpha {alpha:g}: |E| = {p.size}, robot cost {p.robot_cost} "
            f"(optimal {fr.robot_optimal_cost}), objective {sol.objective:g}; {done}",
        )
    kind = {"ME": "mce", "MCE": "mme"}[search]
    e = solver.explain(plan, kind=kind)
    done = "exact" if e.exact else "not proven minimal: " + "; ".join(e.notes)
    return MmpAnswer(
        search,
        e.explanation,
        e.plan,
        e.robot_cost,
        None,
        e.exact,
        f"{search} ({kind.upper()} of a {len(e.plan)}-step plan of robot cost {e.robot_cost}): "
        f"|E| = {len(e.explanation)}; {done}",
    )
