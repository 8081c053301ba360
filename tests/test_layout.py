"""The package layout: stages import only downward, and old flat module paths still work."""

from __future__ import annotations

import ast
import importlib
import warnings
from pathlib import Path

import pytest

import mega_sat
from mega_sat._moved import MOVED

PACKAGE = Path(mega_sat.__file__).parent
# the pipeline, lowest first: a module may import from its own stage or one listed before it
STAGES = [
    "errors",
    "status",
    "options",
    "deadline",
    "output",
    "executor",
    "_moved",
    "model",
    "pddl",
    "ground",
    "analysis",
    "search",
    "sat",
    "planners",
    "results",
    "engines",
    "api",
    "bench",
    "cli",
]


def _stage(path: Path) -> str:
    rel = path.relative_to(PACKAGE).parts
    return rel[0].removesuffix(".py")


def test_every_import_runs_down_the_pipeline():
    rank = {name: i for i, name in enumerate(STAGES)}
    upward = []
    for path in PACKAGE.rglob("*.py"):
        me = _stage(path)
        if me == "__init__":
            continue
        assert me in rank, f"{path} is in no stage of the pipeline"
        for node in ast.walk(ast.parse(path.read_text())):
            if isinstance(node, ast.ImportFrom) and (node.module or "").startswith("mega_sat."):
                target = node.module.split(".")[1]
                if rank.get(target, -1) > rank[me]:
                    upward.append(f"{path.relative_to(PACKAGE)} -> {node.module}")
    assert sorted(set(upward)) == []


@pytest.mark.parametrize("old", sorted(MOVED))
def test_old_flat_path_warns_and_gives_the_moved_module(old):
    new = importlib.import_module(f"mega_sat.{MOVED[old]}")
    with warnings.catch_warnings(record=True) as caught:
        warnings.simplefilter("always")
        import sys

        sys.modules.pop(f"mega_sat.{old}", None)
        got = importlib.import_module(f"mega_sat.{old}")
    assert got is new
    assert any(
        issubclass(w.category, DeprecationWarning) and f"mega_sat.{MOVED[old]}" in str(w.message)
        for w in caught
    )


def test_model_package_keeps_its_names():
    from mega_sat.model import Model, PlanStep, step_str

    assert Model.__module__ == "mega_sat.model.lifted"
    assert step_str(("move", "a", "b")) == "(move a b)"
    assert PlanStep == tuple[str, ...]


def test_options_parse_key_value_pairs_and_refuse_bad_ones():
    from mega_sat.errors import UsageError
    from mega_sat.options import Options

    got = Options().with_pairs(["horizon_cap=50", "step-first=false", "counting_time_limit=0.5"])
    assert (got.horizon_cap, got.step_first, got.counting_time_limit) == (50, False, 0.5)
    assert Options().horizon_cap == 200
    for bad, words in [
        ("horizon_cap", "expected key=value"),
        ("nope=1", "unknown option 'nope'"),
        ("horizon_cap=x", "expected a number"),
        ("horizon_cap=0", "must be positive"),
        ("plan_below_robot_conflicts=-1", "must be 0 or more"),
        ("step_first=maybe", "expected true or false"),
    ]:
        with pytest.raises(UsageError, match=words):
            Options().with_pairs([bad])
    # 0 only where the option's doc says what it means ("0: never")
    assert Options().with_pairs(["plan_below_robot_conflicts=0"]).plan_below_robot_conflicts == 0
    assert all(doc for _, _, doc in Options.docs())


def test_status_reads_as_its_word():
    import json

    from mega_sat.status import Status

    assert f"{Status.OPTIMAL}" == "optimal" == Status.OPTIMAL
    assert json.dumps([Status.INFEASIBLE]) == '["infeasible"]'
    assert not Status.TIMEOUT.decided and Status.UNSOLVABLE.decided


def _third_party_imports() -> set[str]:
    import sys

    found = set()
    for path in PACKAGE.rglob("*.py"):
        for node in ast.walk(ast.parse(path.read_text())):
            if isinstance(node, ast.Import):
                names = [a.name for a in node.names]
            elif isinstance(node, ast.ImportFrom) and node.level == 0 and node.module:
                names = [node.module]
            else:
                continue
            for name in names:
                top = name.split(".")[0]
                if top not in sys.stdlib_module_names and top != "mega_sat":
                    found.add(top)
    return found


def test_declared_dependencies_match_the_imports():
    import re

    tomllib = pytest.importorskip("tomllib")  # Python 3.11+

    project = tomllib.loads((PACKAGE.parent / "pyproject.toml").read_text())["project"]
    declared = {re.split(r"[<>=!\[ ]", d)[0].lower() for d in project["dependencies"]}
    extras = {
        re.split(r"[<>=!\[ ]", d)[0].lower()
        for group in project["optional-dependencies"].values()
        for d in group
    }
    distribution = {"pysat": "python-sat", "unified_planning": "unified-planning"}
    imported = {distribution.get(m, m) for m in _third_party_imports()}
    # every import is declared, core or extra; every core dependency is imported
    assert imported - declared - extras == set()
    assert declared - imported == set()


def test_a_small_frontier_imports_neither_numpy_nor_pulp():
    """numpy (about 60 ms to import) and PuLP (about 35 ms) are imported by the code that
    needs them, so a task that needs neither starts as fast as the A* baseline."""
    import subprocess
    import sys

    task = PACKAGE.parent / "domains" / "usar-fetch" / "delta" / "2" / "p2"
    code = (
        "import sys\n"
        "from mega_sat.api import MegaSolver\n"
        "from mega_sat.pddl.loading import load_task_dir\n"
        f"f = MegaSolver(load_task_dir({str(task)!r})).frontier()\n"
        "assert f.exact and f.points, f\n"
        "print(sorted(m for m in ('numpy', 'pulp') if m in sys.modules))\n"
    )
    out = subprocess.run([sys.executable, "-c", code], capture_output=True, text=True, check=True)
    assert out.stdout.strip() == "[]"
