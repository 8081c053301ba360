"""Exported DIMACS/WCNF formulas agree with the oracles (RC2 optimum == OPT)."""

from __future__ import annotations

import json

from helpers.fuzzing import oracle_settings
from helpers.sat_families import families, selections
from hypothesis import given
from hypothesis import strategies as st
from pysat.examples.rc2 import RC2
from pysat.formula import CNF, WCNF
from pysat.solvers import Solver

from mega_sat.ground.family import GroundFamily
from mega_sat.sat.cnf_export import export, export_joint, export_opt
from mega_sat.sat.oracles import SatOracles

SETTINGS = oracle_settings(60)


def sat(path) -> bool:
    with Solver(name="cadical195", bootstrap_with=CNF(from_file=str(path)).clauses) as s:
        return s.solve()


@SETTINGS
@given(fam=families(max_atoms=3, max_actions=5), data=st.data())
def test_opt_export(fam: GroundFamily, data, tmp_path_factory):
    out = tmp_path_factory.mktemp("opt")
    sel = data.draw(selections(fam.n_updates))
    with SatOracles(fam) as orc:
        r = orc.opt(sel)
    bound = data.draw(st.integers(0, 8))
    paths = export_opt(fam, sel, bound, out)
    assert sat(paths["cnf"]) == (r.status == "optimal" and r.cost <= bound)
    if r.status == "optimal" and r.cost <= bound:
        with RC2(WCNF(from_file=str(paths["wcnf"]))) as rc2:
            assert rc2.compute() is not None and rc2.cost == r.cost
    meta = json.loads(paths["vars"].read_text())
    assert meta["kind"] == "opt" and meta["exact"] and meta["horizon"] == bound // fam.min_cost


@SETTINGS
@given(fam=families(max_atoms=3, max_actions=5), data=st.data())
def test_joint_export(fam: GroundFamily, data, tmp_path_factory):
    out = tmp_path_factory.mktemp("joint")
    sel = data.draw(selections(fam.n_updates))
    hb = data.draw(st.integers(0, 6))
    rb = data.draw(st.one_of(st.none(), st.integers(0, 6)))
    with SatOracles(fam) as orc:
        j = orc.joint(sel, rb, hb)
    paths = export_joint(fam, sel, rb, hb, out)
    assert sat(paths["cnf"]) == (j.status == "plan")
    if j.status == "plan":
        with RC2(WCNF(from_file=str(paths["wcnf"]))) as rc2:
            assert rc2.compute() is not None and rc2.cost == j.robot_cost


def test_default_bound_and_names(tmp_path):
    from mega_sat.ground.family import GroundAction

    act = GroundAction(
        "move", ("p1", "p2"), (0, True), ((0, None),), (), ((1, None),), ((0, None),), (((), 1),)
    )
    fam = GroundFamily((("at", "p1"), ("at", "p2")), 1, (act,), ((0, None),), ((1, None),))
    paths = export(fam, {0}, "opt", tmp_path, update_names=["add-move-has-parameters-?a ?b"])
    meta = json.loads(paths["vars"].read_text())
    assert meta["human_bound"] == 1 and meta["horizon"] == 1
    names = set(meta["variables"].values())
    assert "e[0]=add-move-has-parameters-?a ?b" in names
    assert "a[0]=(move p1 p2)" in names and "x[human][1](at p2)" in names
    assert "u[human][0][1]" in names
    assert sat(paths["cnf"])


def test_a_robot_bound_is_refused_for_opt(tmp_path):
    """OPT has no robot plan: a robot bound given with it would be written into the map and
    used by nothing, so it is refused (the CLI says so before grounding)."""
    from pathlib import Path

    import pytest
    from click.testing import CliRunner

    from mega_sat.cli.commands import main

    fam = GroundFamily((("at", "p1"),), 0, (), (), ((0, None),))
    with pytest.raises(ValueError, match="robot_bound"):
        export(fam, set(), "opt", tmp_path / "x", robot_bound=3, human_bound=1)
    res = CliRunner().invoke(
        main,
        [
            "encode",
            "--task",
            str(Path(__file__).parents[1] / "domains/usar-fetch/p1"),
            "--robot-bound",
            "3",
            "--out",
            str(tmp_path),
        ],
    )
    assert res.exit_code == 2 and "give it with --kind joint" in res.output
    assert not (tmp_path / "x").exists()
