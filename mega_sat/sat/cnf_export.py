"""DIMACS export of the OPT and JOINT formulas, for external SAT and MaxSAT solvers.

The exported formula is the oracles' encoding (:mod:`mega_sat.sat.encoding`) at the horizon
that makes the bound exact (``floor(bound / c_min)`` steps, at most ``horizon_cap``), with the
candidate model, the goal activation and the cost bounds as unit clauses instead of
assumptions.  So:

* ``<kind>.cnf`` is satisfiable iff a plan (OPT) or joint plan (JOINT) within the bounds exists;
* ``<kind>.wcnf`` drops the cost bound of the minimized copy (human for OPT, robot for JOINT)
  and adds one soft unit clause ``-v`` per cost variable of each step, weighted by what it
  stands for (unary: one cost unit each; binary: bit ``b`` weighs ``2**b`` cost units): its
  MaxSAT optimum is the optimal cost (as long as ``bound`` is at least the optimum);
* ``<kind>.vars.json`` maps variables to meanings (``a[3]=(move p1 p2)``,
  ``x[human][2](at p1)``, ``e[5]=add-has-initial-state-...``, ``u[human][4][2]`` or, with
  binary costs, ``w[human][4][2]``) plus the horizon, bounds and whether the horizon argument
  is exact (it is not with zero-cost actions, nor when the horizon was capped).
"""

from __future__ import annotations

import json
from collections.abc import Iterable, Sequence
from pathlib import Path

from pysat.formula import CNF, WCNF

from mega_sat.ground.family import GroundFamily
from mega_sat.options import DEFAULT, Options
from mega_sat.sat.encoding import HUMAN, ROBOT, FamilyEncoding


def _horizon(family: GroundFamily, bound: int, cap: int) -> tuple[int, bool]:
    """Steps that every plan of cost ``<= bound`` fits in, and whether that is a proof: not
    with zero-cost actions, nor above ``cap`` (large costs over a small cheapest one)."""
    if family.min_cost <= 0:
        return min(max(bound, 0), cap), False
    need = max(bound, 0) // family.min_cost
    return min(need, cap), need <= cap


def _write(
    enc: FamilyEncoding,
    clauses: list[list[int]],
    units: list[int],
    soft: list[tuple[int, int]],
    meta: dict,
    out_dir: Path,
    kind: str,
    update_names: Sequence[str] | None,
) -> dict[str, Path]:
    out_dir.mkdir(parents=True, exist_ok=True)
    comments = [
        f"c mega-sat {kind} formula: {enc.family.describe()}",
        f"c horizon {enc.horizon}, exact horizon: {meta['exact']}",
        f"c variable meanings in {kind}.vars.json",
    ]
    cnf = CNF(from_clauses=clauses + [[u] for u in units])
    paths = {
        "cnf": out_dir / f"{kind}.cnf",
        "wcnf": out_dir / f"{kind}.wcnf",
        "vars": out_dir / f"{kind}.vars.json",
    }
    cnf.to_file(str(paths["cnf"]), comments=comments)
    wcnf = WCNF()
    for c in clauses:
        wcnf.append(c)
    for u in units[: meta["n_hard_units_wcnf"]]:
        wcnf.append([u])
    for v, weight in soft:
        wcnf.append([-v], weight=weight)
    wcnf.to_file(str(paths["wcnf"]), comments=comments)
    names = enc.var_map()
    if update_names is not None:
        for i, name in enumerate(update_names):
            names[enc.e(i)] = f"e[{i}]={name}"
    meta = {k: v for k, v in meta.items() if k != "n_hard_units_wcnf"}
    meta["variables"] = {str(k): v for k, v in sorted(names.items())}
    paths["vars"].write_text(json.dumps(meta, indent=1) + "\n")
    return paths


def export(
    family: GroundFamily,
    selection: Iterable[int],
    kind: str,
    out_dir: str | Path,
    *,
    robot_bound: int | None = None,
    human_bound: int | None = None,
    update_names: Sequence[str] | None = None,
    options: Options = DEFAULT,
) -> dict[str, Path]:
    """Write ``<kind>.cnf``, ``<kind>.wcnf`` and ``<kind>.vars.json`` into ``out_dir``.

    ``kind="opt"``: plans of ``human + selection`` with cost <= ``human_bound`` (default: the
    optimum, computed with the OPT oracle).  ``kind="joint"``: JOINT with both bounds
    (``human_bound`` defaults to the optimum of ``human + selection``).  The horizon is at
    most ``options.horizon_cap`` steps, as in the oracles.  Returns the paths.
    """
    sel = frozenset(selection)
    if kind not in ("opt", "joint"):
        raise ValueError(f"kind must be 'opt' or 'joint', not {kind!r}")
    if kind == "opt" and robot_bound is not None:
        raise ValueError("robot_bound bounds JOINT's robot plan: OPT has none")
    if human_bound is None:
        from mega_sat.sat.oracles import SatOracles

        with SatOracles(family, options=options) as orc:
            r = orc.opt(sel)
        if r.status != "optimal":
            raise ValueError(f"human + E has no plan ({r.status}: {r.reason}); give a bound")
        human_bound = r.cost
    if human_bound < 0 or (robot_bound is not None and robot_bound < 0):
        raise ValueError("bounds must be >= 0")
    bound = human_bound if (kind == "opt" or robot_bound is None) else min(human_bound, robot_bound)
    h, exact = _horizon(family, bound, options.horizon_cap)
    clauses: list[list[int]] = []
    copies = (HUMAN,) if kind == "opt" else (HUMAN, ROBOT)
    enc = FamilyEncoding(family, clauses.append, copies=copies)
    enc.extend(h)
    hard = enc.selection_assumptions(sel)
    minimized = HUMAN if kind == "opt" else ROBOT
    other = [] if kind == "opt" else enc.cost_assumptions(HUMAN, human_bound, h)
    own = enc.cost_assumptions(minimized, human_bound if kind == "opt" else robot_bound, h)
    hard += enc.goal_assumptions(h) + other
    # soft units: every cost variable of the minimized copy, worth what it stands for
    soft = [
        (v, w * enc.cost_unit) for t in range(h) for v, w in enc.step_cost_literals(minimized, t)
    ]
    meta = {
        "kind": kind,
        "selection": sorted(sel),
        "horizon": h,
        "exact": exact,
        "human_bound": human_bound,
        "robot_bound": robot_bound,
        "cost_unit": enc.cost_unit,
        "cost_bits": enc.cost_bits,
        "vars": enc.top,
        "n_hard_units_wcnf": len(hard),
    }
    return _write(enc, clauses, hard + own, soft, meta, Path(out_dir), kind, update_names)


def export_opt(
    family: GroundFamily, selection: Iterable[int], bound: int | None, out_dir: str | Path, **kw
) -> dict[str, Path]:
    """OPT formula of ``human + selection`` with cost <= ``bound`` (see :func:`export`)."""
    return export(family, selection, "opt", out_dir, human_bound=bound, **kw)


def export_joint(
    family: GroundFamily,
    selection: Iterable[int],
    robot_bound: int | None,
    human_bound: int | None,
    out_dir: str | Path,
    **kw,
) -> dict[str, Path]:
    """JOINT formula (see :func:`export`)."""
    return export(
        family, selection, "joint", out_dir, robot_bound=robot_bound, human_bound=human_bound, **kw
    )
