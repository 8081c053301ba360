"""PDDL reader: type compilation, costs, case, and one-line errors naming file/line/construct."""

from __future__ import annotations

from pathlib import Path

import pytest

from mega_sat.errors import PDDLError
from mega_sat.pddl.reader import parse_model, read_model

DATA = Path(__file__).parent / "data" / "frontend"
BASE_DOMAIN = DATA / "base-domain.pddl"
BASE_PROBLEM = DATA / "base-problem.pddl"


def _error(domain: Path, problem: Path) -> PDDLError:
    with pytest.raises(PDDLError) as info:
        read_model(domain, problem)
    msg = str(info.value)
    assert "\n" not in msg and not msg.startswith("error: ")
    return info.value


def test_typed_domain_compiles_types_into_predicates():
    m = read_model(DATA / "typed-domain.pddl", DATA / "typed-problem.pddl")
    assert m.domain_name == "typed-logistics" and m.problem_name == "typed-1"
    assert m.type_predicates == {"truck", "car", "vehicle", "package", "locatable", "place"}
    for t in m.type_predicates:
        assert m.predicates[t] == 1
    assert m.predicates["at"] == 2 and m.predicates["road"] == 2
    # an object gets its type and every supertype except 'object'
    assert {a for a in m.init if a[1] == "car1" and len(a) == 2} == {
        ("car", "car1"),
        ("vehicle", "car1"),
        ("locatable", "car1"),
    }
    # typed domain constants are objects, their type atoms are initial-state atoms
    assert {"depot", "van1"} <= m.objects
    assert {("place", "depot"), ("truck", "van1"), ("vehicle", "van1")} <= m.init
    # an untyped object has no type atoms
    assert "thing" in m.objects
    assert not any("thing" in a[1:] for a in m.init)
    drive = m.schemas["drive"]
    assert drive.params == ("?v", "?from", "?to")
    assert {("vehicle", "?v"), ("place", "?from"), ("place", "?to")} <= drive.pre
    assert drive.negpre == {("broken", "?v")}
    assert drive.add == {("at", "?v", "?to")} and drive.delete == {("at", "?v", "?from")}
    assert ("at", "?v", "depot") in m.schemas["unload-at-depot"].pre
    wait = m.schemas["wait"]  # '?x' is of type object: no type precondition; '()' is empty
    assert wait.pre == frozenset() and wait.add == frozenset() and wait.cost == 1
    assert not m.uses_costs and all(s.cost == 1 for s in m.schemas.values())
    assert m.goal == {("at", "pkg", "depot")}


def test_cost_functions_and_constant_costs():
    m = read_model(DATA / "cost-domain.pddl", DATA / "cost-problem.pddl")
    assert m.uses_costs
    assert m.schemas["drive"].cost == ("road-length", "?from", "?to")
    assert m.schemas["teleport"].cost == 10
    assert m.schemas["look"].cost == 0  # no cost effect under :action-costs costs 0
    assert m.functions == {("road-length", "a", "b"): 3, ("road-length", "b", "c"): 4}
    assert m.function_arities == {"road-length": 2}
    assert "total-cost" not in m.predicates
    assert m.schema_cost(m.schemas["drive"], ("b", "c")) == 4


def test_upper_case_ipc_file_loads_lower_cased():
    m = read_model(DATA / "upper-domain.pddl", DATA / "upper-problem.pddl")
    assert m.domain_name == "blocks" and m.problem_name == "blocks-3-0"
    assert set(m.schemas) == {"pick-up", "put-down", "stack", "unstack"}
    assert m.objects == {"a", "b", "c"}
    assert ("on", "c", "a") in m.init and ("handempty",) in m.init
    assert m.schemas["stack"].params == ("?x", "?y")
    assert m.goal == {("on", "a", "b"), ("on", "b", "c")}


def test_undeclared_supertype_and_object_parent():
    dom = """(define (domain d) (:requirements :typing)
      (:types truck - vehicle place - object)
      (:predicates (at ?v ?p))
      (:action go :parameters (?v - vehicle ?p - place) :precondition (and) :effect (at ?v ?p)))"""
    prob = """(define (problem p) (:domain d) (:objects t - truck x - place)
      (:init) (:goal (and (at t x))))"""
    m = parse_model(dom, prob)
    assert m.type_predicates == {"truck", "vehicle", "place"}
    assert m.init == {("truck", "t"), ("vehicle", "t"), ("place", "x")}
    assert m.schemas["go"].pre == {("vehicle", "?v"), ("place", "?p")}


def test_object_as_a_type_is_any_object():
    """``- object`` (PDDL's root type, declared or not) on parameters, predicate and function
    arguments, constants and objects, and inside ``either``: the library refuses it, mega-sat
    reads it as untyped, which means the same."""
    dom = """(define (domain d) (:requirements :typing :action-costs)
      (:types loc - object thing)
      (:constants home - object)
      (:predicates (at ?x - object) (road ?x ?y - (either loc object)) (has ?t - thing))
      (:functions (total-cost) - number (dist ?x ?y - object) - number)
      (:action go :parameters (?x - object ?y - loc) :precondition (and (at ?x) (road ?x ?y))
        :effect (and (not (at ?x)) (at ?y) (increase (total-cost) (dist ?x ?y)))))"""
    prob = """(define (problem p) (:domain d) (:objects a b - loc z - object t - thing)
      (:init (at z) (road z a) (= (dist z a) 3) (= (total-cost) 0)) (:goal (at a))
      (:metric minimize (total-cost)))"""
    m = parse_model(dom, prob)
    assert m.schemas["go"].params == ("?x", "?y")
    assert m.schemas["go"].pre == {("at", "?x"), ("road", "?x", "?y"), ("loc", "?y")}
    assert m.objects == {"a", "b", "z", "t", "home"}
    assert m.init >= {("loc", "a"), ("thing", "t"), ("at", "z")}
    assert not any(a[1:] == ("z",) and a[0] != "at" for a in m.init)
    from mega_sat.ground.grounding import ground_model

    costs = {(a.name, a.args): a.cost for a in ground_model(m).actions}
    assert costs[("go", ("z", "a"))] == 3


def test_types_listing_object_or_a_type_twice():
    """``object`` among the declared types, and a type declared twice with the same parent, are
    valid PDDL (Fast Downward reads them); the library refuses both."""
    prob = """(define (problem p) (:domain d) (:objects t - truck x - place)
      (:init) (:goal (and (at t x))))"""
    rest = """(:predicates (at ?v ?p))
      (:action go :parameters (?v - vehicle ?p - place) :precondition (and) :effect (at ?v ?p)))"""
    for types in (
        "(:types truck - vehicle object vehicle place - object)",
        "(:types truck - vehicle truck - vehicle place place\n vehicle)",
        "(:types truck - vehicle place object)",
    ):
        dom = f"(define (domain d) (:requirements :typing)\n {types}\n {rest}"
        m = parse_model(dom, prob)
        assert m.type_predicates == {"truck", "vehicle", "place"}, types
        assert m.init == {("truck", "t"), ("vehicle", "t"), ("place", "x")}
        assert m.schemas["go"].pre == {("vehicle", "?v"), ("place", "?p")}
    only_object = "(define (domain d) (:types object) (:predicates (at ?x))"
    only_object += " (:action go :parameters (?x) :effect (at ?x)))"
    assert (
        parse_model(
            only_object, "(define (problem p) (:domain d) (:objects a) (:init) (:goal (at a)))"
        ).type_predicates
        == set()
    )


def test_nested_and_in_effects_is_flattened():
    """``(and (and (q)) (and) (not (p)))`` is a valid effect (the library's grammar takes nested
    'and' only in conditions): it means (q) and not (p)."""
    dom = """(define (domain d) (:requirements :strips :negative-preconditions)
      (:predicates (p) (q) (g))
      (:action b :parameters () :precondition (and (p) (and) (not (q)))
        :effect (and (and (q)) (and) (and (not (p)) (and (g))))))"""
    prob = "(define (problem x) (:domain d) (:init (p)) (:goal (g)))"
    b = parse_model(dom, prob).schemas["b"]
    assert b.add == {("q",), ("g",)} and b.delete == {("p",)}
    assert b.pre == {("p",)} and b.negpre == {("q",)}
    bad = dom.replace("(and (g))", "(and (g) (h))")
    with pytest.raises(PDDLError, match="line 4: undefined predicate 'h'"):
        parse_model(bad, prob)


def test_a_function_given_two_values_is_refused():
    dom = """(define (domain d) (:requirements :action-costs)
      (:predicates (p ?x)) (:functions (total-cost) - number (f ?x) - number)
      (:action a :parameters (?x) :precondition (and) :effect (and (p ?x)
        (increase (total-cost) (f ?x)))))"""
    prob = """(define (problem x) (:domain d) (:objects o) (:init (= (f o) 3)
      (= (f o) {})) (:goal (p o)))"""
    with pytest.raises(PDDLError, match=r"line 2: \(f o\) is given two values \(3 and 9\)"):
        parse_model(dom, prob.format(9), problem_path="x.pddl")
    assert parse_model(dom, prob.format(3)).functions[("f", "o")] == 3
    assert parse_model(dom, prob.format("3.0")).functions[("f", "o")] == 3  # the same value


def test_preferences_are_named_when_refused():
    dom = "(define (domain d) (:predicates (p)) (:action a :parameters () :effect (p)))"
    prob = "(define (problem x) (:domain d) (:init) (:goal (and (preference g1 (p)))))"
    with pytest.raises(PDDLError, match="preferences 'preference' \\(PDDL3\\) is not supported"):
        parse_model(dom, prob)


def test_cost_effects_without_the_action_costs_flag_keep_their_costs():
    """IPC 2011's floortile declares only :typing and has cost effects; Fast Downward reads the
    costs, and so does mega-sat (an action without a cost effect then costs 0)."""
    dom = """(define (domain base) (:requirements :strips)
      (:predicates (p ?x) (q ?x)) (:functions (total-cost) - number)
      (:action a :parameters (?x) :precondition (p ?x)
        :effect (and (q ?x) (increase (total-cost) 2)))
      (:action b :parameters (?x) :precondition (q ?x) :effect (p ?x)))"""
    prob = "(define (problem x) (:domain base) (:objects o) (:init (p o)) (:goal (q o)))"
    m = parse_model(dom, prob)
    assert m.uses_costs and m.schemas["a"].cost == 2 and m.schemas["b"].cost == 0


def test_equality_declared_as_a_predicate_is_left_out():
    """``(= ?x ?y)`` in :predicates (written for Fast Downward) declares the built-in equality:
    the declaration is read and dropped, and equality in a precondition is read as usual."""
    dom = """(define (domain d) (:requirements :strips)
      (:predicates (p ?x) (= ?x - object ?y - object))
      (:action a :parameters (?x) :precondition (p ?x) :effect (not (p ?x))))"""
    prob = "(define (problem x) (:domain d) (:objects o) (:init (p o)) (:goal (and)))"
    assert parse_model(dom, prob).predicates == {"p": 1}
    only = dom.replace("(p ?x) (= ?x", "(= ?x").replace(
        "(p ?x) :effect (not (p ?x))", "(and) :effect (and)"
    )
    assert parse_model(only, prob.replace("(p o)", "")).predicates == {}
    used = dom.replace(":precondition (p ?x)", ":precondition (and (p ?x) (= ?x ?x))")
    m = parse_model(used, prob)
    assert m.predicates == {"p": 1, "=": 2} and ("=", "?x", "?x") in m.schemas["a"].pre


def test_adl_flag_accepted_when_no_unsupported_construct_is_used():
    dom = BASE_DOMAIN.read_text().replace(":negative-preconditions", ":adl :equality")
    m = parse_model(dom, BASE_PROBLEM.read_text())
    assert m.schemas["a"].negpre == {("q", "?y")}


def test_negative_initial_literals_are_ignored_and_total_cost_zero_ignored():
    prob = BASE_PROBLEM.read_text().replace("(:init", "(:init (not (q o2))")
    m = parse_model(BASE_DOMAIN.read_text(), prob)
    assert m.init == {("p", "o1"), ("r", "o1", "o2")}


@pytest.mark.parametrize(
    ("name", "construct", "line"),
    [
        ("when", "conditional effect 'when'", 8),
        ("forall-effect", "universal effect 'forall'", 8),
        ("forall", "universal quantifier 'forall'", 7),
        ("exists", "existential quantifier 'exists'", 7),
        ("or", "disjunction 'or'", 7),
        ("imply", "implication 'imply'", 7),
        ("not-and", "negation of a compound condition", 7),
        ("equality", "equality '(= ...)' in an effect", 8),
        ("comparison", "numeric comparison '>'", 7),
        ("decrease", "numeric effect 'decrease'", 8),
        ("assign", "numeric effect 'assign'", 8),
        ("increase-fluent", "numeric effect 'increase' of '(fuel ...)'", 8),
        ("either", "'either' type", 6),
        ("derived", "derived predicates (:derived)", 4),
        ("durative-action", "durative actions (:durative-action)", 4),
        ("durative-requirement", "requirement :durative-actions", 3),
        ("cost-expression", "cost expression '(+ ...)'", 9),
        ("fractional-cost", "action cost '2.5'", 8),
        ("object-fluent", "object fluents", 5),
    ],
)
def test_unsupported_domain_constructs(name, construct, line):
    path = DATA / "unsupported" / f"{name}.pddl"
    e = _error(path, BASE_PROBLEM)
    assert f"{path}: line {line}: " in str(e)
    assert construct in str(e) and "not supported" in str(e)


@pytest.mark.parametrize(
    ("name", "construct", "line"),
    [
        ("negated-equality-goal", "equality '(= ...)' in the goal", 7),
        ("or-goal", "non-conjunctive goal (disjunction 'or')", 6),
        ("metric", "metric other than 'minimize (total-cost)'", 7),
        ("timed-literal", "timed initial literal", 6),
        ("constraints", "(:constraints)", 7),
    ],
)
def test_unsupported_problem_constructs(name, construct, line):
    path = DATA / "unsupported" / f"{name}.pddl"
    e = _error(BASE_DOMAIN, path)
    assert str(e).startswith(f"{path}: line {line}: ")
    assert construct in str(e) and "not supported" in str(e)


@pytest.mark.parametrize(
    ("name", "message", "line"),
    [
        ("unbalanced", "'(' is never closed (unbalanced parentheses): ':effect' on line 7", 6),
        ("extra-open", "'(' is never closed (unbalanced parentheses): ':effect' on line 8", 7),
        ("unclosed-action", "'(' is never closed (unbalanced parentheses): the form on line 9", 4),
        ("extra-open-list", "a list here starts with another list (a '(' too many)", 10),
        ("extra-paren", "unexpected text after the end of '(define ...)'", 4),
        ("undefined-predicate", "undefined predicate 's' in the precondition of action 'a'", 7),
        ("domain-arity", "predicate 'r' takes 2 argument(s), got 1", 8),
        ("undefined-type", "undefined type 'city' in the parameters of action 'a'", 6),
        ("undefined-variable", "undefined variable '?y' in the effect of action 'a'", 7),
        ("type-predicate-collision", "'p' is both a type and a predicate", 5),
        ("syntax", "syntax error: unexpected ':effect'", 8),
    ],
)
def test_malformed_domains(name, message, line):
    path = DATA / "malformed" / f"{name}.pddl"
    e = _error(path, BASE_PROBLEM)
    assert str(e).startswith(f"{path}: line {line}: ") and message in str(e)


@pytest.mark.parametrize(
    ("name", "message", "line"),
    [
        ("undefined-object", "undefined object 'o3' in :init", 5),
        ("problem-arity", "predicate 'q' takes 1 argument(s), got 2 in :goal", 6),
        ("problem-undefined-predicate", "undefined predicate 's' in :goal", 6),
        ("goal-variable", "variable '?x' in :goal", 6),
        ("bad-name-problem", "syntax error: unexpected '2'", 4),  # reported by lark
        # the innermost form open at the end: the goal on line 7, not the define
        ("unclosed-goal", "'(' is never closed (unbalanced parentheses)", 7),
        # the ')' on line 8 is indented to close the define but closes the goal of line 7
        (
            "unclosed-goal-closed-late",
            "'(' is never closed (unbalanced parentheses): the ')' on line 8 closes it, "
            "indented like an outer form's (a ')' missing before line 8, or a '(' too many)",
            7,
        ),
    ],
)
def test_malformed_problems(name, message, line):
    path = DATA / "malformed" / f"{name}.pddl"
    e = _error(BASE_DOMAIN, path)
    assert str(e) == f"{path}: line {line}: {message}"


def test_library_errors_leave_the_parser_usable():
    _error(DATA / "malformed" / "syntax.pddl", BASE_PROBLEM)
    _error(BASE_DOMAIN, DATA / "malformed" / "bad-name-problem.pddl")
    m = read_model(DATA / "typed-domain.pddl", DATA / "typed-problem.pddl")
    assert "depot" in m.objects
    # a later domain without :constants must not see the earlier one's constants
    dom = BASE_DOMAIN.read_text().replace("(q ?x) (not", "(q depot) (not")
    with pytest.raises(PDDLError, match="undefined constant 'depot'"):
        parse_model(dom, BASE_PROBLEM.read_text())


def test_missing_file_is_named(tmp_path):
    missing = tmp_path / "nope.pddl"
    with pytest.raises(PDDLError) as info:
        read_model(BASE_DOMAIN, missing)
    assert str(info.value) == f"{missing}: problem file not found"
    with pytest.raises(PDDLError, match="domain file is a directory"):
        read_model(tmp_path, BASE_PROBLEM)


def test_problem_given_as_domain():
    e = _error(BASE_PROBLEM, BASE_PROBLEM)
    assert "this is a problem file, expected a domain file" in str(e)
    assert f"{BASE_PROBLEM}: line 2:" in str(e)


@pytest.mark.parametrize(
    ("dom_edit", "prob_edit", "message"),
    [
        ((":negative-preconditions", ":foo"), None, "unknown requirement ':foo'"),
        (("(:action a", "(:action a :parameters (?x) :effect (q ?x)) (:action a"), None,
         "action 'a' is defined twice"),
        (None, ("(:objects o1 o2)", "(:objects o1 o2) (:bogus)"), "unknown problem section"),
        (None, ("(:init", "(:init (= (q o1) 3)"), "undefined function 'q'"),
        (None, ("(:goal (and (q o1)))", "(:goal (and (q o1))) (:metric minimize (total-cost))"),
         "the metric uses (total-cost), which the domain does not declare"),
        (None, ("(:goal (and (q o1)))", ""), "missing (:goal ...)"),
    ],
)  # fmt: skip
def test_other_checks(dom_edit, prob_edit, message):
    dom, prob = BASE_DOMAIN.read_text(), BASE_PROBLEM.read_text()
    if dom_edit:
        dom = dom.replace(*dom_edit)
    if prob_edit:
        prob = prob.replace(*prob_edit)
    with pytest.raises(PDDLError) as info:
        parse_model(dom, prob, domain_path="d.pddl", problem_path="p.pddl")
    assert message in str(info.value)
    assert "\n" not in str(info.value)


def test_object_declared_with_two_types():
    dom = (DATA / "typed-domain.pddl").read_text()
    prob = (DATA / "typed-problem.pddl").read_text().replace("thing)", "thing depot - package)")
    with pytest.raises(PDDLError, match="object 'depot' is declared with two types"):
        parse_model(dom, prob)


def test_object_declared_twice_names_its_line():
    """The PDDL library's own message had no line ("duplicate name ... already inherits")."""
    dom = (DATA / "typed-domain.pddl").read_text()
    prob = (DATA / "typed-problem.pddl").read_text().replace("a b - place", "a b a - place")
    with pytest.raises(PDDLError, match=r"p.pddl: line 3: object 'a' is declared twice"):
        parse_model(dom, prob, domain_path="d.pddl", problem_path="p.pddl")


@pytest.mark.parametrize("section", [":metric", ":goal", ":init", ":objects"])
def test_a_problem_section_given_twice_is_named(section):
    """A stored IPC problem repeats its ``(:metric ...)``; the library's message was "syntax
    error: unexpected '('" at the second one."""
    dom = (DATA / "cost-domain.pddl").read_text()
    prob = (DATA / "cost-problem.pddl").read_text()
    body = prob.rstrip()
    assert body.endswith(")")
    start = prob.index(f"({section}")
    depth, end = 0, start
    for end in range(start, len(prob)):
        depth += {"(": 1, ")": -1}.get(prob[end], 0)
        if depth == 0:
            break
    twice = body[:-1] + "\n" + prob[start : end + 1] + ")\n"
    line = twice.count("\n", 0, twice.rindex(f"({section}")) + 1
    with pytest.raises(PDDLError) as info:
        parse_model(dom, twice, domain_path="d.pddl", problem_path="p.pddl")
    assert str(info.value) == (
        f"p.pddl: line {line}: a second ({section} ...) section: a problem has one"
    )


def test_cost_function_values_must_be_non_negative_integers():
    dom = (DATA / "cost-domain.pddl").read_text()
    prob = (DATA / "cost-problem.pddl").read_text().replace("a b) 3)", "a b) 3.5)")
    with pytest.raises(PDDLError, match=r"line 6: cost function value 3\.5"):
        parse_model(dom, prob)


def test_omitted_action_parts_empty_sections_and_crlf():
    dom = (
        "(define (domain d)\r\n (:requirements :strips) (:types) (:constants)\r\n"
        " (:predicates (p ?x) (q))\r\n"
        " (:action no-params :effect (q))\r\n"
        " (:action no-pre :parameters (?x) :effect (not (p ?x)))\r\n"
        " (:action no-effect :parameters (?x) :precondition (p ?x)))\r\n"
    )
    prob = "(define (problem p) (:domain d) (:objects o) (:init (p o)) (:goal (q)))"
    m = parse_model(dom, prob)
    assert m.schemas["no-params"].params == () and m.schemas["no-params"].add == {("q",)}
    assert m.schemas["no-pre"].pre == frozenset() and m.schemas["no-pre"].delete == {("p", "?x")}
    assert m.schemas["no-effect"].pre == {("p", "?x")} and m.schemas["no-effect"].add == set()
    with pytest.raises(PDDLError, match=r"^d\.pddl: line 5: undefined predicate 'r'"):
        parse_model(dom.replace("(not (p ?x))", "(r ?x)"), prob, domain_path="d.pddl")


def test_a_valid_file_is_parsed_once(monkeypatch):
    from mega_sat.pddl import library as pddl_library
    from mega_sat.pddl import reader as pddl_reader

    parsed: list[str] = []
    real_parse_tree = pddl_library.parse_tree

    def counting_parse_tree(text, kind):
        parsed.append(kind)
        return real_parse_tree(text, kind)

    def no_text_reading(*args):
        raise AssertionError("a valid file is read from the library's tokens")

    monkeypatch.setattr(pddl_reader, "parse_tree", counting_parse_tree)
    monkeypatch.setattr(pddl_library, "parse_tree", counting_parse_tree)
    monkeypatch.setattr(pddl_reader, "read_sexpr", no_text_reading)
    m = read_model(DATA / "typed-domain.pddl", DATA / "typed-problem.pddl")
    assert parsed == ["domain", "problem"] and m.domain_name == "typed-logistics"


def test_a_duplicate_before_a_syntax_error_comes_first():
    # the duplicate object is reported where it is (once the library's own error, without a
    # line), before the syntax error of the metric placed before the goal
    dom = (
        "(define (domain d) (:requirements :action-costs) (:predicates (p ?x))"
        " (:functions (total-cost) - number) (:action a :parameters (?x) :effect (p ?x)))"
    )
    prob = "(define (problem q) (:domain d) (:objects o o) (:init) (:goal (p o)))"
    with pytest.raises(PDDLError, match=r"^p\.pddl: line 1: object 'o' is declared twice"):
        parse_model(dom, prob, problem_path="p.pddl")
    late = prob.replace("(:goal", "(:metric minimize (total-cost)) (:goal")
    with pytest.raises(PDDLError, match=r"^p\.pddl: line 1: object 'o' is declared twice"):
        parse_model(dom, late, problem_path="p.pddl")
    with pytest.raises(PDDLError, match=r"^p\.pddl: line 1: syntax error: unexpected ':metric'"):
        parse_model(dom, late.replace("o o)", "o)"), problem_path="p.pddl")


def test_a_failed_file_leaves_nothing_for_the_next():
    # the library's syntax error comes after its transformer has read the types
    typed = (DATA / "typed-domain.pddl").read_text().replace("(:predicates", "(:predicates (1r)")
    with pytest.raises(PDDLError, match="syntax error: unexpected '1'"):
        parse_model(typed, (DATA / "typed-problem.pddl").read_text())
    m = read_model(DATA / "typed-domain.pddl", DATA / "typed-problem.pddl")
    assert "truck" in m.type_predicates


KEYWORD_DOMAIN = """(define (domain kw)
  (:requirements :strips :typing :negative-preconditions)
  (:types thing place)
  (:predicates (at ?object - thing ?either - place) (holding ?object) (free))
  (:functions (weight ?domain - thing) - number)
  (:action pick :parameters (?object - thing ?object-v - place)
    :precondition (and (at ?object ?object-v) (free) (not (holding ?object)))
    :effect (and (holding ?object) (not (at ?object ?object-v)) (not (free))))
  (:action drop :parameters (?when - thing ?p - place)
    :precondition (holding ?when)
    :effect (and (at ?when ?p) (not (holding ?when)) (free))))"""
KEYWORD_PROBLEM = """(define (problem kw1) (:domain kw)
  (:objects box - thing a b - place)
  (:init (at box a) (free))
  (:goal (at box b)))"""


def test_variables_named_like_keywords_keep_their_names():
    """PDDL allows ``?object``, ``?either``, ``?when``; the ``pddl`` library takes them for its
    keywords.  They are renamed for the library and named as the file names them in the model
    (``?object-v``, already taken, stays itself)."""
    m = parse_model(KEYWORD_DOMAIN, KEYWORD_PROBLEM)
    pick, drop = m.schemas["pick"], m.schemas["drop"]
    assert pick.params == ("?object", "?object-v")
    assert pick.pre == {
        ("at", "?object", "?object-v"),
        ("free",),
        ("thing", "?object"),
        ("place", "?object-v"),
    }
    assert pick.negpre == {("holding", "?object")}
    assert pick.delete == {("at", "?object", "?object-v"), ("free",)}
    assert drop.params == ("?when", "?p") and drop.add == {("at", "?when", "?p"), ("free",)}
    assert m.predicates["at"] == 2 and m.function_arities == {"weight": 1}


@pytest.mark.parametrize(
    ("where", "old", "new", "what"),
    [
        ("problem", "box - thing", "either - thing", "an object"),
        (
            "domain",
            "(:types thing place)",
            "(:types thing place)\n  (:constants domain)",
            "a constant",
        ),
        ("domain", "(free))", "(free) (either))", "a predicate"),
        ("domain", ":action drop", ":action and", "an action"),
        ("domain", "(domain kw)", "(domain either)", "the domain"),
        ("problem", "(problem kw1)", "(problem object)", "the problem"),
        ("domain", "(:types thing place)", "(:types thing place oneof)", "a type"),
    ],
)
def test_keywords_as_names_of_objects_and_schemas_are_refused(where, old, new, what):
    dom, prob = KEYWORD_DOMAIN, KEYWORD_PROBLEM
    if where == "domain":
        dom = dom.replace(old, new, 1)
    else:
        prob = prob.replace(old, new, 1)
    assert (dom, prob) != (KEYWORD_DOMAIN, KEYWORD_PROBLEM)
    with pytest.raises(PDDLError, match=f"the keyword '.*' as the name of {what} is not sup"):
        parse_model(dom, prob)


def test_header_sections_in_any_order():
    """Fast Downward reads :constants after :predicates and :types after both (the BNF's
    order is not kept by hand written domains); a section given twice is one clear error."""
    dom = """(define (domain d) (:requirements :strips :action-costs) (:types t)
      (:functions (c ?x - t) - number (total-cost) - number)
      (:predicates (p ?x - t))
      (:constants k - t)
      (:action a :parameters (?x - t) :precondition (p ?x)
        :effect (and (not (p ?x)) (p k) (increase (total-cost) (c ?x)))))"""
    prob = """(define (problem q) (:domain d) (:objects o - t)
      (:init (p o) (= (c o) 2) (= (c k) 1)) (:goal (p k)))"""
    m = parse_model(dom, prob)
    assert m.objects == {"k", "o"} and m.schemas["a"].cost == ("c", "?x")
    assert m.schemas["a"].add == {("p", "k")} and m.function_arities == {"c": 1}
    twice = dom.replace("(:constants k - t)", "(:constants k - t)\n      (:predicates (q))")
    with pytest.raises(PDDLError, match=r"^d\.pddl: line 5: a second ':predicates' section$"):
        parse_model(twice, prob, domain_path="d.pddl")
    # the types last, with a hierarchy, a comment and a line break: the same model
    late = dom.replace(" (:types t)", "").replace(
        "(:constants k - t)", "(:constants k - t)\n      (:types u - object\n t - u) ; last"
    )
    moved = parse_model(late, prob)
    assert moved.schemas == m.schemas and moved.init == m.init | {("u", "o"), ("u", "k")}
    again = late.replace("(p k)", "(p j)")  # an error after the moved section: its own line
    with pytest.raises(PDDLError, match=r"^d\.pddl: line 8: .*'j'"):
        parse_model(again, prob, domain_path="d.pddl")
    with pytest.raises(PDDLError, match=r"^d\.pddl: line 6: a second ':types' section$"):
        parse_model(late.replace("(:types u", "(:types v)\n      (:types u"), prob,
                    domain_path="d.pddl")  # fmt: skip


def test_negated_equalities_in_init_are_dropped():
    prob = BASE_PROBLEM.read_text().replace("(:init", "(:init (not (= o1 o2))")
    m = parse_model(BASE_DOMAIN.read_text(), prob)
    assert m.init == {("p", "o1"), ("r", "o1", "o2")}
    bad = BASE_PROBLEM.read_text().replace("(:init", "(:init (not (= o1 o1))")
    with pytest.raises(PDDLError, match=r"'\(not \(= o1 o1\)\)' in :init contradicts equality"):
        parse_model(BASE_DOMAIN.read_text(), bad)
    three = BASE_PROBLEM.read_text().replace("(:init", "(:init (not (= o1 o2 o1))")
    with pytest.raises(PDDLError, match=r"'=' takes 2 arguments, got 3 in :init"):
        parse_model(BASE_DOMAIN.read_text(), three)


def test_an_undefined_type_in_a_predicate_declaration_names_its_line():
    dom = """(define (domain d) (:requirements :strips :typing) (:types t)
      (:predicates (p ?x - t)
                   (q ?x - tt))
      (:action a :parameters (?x - t) :precondition (p ?x) :effect (not (p ?x))))"""
    prob = "(define (problem q) (:domain d) (:objects o - t) (:init (p o)) (:goal (and)))"
    with pytest.raises(PDDLError, match=r"^d\.pddl: line 3: undefined type 'tt' in predicate 'q'$"):
        parse_model(dom, prob, domain_path="d.pddl")
