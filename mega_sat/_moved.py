"""Old flat module paths (``mega_sat.oracles``, ...) kept importable after the move into
subpackages: importing one gives the module at its new path, with a DeprecationWarning that
names that path.  Names whose old module became a package (``model``, ``search``, ``cli``) are
not listed: their packages answer for themselves."""

from __future__ import annotations

import importlib
import importlib.abc
import importlib.util
import sys
import warnings

MOVED = {
    "pddl_reader": "pddl.reader",
    "pddl_writer": "pddl.writer",
    "planio": "pddl.planio",
    "loading": "pddl.loading",
    "up_models": "pddl.up_models",
    "update_costs": "pddl.update_costs",
    "features": "model.features",
    "task": "model.task",
    "family": "ground.family",
    "grounding": "ground.grounding",
    "atom_table": "ground.atom_table",
    "simulate": "ground.simulate",
    "abstraction": "analysis.abstraction",
    "pair_reachability": "analysis.pair_reachability",
    "invariants": "analysis.invariants",
    "operator_counting": "analysis.operator_counting",
    "cbc": "analysis.cbc",
    "joint_search": "search.joint",
    "plan_reduction": "search.plan_reduction",
    "sat_encoding": "sat.encoding",
    "oracles": "sat.oracles",
    "cnf_export": "sat.cnf_export",
    "symmetry": "sat.symmetry",
    "node_planner": "planners.node_planner",
    "fast_downward": "planners.fast_downward",
    "tiered_opt": "planners.tiered_opt",
    "val": "planners.val",
    "sat_engine": "engines.sat_loop",
    "astar_engine": "engines.astar",
    "mce": "engines.mce",
    "mme": "engines.mme",
    "verify": "engines.verify",
    "hitting_set": "engines.hitting_set",
    "support": "engines.support",
    "progress": "engines.progress",
    "batch": "cli.batch",
    "mmp": "cli.mmp",
    "plotting": "cli.plotting",
    "benchmark": "bench.harness",
    "oracle_bench": "bench.oracle_calls",
    "generate": "bench.generate",
}


class _Loader(importlib.abc.Loader):
    def __init__(self, new: str):
        self.new = new

    def create_module(self, spec):
        return importlib.import_module(self.new)

    def exec_module(self, module) -> None:
        pass


class _Finder(importlib.abc.MetaPathFinder):
    """Answers ``mega_sat.<old>`` with the module at its new path."""

    def find_spec(self, fullname, path=None, target=None):
        prefix, _, old = fullname.partition(".")
        if prefix != "mega_sat" or old not in MOVED:
            return None
        new = f"mega_sat.{MOVED[old]}"
        warnings.warn(f"{fullname} moved to {new}", DeprecationWarning, stacklevel=3)
        return importlib.util.spec_from_loader(fullname, _Loader(new))


def install() -> None:
    if not any(isinstance(f, _Finder) for f in sys.meta_path):
        sys.meta_path.append(_Finder())
