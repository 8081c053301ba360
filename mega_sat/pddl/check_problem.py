"""Check a PDDL problem's s-expressions against its domain (see :mod:`mega_sat.pddl.check`)."""

from __future__ import annotations

import warnings

from mega_sat.pddl.check import (
    INT_RE,
    KEYWORDS,
    NUMBER_RE,
    REFUSED_SECTIONS,
    Checker,
    DomainInfo,
)
from mega_sat.pddl.sexpr import Node, SList, Tok, show


class PDDLWarning(UserWarning):
    """Something in a PDDL file that mega-sat reads anyway but the user should know about."""


class ProblemChecker(Checker):
    """The checks of a problem file, against what the domain check found.

    ``borrowed``: the file is another model's problem read with this domain (the robot's
    problem as the human's when no human problem is given).  Values of cost functions this
    domain does not declare, and a metric it cannot state, belong to the other model's costs
    and are left out instead of refused.
    """

    def __init__(self, path: str, *, borrowed: bool = False):
        super().__init__(path)
        self.borrowed = borrowed
        self.left_out = False  # whether ``borrowed`` left something out

    def problem(self, root: SList, info: DomainInfo) -> list[SList]:
        """Check a problem against ``info``; return the forms a repaired text leaves out: its
        ``:requirements`` sections (the domain's flags are the ones that count) and negated
        equalities in ``:init`` (true by equality)."""
        self.header(root, "problem")
        self.values: dict[tuple[str, ...], int] = {}
        drop: list[SList] = []
        objects: dict[str, str] = dict(info.constants)
        saw_init = saw_goal = False
        seen: set[str] = set()
        for key, node in self.sections(root):
            if key in seen:  # which one counts would be a guess; PDDL has one of each
                raise self.fail(f"a second ({key} ...) section: a problem has one", node)
            seen.add(key)
            if key == ":domain":
                named = node.items[1] if len(node.items) == 2 else None
                if isinstance(named, Tok) and named.text != info.name:
                    # human problems are often shared by domains of other names: read it
                    warnings.warn(
                        PDDLWarning(
                            f"{self.path}: line {named.line}: the problem names domain "
                            f"'{named.text}' but the domain file defines '{info.name}'; "
                            f"reading it as a problem of '{info.name}'"
                        ),
                        stacklevel=2,
                    )
                continue
            if key == ":requirements":
                self.requirements(node)
                drop.append(node)
            elif key == ":objects":
                listed: set[str] = set()
                for tok, typ in self.typed_list(node.items[1:], ":objects"):
                    self.name_not_reserved(tok, "an object")
                    self.check_type(typ, info.types, tok, ":objects")
                    if tok.text in listed and objects[tok.text] == typ:
                        raise self.fail(f"object '{tok.text}' is declared twice", tok)
                    listed.add(tok.text)
                    if objects.get(tok.text, typ) != typ:
                        raise self.fail(
                            f"object '{tok.text}' is declared with two types "
                            f"('{objects[tok.text]}' and '{typ}')",
                            tok,
                        )
                    objects[tok.text] = typ
            elif key == ":init":
                saw_init = True
                for el in node.items[1:]:
                    if self.init_element(el, info, objects):
                        drop.append(el)
            elif key == ":goal":
                saw_goal = True
                if len(node.items) != 2:
                    raise self.fail("expected one condition in :goal", node)
                self.goal(node.items[1], info, objects)
            elif key == ":metric":
                if self.borrowed and not info.uses_total_cost:
                    drop.append(node)
                    self.left_out = True
                else:
                    self.metric(node, info)
            elif key == ":constraints":
                raise self.refuse(REFUSED_SECTIONS[key], node)
            else:
                raise self.fail(f"unknown problem section '{key}'", node)
        if not saw_init:
            raise self.fail("missing (:init ...)", root)
        if not saw_goal:
            raise self.fail("missing (:goal ...)", root)
        return drop

    def init_element(self, el: Node, info: DomainInfo, objects: dict[str, str]) -> bool:
        """Check one element of :init; True for one to leave out (it says nothing)."""
        if not isinstance(el, SList):
            raise self.fail(f"expected an atom in :init, got {show(el)}", el)
        if el.head == "=":
            return self.function_value(el, info, objects)
        elif el.head == "not":
            if len(el.items) != 2 or not isinstance(el.items[1], SList):
                raise self.fail("malformed 'not' in :init", el)
            sub = el.items[1]
            if sub.head == "=":
                # a negated equality of objects, as some problems state: closed world and
                # equality say it already, unless it denies that an object equals itself
                if self.is_numeric(sub):
                    raise self.refuse("numeric comparison '='", sub)
                if len(sub.items) != 3:
                    raise self.fail(
                        f"'=' takes 2 arguments, got {len(sub.items) - 1} in :init", sub
                    )
                self.terms(sub.items[1:], None, objects, ":init")
                a = sub.items[1].text
                if a == sub.items[2].text:
                    raise self.fail(f"'(not (= {a} {a}))' in :init contradicts equality", el)
                return True
            self.atom(sub, info, None, objects, ":init")
        elif (
            el.head == "at"
            and len(el.items) == 3
            and isinstance(el.items[1], Tok)
            and NUMBER_RE.fullmatch(el.items[1].text)
            and isinstance(el.items[2], SList)
        ):
            raise self.refuse("timed initial literal '(at TIME ...)'", el)
        else:
            self.atom(el, info, None, objects, ":init")
        return False

    def function_value(self, el: SList, info: DomainInfo, objects: dict[str, str]) -> bool:
        """Check one ``(= (f ...) v)`` of :init; True for one to leave out (``borrowed``)."""
        if len(el.items) != 3 or not isinstance(el.items[1], SList):
            raise self.refuse("equality '(= ...)' in :init", el)
        term, value = el.items[1], el.items[2]
        if not isinstance(value, Tok) or not NUMBER_RE.fullmatch(value.text):
            raise self.fail(f"expected a number in {show(el)}", el)
        f = term.head
        if f == "total-cost":
            if not info.uses_total_cost:
                if self.borrowed:
                    self.left_out = True
                    return True
                raise self.fail("(total-cost) is not declared in the domain's :functions", el)
            return False
        if f is None or f not in info.functions:
            if self.borrowed and f is not None:
                self.left_out = True
                return True
            raise self.fail(f"undefined function '{f}' in :init", el)
        if len(term.items) - 1 != info.functions[f]:
            raise self.fail(
                f"function '{f}' takes {info.functions[f]} argument(s), "
                f"got {len(term.items) - 1} in :init",
                term,
            )
        self.terms(term.items[1:], None, objects, ":init")
        if not INT_RE.fullmatch(value.text) or value.text.startswith("-"):
            raise self.refuse(
                f"cost function value {value.text} (costs must be non-negative integers)", el
            )
        key = tuple(t.text for t in term.items)
        number = int(value.text.split(".")[0])  # INT_RE: an integer, maybe written "2.0"
        old = self.values.setdefault(key, number)
        if old != number:  # which one counts would be a guess
            shown = f"({' '.join(key)})"
            raise self.fail(f"{shown} is given two values ({old} and {value.text})", el)
        return False

    def goal(self, node: Node, info: DomainInfo, objects: dict[str, str]) -> None:
        if isinstance(node, SList) and node.head == "and":
            for sub in node.items[1:]:
                self.goal(sub, info, objects)
        elif isinstance(node, SList) and node.head not in KEYWORDS and node.head is not None:
            self.atom(node, info, None, objects, ":goal")
        elif (
            isinstance(node, SList)
            and node.head == "not"
            and len(node.items) == 2
            and isinstance(node.items[1], SList)
            and node.items[1].head not in KEYWORDS
            and node.items[1].head not in (None, "=")
        ):  # a negative goal
            self.atom(node.items[1], info, None, objects, ":goal")
        else:
            self.condition(node, info, set(), ":goal", goal=True)
            raise self.fail(f"unexpected {show(node)} in :goal", node)

    def metric(self, node: SList, info: DomainInfo) -> None:
        items = node.items
        ok = (
            len(items) == 3
            and isinstance(items[1], Tok)
            and items[1].text == "minimize"
            and isinstance(items[2], SList)
            and len(items[2].items) == 1
            and items[2].head == "total-cost"
        )
        if not ok:
            raise self.refuse("metric other than 'minimize (total-cost)'", node)
        if not info.uses_total_cost:
            raise self.fail("the metric uses (total-cost), which the domain does not declare", node)
