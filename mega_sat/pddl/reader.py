"""Read PDDL domain + problem files into a normalised :class:`~mega_sat.model.lifted.Model`.

Reading happens in two passes, so that every refusal is a one-line :class:`PDDLError` naming the
file, the line and the construct, never a raw library traceback:

1. **Check.**  The text is lower-cased (PDDL is case-insensitive), ``;`` comments are blanked
   out, and the file is read into s-expressions that remember their line.  A structural walk
   then refuses everything mega-sat does not support and checks names and arities:

   * refused constructs: conditional effects (``when``), quantifiers (``forall``, ``exists``),
     disjunctions (``or``, ``imply``, negated compound conditions), equality ``(= ?x ?y)``,
     numeric comparisons, numeric effects other than ``(increase (total-cost) ...)``
     (``decrease``, ``assign``, ``scale-up``, ``scale-down``, increases of other functions),
     ``oneof``, ``either`` types (except in predicate and function declarations, whose argument
     types are ignored anyway), ``:derived``, ``:durative-action``, ``:process``, ``:event``,
     ``:constraints``, object fluents, timed initial literals, negative or non-conjunctive goals,
     cost expressions other than a non-negative integer or a static function term, and metrics
     other than ``minimize (total-cost)``;
   * requirement flags: a flag only *permits* constructs, so flags whose constructs are
     detected one by one (``:adl``, ``:equality``, ``:conditional-effects``,
     ``:disjunctive-preconditions``, the quantifier flags, ``:derived-predicates``,
     ``:numeric-fluents``, ``:fluents``) are accepted and only an actual use is refused.  Flags
     outside classical planning (``:durative-actions``, ``:timed-initial-literals``,
     ``:preferences``, ``:constraints``, ``:object-fluents``, ...) and unknown flags are
     refused, since a file declaring them almost certainly relies on them;
   * missing flags are tolerated (as Fast Downward does: ``(not ...)`` without
     ``:negative-preconditions``, types without ``:typing``), except that an action cost
     ``(increase (total-cost) ...)`` requires ``:action-costs``: without it every action costs 1
     and silently dropping a cost effect would change the task.

2. **Parse.**  The checked text goes to the ``pddl`` package (its requirements section replaced
   by one that admits everything the check let through, keeping line numbers), and its objects
   are converted into a :class:`Model`.  Types are compiled into static unary predicates as
   :mod:`mega_sat.model.lifted` describes; a type whose name is also a predicate is an error.  With
   ``:action-costs`` an action without a cost effect costs 0 (the PDDL semantics), and costs
   come from the domain whether or not the problem states ``(:metric minimize (total-cost))``.
   Negative initial literals ``(not p)`` are dropped (closed world), as is
   ``(= (total-cost) 0)``.
"""

from __future__ import annotations

import functools
import re
import warnings
from collections.abc import Iterator
from dataclasses import dataclass, field
from pathlib import Path

from mega_sat.errors import PDDLError
from mega_sat.model.lifted import Atom, CostTerm, Model, Schema


class PDDLWarning(UserWarning):
    """Something in a PDDL file that mega-sat reads anyway but the user should know about."""


# ----------------------------------------------------------------------------------------------
# s-expressions with line numbers


@dataclass(frozen=True)
class _Tok:
    text: str
    line: int
    end: int


@dataclass(frozen=True)
class _List:
    items: tuple[_Tok | _List, ...]
    line: int
    start: int
    end: int

    @property
    def head(self) -> str | None:
        if self.items and isinstance(self.items[0], _Tok):
            return self.items[0].text
        return None


_Node = _Tok | _List
_TOKEN_RE = re.compile(r"\(|\)|[^\s()]+")
_COMMENT_RE = re.compile(r";[^\n]*")


def normalise_text(text: str) -> str:
    """Lower-case ``text`` and blank out ``;`` comments and a leading byte-order mark, keeping
    every offset and line."""
    if text.startswith("\ufeff"):
        text = " " + text[1:]
    return _COMMENT_RE.sub(lambda m: " " * len(m.group()), text.lower())


def _indent(text: str, pos: int) -> int:
    """Column of the first non-blank character of the line holding ``pos``."""
    start = text.rfind("\n", 0, pos) + 1
    line = text[start:pos]
    return len(line) - len(line.lstrip())


def _read_sexpr(text: str, path: str) -> _List:
    """The single top-level list of a normalised PDDL file."""
    stack: list[tuple[int, int, list[_Node]]] = []
    top: list[_Node] = []
    line, pos = 1, 0
    # where a '(' left open most likely is: the first form that starts a line at or left of
    # the indentation of a form still open (below the outermost), which it should have closed,
    # or the first section keyword (':effect') inside a condition or atom
    suspect: tuple[int, str, int] | None = None
    # failing those, a list whose first element is a list, which PDDL never writes: its '('
    # is most likely one too many
    nested_head: int | None = None
    for m in _TOKEN_RE.finditer(text):
        line += text.count("\n", pos, m.start())
        pos = m.start()
        tok = m.group()
        if not stack and top:
            raise PDDLError(
                "unexpected text after the end of '(define ...)' (a ')' too many before it?)",
                path=path,
                where=f"line {line}",
            )
        if tok == "(":
            if (
                suspect is None
                and len(stack) > 1
                and stack[-1][0] < line
                and not text[text.rfind("\n", 0, pos) + 1 : pos].strip()
                and _indent(text, pos) <= _indent(text, stack[-1][1])
            ):
                suspect = (stack[-1][0], "the form", line)
            if nested_head is None and stack and not stack[-1][2]:
                nested_head = stack[-1][0]
            stack.append((line, m.start(), []))
        elif tok == ")":
            if not stack:
                raise PDDLError(
                    "unexpected ')' (unbalanced parentheses)", path=path, where=f"line {line}"
                )
            l0, s0, items = stack.pop()
            if (
                suspect is None
                and stack
                and l0 < line
                and not text[text.rfind("\n", 0, pos) + 1 : pos].strip()
                and _indent(text, pos) < _indent(text, s0)
                and _indent(text, pos) <= _indent(text, stack[-1][1])
            ):
                # a ')' alone at the start of a line, left of the form it closes and as far
                # left as the form around it: meant for an outer form, so this one was left open
                suspect = (l0, "the ')'", line)
            node = _List(tuple(items), l0, s0, m.end())
            (stack[-1][2] if stack else top).append(node)
        else:
            if suspect is None and tok.startswith(":") and stack and stack[-1][2]:
                head = stack[-1][2][0]  # a list never starts with a list in PDDL
                if isinstance(head, _List) or (
                    not head.text.startswith(":") and head.text != "define"
                ):
                    suspect = (stack[-1][0], f"'{tok}'", line)
            (stack[-1][2] if stack else top).append(_Tok(tok, line, m.end()))
    if stack:
        if suspect is not None:
            opened, what, inside = suspect
            how = (
                "closes it, indented like an outer form's" if what == "the ')'" else "is inside it"
            )
            raise PDDLError(
                f"'(' is never closed (unbalanced parentheses): {what} on line {inside} "
                f"{how} (a ')' missing before line {inside}, or a '(' too many)",
                path=path,
                where=f"line {opened}",
            )
        if nested_head is not None:
            raise PDDLError(
                "'(' is never closed (unbalanced parentheses): a list here starts with another "
                "list (a '(' too many)",
                path=path,
                where=f"line {nested_head}",
            )
        raise PDDLError(
            "'(' is never closed (unbalanced parentheses)", path=path, where=f"line {stack[-1][0]}"
        )
    if not top:
        raise PDDLError("file is empty", path=path)
    if not isinstance(top[0], _List):
        raise PDDLError("expected '(define ...)'", path=path, where=f"line {top[0].line}")
    return top[0]


# ----------------------------------------------------------------------------------------------
# pass 1: the check

_ACCEPTED_REQS = frozenset({
    ":strips", ":typing", ":negative-preconditions", ":action-costs", ":equality", ":adl",
    ":conditional-effects", ":disjunctive-preconditions", ":existential-preconditions",
    ":universal-preconditions", ":quantified-preconditions", ":derived-predicates",
    ":numeric-fluents", ":fluents",
})  # fmt: skip
_REFUSED_REQS = {
    ":durative-actions": "durative actions",
    ":duration-inequalities": "duration inequalities",
    ":continuous-effects": "continuous effects",
    ":timed-initial-literals": "timed initial literals",
    ":preferences": "preferences",
    ":constraints": "state-trajectory constraints",
    ":object-fluents": "object fluents",
    ":non-deterministic": "non-deterministic effects",
    ":probabilistic-effects": "probabilistic effects",
}
_REFUSED_SECTIONS = {
    ":derived": "derived predicates (:derived)",
    ":durative-action": "durative actions (:durative-action)",
    ":process": "processes (:process)",
    ":event": "events (:event)",
    ":constraints": "state-trajectory constraints (:constraints)",
}
_CONDITION_REFUSALS = {
    "or": "disjunction 'or'",
    "imply": "implication 'imply'",
    "forall": "universal quantifier 'forall'",
    "exists": "existential quantifier 'exists'",
    "when": "conditional effect 'when'",
    "oneof": "non-deterministic effect 'oneof'",
    "<": "numeric comparison '<'",
    ">": "numeric comparison '>'",
    "<=": "numeric comparison '<='",
    ">=": "numeric comparison '>='",
    "either": "'either' type",
}
_EFFECT_REFUSALS = {
    "when": "conditional effect 'when'",
    "forall": "universal effect 'forall'",
    "oneof": "non-deterministic effect 'oneof'",
    "decrease": "numeric effect 'decrease' (numeric fluents)",
    "assign": "numeric effect 'assign' (numeric fluents)",
    "scale-up": "numeric effect 'scale-up' (numeric fluents)",
    "scale-down": "numeric effect 'scale-down' (numeric fluents)",
    "or": "disjunction 'or'",
    "exists": "existential quantifier 'exists'",
}
_KEYWORDS = frozenset({"and", "not", "=", *_CONDITION_REFUSALS, *_EFFECT_REFUSALS, "increase"})
_INT_RE = re.compile(r"-?[0-9]+(\.0*)?")
_NUMBER_RE = re.compile(r"-?[0-9]+(\.[0-9]*)?")


@dataclass
class _DomainInfo:
    """What the problem check needs from the domain, and where to splice requirements."""

    name: str = ""
    requirements: set[str] = field(default_factory=set)
    types: dict[str, str] = field(default_factory=dict)
    constants: dict[str, str] = field(default_factory=dict)
    predicates: dict[str, int] = field(default_factory=dict)
    functions: dict[str, int] = field(default_factory=dict)
    uses_total_cost: bool = False
    req_node: _List | None = None
    name_node: _List | None = None
    edits: list[tuple[int, int, str]] = field(default_factory=list)
    """Text edits (start, end, replacement) that let the pddl package read valid PDDL."""


class _Checker:
    """The structural walk of pass 1; raises :class:`PDDLError` at the first problem."""

    def __init__(self, path: str):
        self.path = path

    def fail(self, message: str, node: _Node | None) -> PDDLError:
        where = f"line {node.line}" if node is not None else None
        return PDDLError(message, path=self.path, where=where)

    def refuse(self, construct: str, node: _Node) -> PDDLError:
        return self.fail(f"{construct} is not supported by mega-sat", node)

    # -- shared helpers ------------------------------------------------------------------------

    def header(self, root: _List, kind: str) -> tuple[_List, str]:
        """Check ``(define (kind NAME) ...)``; return the name node and the name."""
        if root.head != "define":
            raise self.fail("expected '(define ...)'", root)
        if len(root.items) < 2 or not isinstance(root.items[1], _List):
            raise self.fail(f"expected '({kind} NAME)' after 'define'", root)
        node = root.items[1]
        other = "problem" if kind == "domain" else "domain"
        if node.head == other:
            raise self.fail(f"this is a {other} file, expected a {kind} file", node)
        if node.head != kind or len(node.items) != 2 or not isinstance(node.items[1], _Tok):
            raise self.fail(f"expected '({kind} NAME)' after 'define'", node)
        return node, node.items[1].text

    def sections(self, root: _List) -> Iterator[tuple[str, _List]]:
        for node in root.items[2:]:
            if not isinstance(node, _List) or not (node.head or "").startswith(":"):
                raise self.fail(f"expected a section '(:keyword ...)', got {_show(node)}", node)
            yield node.head or "", node

    def requirements(self, node: _List) -> set[str]:
        out = set()
        for tok in node.items[1:]:
            if not isinstance(tok, _Tok):
                raise self.fail("malformed :requirements", tok)
            if tok.text in _REFUSED_REQS:
                raise self.refuse(f"requirement {tok.text} ({_REFUSED_REQS[tok.text]})", tok)
            if tok.text not in _ACCEPTED_REQS:
                raise self.fail(f"unknown requirement '{tok.text}'", tok)
            out.add(tok.text)
        return out

    def typed_list(
        self, items: tuple[_Node, ...], what: str, *, either_ok: bool = False
    ) -> list[tuple[_Tok, str]]:
        """``a b - t c`` as ``[(a, t), (b, t), (c, object)]``."""
        out: list[tuple[_Tok, str]] = []
        pending: list[_Tok] = []
        i = 0
        while i < len(items):
            it = items[i]
            if isinstance(it, _Tok) and it.text == "-":
                if not pending:
                    raise self.fail(f"'-' without a name before it in {what}", it)
                if i + 1 >= len(items):
                    raise self.fail(f"missing type after '-' in {what}", it)
                t = items[i + 1]
                if isinstance(t, _List):
                    if t.head != "either":
                        raise self.fail(f"malformed type {_show(t)} in {what}", t)
                    if not either_ok:
                        raise self.refuse("'either' type", t)
                    typ = "object"
                else:
                    typ = t.text
                out.extend((p, typ) for p in pending)
                pending = []
                i += 2
                continue
            if isinstance(it, _List):
                raise self.fail(f"unexpected {_show(it)} in {what}", it)
            pending.append(it)
            i += 1
        out.extend((p, "object") for p in pending)
        return out

    def check_type(self, typ: str, types: dict[str, str], node: _Node, what: str) -> None:
        if typ != "object" and typ not in types:
            raise self.fail(f"undefined type '{typ}' in {what}", node)

    def atom(
        self,
        node: _List,
        info: _DomainInfo,
        variables: set[str] | None,
        names: set[str] | dict[str, str],
        what: str,
    ) -> None:
        """Check predicate, arity and arguments of an atom; ``variables`` None: no variables."""
        pred = node.head
        if pred is None:
            raise self.fail(f"expected an atom in {what}, got {_show(node)}", node)
        if pred not in info.predicates:
            raise self.fail(f"undefined predicate '{pred}' in {what}", node)
        args = node.items[1:]
        if len(args) != info.predicates[pred]:
            raise self.fail(
                f"predicate '{pred}' takes {info.predicates[pred]} argument(s), "
                f"got {len(args)} in {what}",
                node,
            )
        self.terms(args, variables, names, what)

    def terms(
        self,
        args: tuple[_Node, ...],
        variables: set[str] | None,
        names: set[str] | dict[str, str],
        what: str,
    ) -> None:
        for a in args:
            if isinstance(a, _List):
                raise self.fail(f"unexpected {_show(a)} as an argument in {what}", a)
            if a.text.startswith("?"):
                if variables is None:
                    raise self.fail(f"variable '{a.text}' in {what}", a)
                if a.text not in variables:
                    raise self.fail(f"undefined variable '{a.text}' in {what}", a)
            elif a.text not in names:
                kind = "constant" if variables is not None else "object"
                raise self.fail(f"undefined {kind} '{a.text}' in {what}", a)

    def equality_or_comparison(self, node: _List) -> PDDLError:
        """``(= a b)``: equality of terms, or a numeric comparison when a side is a term."""
        if any(isinstance(x, _List) or _NUMBER_RE.fullmatch(x.text) for x in node.items[1:]):
            return self.refuse("numeric comparison '='", node)
        return self.refuse("equality '(= ...)'", node)

    # -- domain --------------------------------------------------------------------------------

    def domain(self, root: _List) -> _DomainInfo:
        info = _DomainInfo()
        info.name_node, info.name = self.header(root, "domain")
        actions: list[_List] = []
        for key, node in self.sections(root):
            if len(node.items) == 1 and key in (
                ":types",
                ":constants",
                ":predicates",
                ":functions",
            ):
                info.edits.append((node.start, node.end, ""))  # valid, but trips up pddl
            elif key == ":requirements":
                info.requirements |= self.requirements(node)
                info.req_node = node
            elif key == ":types":
                self.types(node, info)
            elif key == ":constants":
                for tok, typ in self.typed_list(node.items[1:], ":constants"):
                    info.constants[tok.text] = typ
                    self.check_type(typ, info.types, tok, ":constants")
            elif key == ":predicates":
                self.predicates(node, info)
            elif key == ":functions":
                self.functions(node, info)
            elif key == ":action":
                actions.append(node)
            elif key in _REFUSED_SECTIONS:
                raise self.refuse(_REFUSED_SECTIONS[key], node)
            else:
                raise self.fail(f"unknown domain section '{key}'", node)
        seen: set[str] = set()
        for node in actions:
            name = self.action(node, info)
            if name in seen:
                raise self.fail(f"action '{name}' is defined twice", node)
            seen.add(name)
        return info

    def types(self, node: _List, info: _DomainInfo) -> None:
        for tok, parent in self.typed_list(node.items[1:], ":types"):
            t = tok.text
            if t == "object":
                if parent != "object":
                    raise self.fail("type 'object' cannot have a supertype", tok)
                continue
            old = info.types.get(t, "object")
            if old not in ("object", parent) and parent != "object":
                raise self.fail(
                    f"type '{t}' is declared with two supertypes ('{old}' and '{parent}')",
                    tok,
                )
            if old == "object":  # a plain 'a b c' entry does not override 'a - t'
                info.types[t] = parent
            if parent != "object":
                info.types.setdefault(parent, "object")
        for t in info.types:  # cycles
            seen, cur = {t}, info.types[t]
            while cur != "object":
                if cur in seen:
                    raise self.fail(f"cycle in the type hierarchy through '{t}'", node)
                seen.add(cur)
                cur = info.types.get(cur, "object")

    def predicates(self, node: _List, info: _DomainInfo) -> None:
        for p in node.items[1:]:
            if not isinstance(p, _List) or p.head is None:
                raise self.fail(f"malformed predicate declaration {_show(p)}", p)
            args = self.typed_list(p.items[1:], f"predicate '{p.head}'", either_ok=True)
            if p.head in info.types:
                raise self.fail(
                    f"'{p.head}' is both a type and a predicate (types become predicates)", p
                )
            if p.head in info.predicates and info.predicates[p.head] != len(args):
                raise self.fail(f"predicate '{p.head}' is declared twice", p)
            info.predicates[p.head] = len(args)

    def functions(self, node: _List, info: _DomainInfo) -> None:
        items = node.items[1:]
        i = 0
        while i < len(items):
            f = items[i]
            if isinstance(f, _Tok) and f.text == "-":
                t = items[i + 1] if i + 1 < len(items) else None
                if not isinstance(t, _Tok) or t.text != "number":
                    raise self.refuse("non-numeric function (object fluents)", t or f)
                i += 2
                continue
            if not isinstance(f, _List) or f.head is None:
                raise self.fail(f"malformed function declaration {_show(f)}", f)
            args = self.typed_list(f.items[1:], f"function '{f.head}'", either_ok=True)
            if f.head == "total-cost":
                if args:
                    raise self.fail("'total-cost' takes no arguments", f)
                info.uses_total_cost = True
            else:
                info.functions[f.head] = len(args)
            i += 1

    def action(self, node: _List, info: _DomainInfo) -> str:
        items = node.items
        if len(items) < 2 or not isinstance(items[1], _Tok) or items[1].text.startswith(":"):
            raise self.fail("expected an action name after ':action'", node)
        name = items[1].text
        what = f"action '{name}'"
        parts: dict[str, _Node] = {}
        i = 2
        while i < len(items):
            key = items[i]
            if not isinstance(key, _Tok) or key.text not in (
                ":parameters",
                ":precondition",
                ":effect",
            ):
                raise self.fail(f"unexpected {_show(key)} in {what}", key)
            if i + 1 >= len(items):
                raise self.fail(f"missing value after '{key.text}' in {what}", key)
            parts[key.text] = items[i + 1]
            i += 2
        self.complete_action(node, parts, info)
        variables: set[str] = set()
        params = parts.get(":parameters")
        if params is not None:
            if not isinstance(params, _List):
                raise self.fail(f"expected a parameter list in {what}", params)
            for tok, typ in self.typed_list(params.items, f"the parameters of {what}"):
                if not tok.text.startswith("?"):
                    raise self.fail(f"parameter '{tok.text}' of {what} must start with '?'", tok)
                if tok.text in variables:
                    raise self.fail(f"duplicate parameter '{tok.text}' in {what}", tok)
                self.check_type(typ, info.types, tok, f"the parameters of {what}")
                variables.add(tok.text)
        pre = parts.get(":precondition")
        if pre is not None:
            self.condition(pre, info, variables, f"the precondition of {what}")
        eff = parts.get(":effect")
        if eff is not None and self.effect(eff, info, variables, f"the effect of {what}") > 1:
            raise self.fail(f"more than one (increase (total-cost) ...) in {what}", eff)
        return name

    def complete_action(self, node: _List, parts: dict[str, _Node], info: _DomainInfo) -> None:
        """Schedule inserting omitted parts: the pddl package needs all three, in order."""
        name = node.items[1]
        pos = name.end
        missing = ""
        for key, empty in ((":parameters", "()"), (":precondition", "(and)")):
            if key in parts:
                if missing:
                    info.edits.append((pos, pos, missing))
                    missing = ""
                pos = parts[key].end
            else:
                missing += f" {key} {empty}"
        if missing:
            info.edits.append((pos, pos, missing))
        if ":effect" not in parts:
            info.edits.append((node.end - 1, node.end - 1, " :effect (and)"))

    def condition(
        self, node: _Node, info: _DomainInfo, variables: set[str], what: str, *, goal=False
    ) -> None:
        if not isinstance(node, _List):
            raise self.fail(f"expected a condition in {what}, got {_show(node)}", node)
        head = node.head
        if head == "and" or not node.items:
            for sub in node.items[1:]:
                self.condition(sub, info, variables, what, goal=goal)
        elif head == "not":
            if goal:
                raise self.refuse("negative goal 'not'", node)
            if len(node.items) != 2 or not isinstance(node.items[1], _List):
                raise self.fail(f"malformed 'not' in {what}", node)
            sub = node.items[1]
            if sub.head == "=":
                raise self.equality_or_comparison(sub)
            if sub.head in _KEYWORDS or sub.head is None:
                raise self.refuse(f"negation of a compound condition '(not ({sub.head} ...))'", sub)
            self.atom(sub, info, variables, info.constants, what)
        elif head == "=":
            raise self.equality_or_comparison(node)
        elif head in _CONDITION_REFUSALS:
            construct = _CONDITION_REFUSALS[head]
            if goal and head in ("or", "imply", "forall", "exists"):
                construct = f"non-conjunctive goal ({construct})"
            raise self.refuse(construct, node)
        else:
            self.atom(node, info, variables, info.constants, what)

    def effect(self, node: _Node, info: _DomainInfo, variables: set[str], what: str) -> int:
        """Check an effect; return how many total-cost increases it has."""
        if not isinstance(node, _List):
            raise self.fail(f"expected an effect in {what}, got {_show(node)}", node)
        head = node.head
        if head == "and" or not node.items:
            return sum(self.effect(sub, info, variables, what) for sub in node.items[1:])
        if head == "not":
            if len(node.items) != 2 or not isinstance(node.items[1], _List):
                raise self.fail(f"malformed 'not' in {what}", node)
            sub = node.items[1]
            if sub.head in _KEYWORDS or sub.head is None:
                raise self.fail(f"expected an atom inside 'not' in {what}", sub)
            self.atom(sub, info, variables, info.constants, what)
            return 0
        if head == "increase":
            self.increase(node, info, variables, what)
            return 1
        if head in _EFFECT_REFUSALS:
            raise self.refuse(_EFFECT_REFUSALS[head], node)
        self.atom(node, info, variables, info.constants, what)
        return 0

    def increase(self, node: _List, info: _DomainInfo, variables: set[str], what: str) -> None:
        if len(node.items) != 3:
            raise self.fail(f"malformed 'increase' in {what}", node)
        target, value = node.items[1], node.items[2]
        if not (isinstance(target, _List) and target.head == "total-cost"):
            raise self.refuse(
                f"numeric effect 'increase' of {_show(target)} (numeric fluents)", node
            )
        if not info.uses_total_cost:
            raise self.fail("(total-cost) is used but not declared in :functions", node)
        if ":action-costs" not in info.requirements:
            raise self.fail("(increase (total-cost) ...) needs the requirement :action-costs", node)
        if isinstance(value, _Tok):
            if not _INT_RE.fullmatch(value.text) or value.text.startswith("-"):
                raise self.refuse(
                    f"action cost '{value.text}' (costs must be non-negative integers)", value
                )
            return
        f = value.head
        if f is None or f not in info.functions:
            if f in ("+", "-", "*", "/"):
                raise self.refuse(
                    f"cost expression '({f} ...)' (only a number or a static function term)",
                    value,
                )
            raise self.fail(f"undefined function '{f}' in {what}", value)
        if len(value.items) - 1 != info.functions[f]:
            raise self.fail(
                f"function '{f}' takes {info.functions[f]} argument(s), "
                f"got {len(value.items) - 1} in {what}",
                value,
            )
        self.terms(value.items[1:], variables, info.constants, what)

    # -- problem -------------------------------------------------------------------------------

    def problem(self, root: _List, info: _DomainInfo) -> list[_List]:
        """Check a problem against ``info``; return the nodes to drop before parsing."""
        self.header(root, "problem")
        drop: list[_List] = []
        objects: dict[str, str] = dict(info.constants)
        saw_init = saw_goal = False
        for key, node in self.sections(root):
            if key == ":domain":
                named = node.items[1] if len(node.items) == 2 else None
                if isinstance(named, _Tok) and named.text != info.name:
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
                for tok, typ in self.typed_list(node.items[1:], ":objects"):
                    self.check_type(typ, info.types, tok, ":objects")
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
                    self.init_element(el, info, objects)
            elif key == ":goal":
                saw_goal = True
                if len(node.items) != 2:
                    raise self.fail("expected one condition in :goal", node)
                self.goal(node.items[1], info, objects)
            elif key == ":metric":
                self.metric(node, info)
            elif key == ":constraints":
                raise self.refuse(_REFUSED_SECTIONS[key], node)
            else:
                raise self.fail(f"unknown problem section '{key}'", node)
        if not saw_init:
            raise self.fail("missing (:init ...)", root)
        if not saw_goal:
            raise self.fail("missing (:goal ...)", root)
        return drop

    def init_element(self, el: _Node, info: _DomainInfo, objects: dict[str, str]) -> None:
        if not isinstance(el, _List):
            raise self.fail(f"expected an atom in :init, got {_show(el)}", el)
        if el.head == "=":
            self.function_value(el, info, objects)
        elif el.head == "not":
            if len(el.items) != 2 or not isinstance(el.items[1], _List):
                raise self.fail("malformed 'not' in :init", el)
            self.atom(el.items[1], info, None, objects, ":init")
        elif (
            el.head == "at"
            and len(el.items) == 3
            and isinstance(el.items[1], _Tok)
            and _NUMBER_RE.fullmatch(el.items[1].text)
            and isinstance(el.items[2], _List)
        ):
            raise self.refuse("timed initial literal '(at TIME ...)'", el)
        else:
            self.atom(el, info, None, objects, ":init")

    def function_value(self, el: _List, info: _DomainInfo, objects: dict[str, str]) -> None:
        if len(el.items) != 3 or not isinstance(el.items[1], _List):
            raise self.refuse("equality '(= ...)' in :init", el)
        term, value = el.items[1], el.items[2]
        if not isinstance(value, _Tok) or not _NUMBER_RE.fullmatch(value.text):
            raise self.fail(f"expected a number in {_show(el)}", el)
        f = term.head
        if f == "total-cost":
            if not info.uses_total_cost:
                raise self.fail("(total-cost) is not declared in the domain's :functions", el)
            return
        if f is None or f not in info.functions:
            raise self.fail(f"undefined function '{f}' in :init", el)
        if len(term.items) - 1 != info.functions[f]:
            raise self.fail(
                f"function '{f}' takes {info.functions[f]} argument(s), "
                f"got {len(term.items) - 1} in :init",
                term,
            )
        self.terms(term.items[1:], None, objects, ":init")
        if not _INT_RE.fullmatch(value.text) or value.text.startswith("-"):
            raise self.refuse(
                f"cost function value {value.text} (costs must be non-negative integers)", el
            )

    def goal(self, node: _Node, info: _DomainInfo, objects: dict[str, str]) -> None:
        if isinstance(node, _List) and node.head == "and":
            for sub in node.items[1:]:
                self.goal(sub, info, objects)
        elif isinstance(node, _List) and node.head not in _KEYWORDS and node.head is not None:
            self.atom(node, info, None, objects, ":goal")
        else:
            self.condition(node, info, set(), ":goal", goal=True)
            raise self.fail(f"unexpected {_show(node)} in :goal", node)

    def metric(self, node: _List, info: _DomainInfo) -> None:
        items = node.items
        ok = (
            len(items) == 3
            and isinstance(items[1], _Tok)
            and items[1].text == "minimize"
            and isinstance(items[2], _List)
            and len(items[2].items) == 1
            and items[2].head == "total-cost"
        )
        if not ok:
            raise self.refuse("metric other than 'minimize (total-cost)'", node)
        if not info.uses_total_cost:
            raise self.fail("the metric uses (total-cost), which the domain does not declare", node)


def _show(node: _Node | None) -> str:
    if node is None:
        return "nothing"
    if isinstance(node, _Tok):
        return f"'{node.text}'"
    return f"'({node.head or ''} ...)'" if node.items else "'()'"


# ----------------------------------------------------------------------------------------------
# pass 2: the pddl package

_PDDL_DOMAIN_REQS = (
    "(:requirements :strips :typing :negative-preconditions :action-costs :numeric-fluents)"
)


def _splice(text: str, start: int, end: int, replacement: str) -> str:
    """Replace ``text[start:end]``, keeping the line count so parser line numbers stay right."""
    return text[:start] + replacement + "\n" * text.count("\n", start, end) + text[end:]


@functools.cache
def _parsers():
    from pddl.parser.domain import DomainParser
    from pddl.parser.problem import ProblemParser

    return DomainParser(), ProblemParser()


def _run_parser(which: int, text: str, path: str):
    """Parse with the ``pddl`` package; every exception becomes a one-line PDDLError."""
    parser = _parsers()[which]
    transformer = getattr(parser, "_transformer", None)
    if transformer is not None:  # reset per-file state left by an earlier parse
        transformer.__init__()
    try:
        return parser(text)
    except Exception as e:  # anything the library raises is a problem of the file
        raise _wrap_library_error(e, path) from None


def _wrap_library_error(e: Exception, path: str) -> PDDLError:
    from lark.exceptions import (
        UnexpectedCharacters,
        UnexpectedEOF,
        UnexpectedInput,
        UnexpectedToken,
    )

    line = getattr(e, "line", None)
    where = f"line {line}" if isinstance(line, int) and line > 0 else None
    if isinstance(e, UnexpectedToken):
        msg = f"syntax error: unexpected '{e.token}'"
    elif isinstance(e, UnexpectedCharacters):
        msg = f"syntax error: unexpected character '{e.char}'"
    elif isinstance(e, UnexpectedEOF):
        msg = "syntax error: unexpected end of file"
    elif isinstance(e, UnexpectedInput):
        msg = "syntax error"
    else:
        orig = getattr(e, "orig_exc", None) or e  # lark's VisitError wraps the real one
        text = " ".join(str(orig).split()) or type(orig).__name__
        msg = f"invalid PDDL: {text}"
    return PDDLError(msg, path=path, where=where)


# ----------------------------------------------------------------------------------------------
# conversion


def _term(t) -> str:
    from pddl.logic.terms import Variable

    return f"?{t.name}" if isinstance(t, Variable) else str(t.name)


def _atom(p) -> Atom:
    return (str(p.name), *(_term(t) for t in p.terms))


def _conjuncts(formula) -> list:
    """The literals of a (possibly nested, possibly empty) conjunction."""
    from pddl.logic.base import And, Or

    if formula is None:
        return []
    if isinstance(formula, And):
        return [x for op in formula.operands for x in _conjuncts(op)]
    if isinstance(formula, Or) and not formula.operands:  # '()' parses as an empty Or
        return []
    return [formula]


def _unexpected(what: object, path: str) -> PDDLError:
    return PDDLError(f"unsupported construct {what}", path=path)


def _schema(action, uses_costs: bool, path: str) -> Schema:
    from pddl.logic.base import Not
    from pddl.logic.functions import Increase, NumericFunction, NumericValue
    from pddl.logic.predicates import Predicate

    params = tuple(f"?{v.name}" for v in action.parameters)
    signature = frozenset(
        (str(tag), f"?{v.name}")
        for v in action.parameters
        for tag in v.type_tags
        if str(tag) != "object"
    )
    pre: set[Atom] = set(signature)
    negpre: set[Atom] = set()
    for lit in _conjuncts(action.precondition):
        if isinstance(lit, Predicate):
            pre.add(_atom(lit))
        elif isinstance(lit, Not) and isinstance(lit.argument, Predicate):
            negpre.add(_atom(lit.argument))
        else:
            raise _unexpected(lit, path)
    add: set[Atom] = set()
    delete: set[Atom] = set()
    cost: int | CostTerm = 0 if uses_costs else 1
    for lit in _conjuncts(action.effect):
        if isinstance(lit, Predicate):
            add.add(_atom(lit))
        elif isinstance(lit, Not) and isinstance(lit.argument, Predicate):
            delete.add(_atom(lit.argument))
        elif isinstance(lit, Increase):
            value = lit.operands[1]
            if isinstance(value, NumericValue):
                cost = int(value.value)
            elif isinstance(value, NumericFunction):
                cost = (str(value.name), *(_term(t) for t in value.terms))
            else:
                raise _unexpected(value, path)
        else:
            raise _unexpected(lit, path)
    return Schema(
        str(action.name),
        params,
        frozenset(pre),
        frozenset(negpre),
        frozenset(add),
        frozenset(delete),
        cost,
        signature,
    )


def _type_atoms(obj: str, typ: str, types: dict[str, str]) -> set[Atom]:
    """``(t obj)`` for ``typ`` and each of its supertypes except ``object``."""
    out = set()
    while typ != "object":
        out.add((typ, obj))
        typ = types.get(typ, "object")
    return out


def parse_model(
    domain_text: str,
    problem_text: str,
    *,
    domain_path: str = "<domain>",
    problem_path: str = "<problem>",
) -> Model:
    """Parse a domain and a problem into a normalised :class:`Model`.

    Raises :class:`PDDLError` (file, line, construct) for malformed or unsupported PDDL.
    """
    from pddl.logic.base import Not
    from pddl.logic.functions import EqualTo as FunctionEqualTo
    from pddl.logic.predicates import Predicate

    dtext = normalise_text(domain_text)
    ptext = normalise_text(problem_text)
    dchk, pchk = _Checker(domain_path), _Checker(problem_path)
    info = dchk.domain(_read_sexpr(dtext, domain_path))
    drop = pchk.problem(_read_sexpr(ptext, problem_path), info)

    edits = list(info.edits)
    if info.req_node is not None:
        edits.append((info.req_node.start, info.req_node.end, _PDDL_DOMAIN_REQS))
    else:
        assert info.name_node is not None
        edits.append((info.name_node.end, info.name_node.end, " " + _PDDL_DOMAIN_REQS))
    for start, end, replacement in sorted(edits, reverse=True):
        dtext = _splice(dtext, start, end, replacement)
    for node in sorted(drop, key=lambda n: -n.start):
        ptext = _splice(ptext, node.start, node.end, "")

    domain = _run_parser(0, dtext, domain_path)
    problem = _run_parser(1, ptext, problem_path)

    types = info.types  # includes supertypes that are never declared on their own
    uses_costs = ":action-costs" in info.requirements
    schemas = {}
    for action in sorted(domain.actions, key=lambda a: str(a.name)):
        s = _schema(action, uses_costs, domain_path)
        schemas[s.name] = s

    predicates = {str(p.name): len(p.terms) for p in domain.predicates}
    type_preds = frozenset(t for t in types if t != "object")
    predicates.update((t, 1) for t in type_preds)

    objects: dict[str, str] = {}
    init: set[Atom] = set()
    for c in (*domain.constants, *problem.objects):
        tags = [str(t) for t in c.type_tags] or ["object"]
        objects[str(c.name)] = tags[0]
        init |= _type_atoms(str(c.name), tags[0], types)

    functions: dict[CostTerm, int] = {}
    for el in problem.init:
        if isinstance(el, Predicate):
            init.add(_atom(el))
        elif isinstance(el, FunctionEqualTo):
            term, value = el.operands
            if str(term.name) == "total-cost":
                continue
            functions[(str(term.name), *(_term(t) for t in term.terms))] = int(value.value)
        elif not isinstance(el, Not):  # negative initial literals: closed world, no-op
            raise _unexpected(el, problem_path)

    goal: set[Atom] = set()
    for lit in _conjuncts(problem.goal):
        if not isinstance(lit, Predicate):
            raise _unexpected(lit, problem_path)
        goal.add(_atom(lit))

    return Model(
        domain_name=str(domain.name),
        problem_name=str(problem.name),
        predicates=predicates,
        schemas=schemas,
        objects=frozenset(objects),
        init=frozenset(init),
        goal=frozenset(goal),
        type_predicates=type_preds,
        functions=functions,
        function_arities=dict(info.functions),
        uses_costs=uses_costs,
    )


def read_text(path: str | Path, what: str) -> str:
    """Read a text file; a missing or unreadable file is a :class:`PDDLError` naming it."""
    try:
        return Path(path).read_text(encoding="utf-8")
    except FileNotFoundError:
        raise PDDLError(f"{what} file not found", path=str(path)) from None
    except IsADirectoryError:
        raise PDDLError(f"{what} file is a directory", path=str(path)) from None
    except UnicodeDecodeError:
        raise PDDLError(f"{what} file is not UTF-8 text", path=str(path)) from None
    except OSError as e:
        raise PDDLError(f"cannot read {what} file: {e.strerror}", path=str(path)) from None


def read_model(domain_path: str | Path, problem_path: str | Path) -> Model:
    """Read a domain file and a problem file into a :class:`Model`."""
    return parse_model(
        read_text(domain_path, "domain"),
        read_text(problem_path, "problem"),
        domain_path=str(domain_path),
        problem_path=str(problem_path),
    )
