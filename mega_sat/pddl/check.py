"""Check PDDL s-expressions against what mega-sat reads, naming file, line and construct.

The check walks the s-expressions of :mod:`mega_sat.pddl.sexpr` and raises a one-line
:class:`PDDLError` at the first problem: a malformed form, an undefined or mis-used name, or a
construct mega-sat does not support.  This module checks the domain; the problem checks build on
it in :mod:`mega_sat.pddl.check_problem`.

* refused constructs: conditional effects (``when``), quantifiers (``forall``, ``exists``),
  disjunctions (``or``, ``imply``, negated compound conditions), equality ``(= ?x ?y)``
  outside preconditions (in preconditions it is read, as the static predicate ``=``), numeric
  comparisons, numeric effects other than ``(increase (total-cost) ...)``
  (``decrease``, ``assign``, ``scale-up``, ``scale-down``, increases of other functions),
  ``oneof``, ``either`` types (except in predicate and function declarations, whose argument
  types are ignored anyway), ``:derived``, ``:durative-action``, ``:process``, ``:event``,
  ``:constraints``, object fluents, timed initial literals, non-conjunctive goals,
  cost expressions other than a non-negative integer or a static function term, and metrics
  other than ``minimize (total-cost)``;
* requirement flags: a flag only *permits* constructs, so flags whose constructs are detected
  one by one (``:adl``, ``:equality``, ``:conditional-effects``, ``:disjunctive-preconditions``,
  the quantifier flags, ``:derived-predicates``, ``:numeric-fluents``, ``:fluents``) are
  accepted and only an actual use is refused.  Flags outside classical planning
  (``:durative-actions``, ``:timed-initial-literals``, ``:preferences``, ``:constraints``,
  ``:object-fluents``, ...) and unknown flags are refused, since a file declaring them almost
  certainly relies on them;
* missing flags are tolerated (as Fast Downward does: ``(not ...)`` without
  ``:negative-preconditions``, types without ``:typing``), except that an action cost
  ``(increase (total-cost) ...)`` requires ``:action-costs``: without it every action costs 1
  and silently dropping a cost effect would change the task.
"""

from __future__ import annotations

import functools
import re
from collections.abc import Iterator
from dataclasses import dataclass, field

from mega_sat.errors import PDDLError
from mega_sat.model.lifted import unused_name
from mega_sat.pddl.sexpr import Node, SList, Tok, show

ACCEPTED_REQS = frozenset({
    ":strips", ":typing", ":negative-preconditions", ":action-costs", ":equality", ":adl",
    ":conditional-effects", ":disjunctive-preconditions", ":existential-preconditions",
    ":universal-preconditions", ":quantified-preconditions", ":derived-predicates",
    ":numeric-fluents", ":fluents",
})  # fmt: skip
REFUSED_REQS = {
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
REFUSED_SECTIONS = {
    ":derived": "derived predicates (:derived)",
    ":durative-action": "durative actions (:durative-action)",
    ":process": "processes (:process)",
    ":event": "events (:event)",
    ":constraints": "state-trajectory constraints (:constraints)",
}
CONDITION_REFUSALS = {
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
EFFECT_REFUSALS = {
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
KEYWORDS = frozenset({"and", "not", "=", *CONDITION_REFUSALS, *EFFECT_REFUSALS, "increase"})
INT_RE = re.compile(r"-?[0-9]+(\.0*)?")
NUMBER_RE = re.compile(r"-?[0-9]+(\.[0-9]*)?")


@dataclass
class DomainInfo:
    """What the problem check and the conversion need from the domain."""

    name: str = ""
    requirements: set[str] = field(default_factory=set)
    types: dict[str, str] = field(default_factory=dict)
    constants: dict[str, str] = field(default_factory=dict)
    predicates: dict[str, int] = field(default_factory=dict)
    functions: dict[str, int] = field(default_factory=dict)
    uses_total_cost: bool = False
    edits: list[tuple[int, int, str]] = field(default_factory=list)
    """Text edits (start, end, replacement) that turn valid PDDL the ``pddl`` library's grammar
    cannot read (an empty section, an action without ``:parameters``) into PDDL it reads."""
    variables: dict[str, dict[str, str]] = field(default_factory=dict)
    """Per action, the variables renamed by the edits because the library takes their names for
    keywords (``?object``): the new name to the file's own, to name them as the file does."""


@functools.cache
def reserved_words() -> frozenset[str]:
    """Words the ``pddl`` library refuses as names ('object', 'domain', 'either', ...), though
    PDDL allows most of them as variable names."""
    from pddl.parser.symbols import ALL_SYMBOLS

    return frozenset(w for w in ALL_SYMBOLS if w[0].isalpha())


def _tokens(node: Node) -> Iterator[Tok]:
    if isinstance(node, Tok):
        yield node
    else:
        for item in node.items:
            yield from _tokens(item)


class Checker:
    """The structural walk of a domain; raises :class:`PDDLError` at the first problem."""

    def __init__(self, path: str):
        self.path = path

    def fail(self, message: str, node: Node | None) -> PDDLError:
        where = f"line {node.line}" if node is not None else None
        return PDDLError(message, path=self.path, where=where)

    def refuse(self, construct: str, node: Node) -> PDDLError:
        return self.fail(f"{construct} is not supported by mega-sat", node)

    # -- shared helpers ------------------------------------------------------------------------

    def header(self, root: SList, kind: str) -> tuple[SList, str]:
        """Check ``(define (kind NAME) ...)``; return the name node and the name."""
        if root.head != "define":
            raise self.fail("expected '(define ...)'", root)
        if len(root.items) < 2 or not isinstance(root.items[1], SList):
            raise self.fail(f"expected '({kind} NAME)' after 'define'", root)
        node = root.items[1]
        other = "problem" if kind == "domain" else "domain"
        if node.head == other:
            raise self.fail(f"this is a {other} file, expected a {kind} file", node)
        if node.head != kind or len(node.items) != 2 or not isinstance(node.items[1], Tok):
            raise self.fail(f"expected '({kind} NAME)' after 'define'", node)
        self.name_not_reserved(node.items[1], f"the {kind}")
        return node, node.items[1].text

    def sections(self, root: SList) -> Iterator[tuple[str, SList]]:
        for node in root.items[2:]:
            if not isinstance(node, SList) or not (node.head or "").startswith(":"):
                raise self.fail(f"expected a section '(:keyword ...)', got {show(node)}", node)
            yield node.head or "", node

    def requirements(self, node: SList) -> set[str]:
        out = set()
        for tok in node.items[1:]:
            if not isinstance(tok, Tok):
                raise self.fail("malformed :requirements", tok)
            if tok.text in REFUSED_REQS:
                raise self.refuse(f"requirement {tok.text} ({REFUSED_REQS[tok.text]})", tok)
            if tok.text not in ACCEPTED_REQS:
                raise self.fail(f"unknown requirement '{tok.text}'", tok)
            out.add(tok.text)
        return out

    def typed_list(
        self, items: tuple[Node, ...], what: str, *, either_ok: bool = False
    ) -> list[tuple[Tok, str]]:
        """``a b - t c`` as ``[(a, t), (b, t), (c, object)]``."""
        out: list[tuple[Tok, str]] = []
        pending: list[Tok] = []
        i = 0
        while i < len(items):
            it = items[i]
            if isinstance(it, Tok) and it.text == "-":
                if not pending:
                    raise self.fail(f"'-' without a name before it in {what}", it)
                if i + 1 >= len(items):
                    raise self.fail(f"missing type after '-' in {what}", it)
                t = items[i + 1]
                if isinstance(t, SList):
                    if t.head != "either":
                        raise self.fail(f"malformed type {show(t)} in {what}", t)
                    if not either_ok:
                        raise self.refuse("'either' type", t)
                    typ = "object"
                else:
                    typ = t.text
                out.extend((p, typ) for p in pending)
                pending = []
                i += 2
                continue
            if isinstance(it, SList):
                raise self.fail(f"unexpected {show(it)} in {what}", it)
            pending.append(it)
            i += 1
        out.extend((p, "object") for p in pending)
        return out

    def rename_keyword_variables(
        self, node: SList, variables: list[str], info: DomainInfo, action: str | None = None
    ) -> None:
        """Schedule renaming each variable of ``variables`` named like a keyword of the
        library (``?object``) everywhere in ``node``, its scope; for an ``action``, record the
        new name so that the model names it as the file does."""
        reserved = reserved_words()
        used = {t.text for t in _tokens(node) if t.text.startswith("?")}
        for var in variables:
            if var[1:] not in reserved:
                continue
            fresh = unused_name(var, used)
            if action is not None:
                info.variables.setdefault(action, {})[fresh] = var
            info.edits += [
                (t.end - len(t.text), t.end, fresh) for t in _tokens(node) if t.text == var
            ]

    def name_not_reserved(self, tok: Node, what: str) -> None:
        """Refuse a name the ``pddl`` library reserves ('either', 'domain', ...) for ``what`` (an
        object, a predicate, ...): unlike a variable it would appear renamed in plans."""
        if isinstance(tok, Tok) and tok.text in reserved_words():
            raise self.refuse(f"the keyword '{tok.text}' as the name of {what}", tok)

    def check_type(self, typ: str, types: dict[str, str], node: Node, what: str) -> None:
        if typ != "object" and typ not in types:
            raise self.fail(f"undefined type '{typ}' in {what}", node)

    def atom(
        self,
        node: SList,
        info: DomainInfo,
        variables: set[str] | None,
        names: set[str] | dict[str, str],
        what: str,
    ) -> None:
        """Check predicate, arity and arguments of an atom; ``variables`` None: no variables."""
        pred = node.head
        if pred is None:
            raise self.fail(f"expected an atom in {what}, got {show(node)}", node)
        if pred not in info.predicates:
            if pred == "preference":
                raise self.refuse("preferences 'preference' (PDDL3)", node)
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
        args: tuple[Node, ...],
        variables: set[str] | None,
        names: set[str] | dict[str, str],
        what: str,
    ) -> None:
        for a in args:
            if isinstance(a, SList):
                raise self.fail(f"unexpected {show(a)} as an argument in {what}", a)
            if a.text.startswith("?"):
                if variables is None:
                    raise self.fail(f"variable '{a.text}' in {what}", a)
                if a.text not in variables:
                    raise self.fail(f"undefined variable '{a.text}' in {what}", a)
            elif a.text not in names:
                kind = "constant" if variables is not None else "object"
                raise self.fail(f"undefined {kind} '{a.text}' in {what}", a)

    def equality_or_comparison(self, node: SList, where: str = "") -> PDDLError:
        """``(= a b)`` where it is not read: equality of terms, or a numeric comparison when a
        side is a term."""
        if self.is_numeric(node):
            return self.refuse("numeric comparison '='", node)
        return self.refuse(f"equality '(= ...)'{where}", node)

    @staticmethod
    def is_numeric(node: SList) -> bool:
        return any(isinstance(x, SList) or NUMBER_RE.fullmatch(x.text) for x in node.items[1:])

    def equality(self, node: SList, info: DomainInfo, variables: set[str], what: str) -> None:
        """``(= t1 t2)`` of two terms in a precondition: read as the static predicate ``=``
        (:data:`mega_sat.model.lifted.EQUALITY`)."""
        if self.is_numeric(node):
            raise self.refuse("numeric comparison '='", node)
        if len(node.items) != 3:
            raise self.fail(f"'=' takes 2 arguments, got {len(node.items) - 1} in {what}", node)
        self.terms(node.items[1:], variables, info.constants, what)

    # -- domain --------------------------------------------------------------------------------

    def domain(self, root: SList) -> DomainInfo:
        info = DomainInfo()
        _, info.name = self.header(root, "domain")
        actions: list[SList] = []
        flag_sections: list[SList] = []
        once: set[str] = set()
        sections = list(self.sections(root))
        # the types first, wherever they stand (Fast Downward reads them anywhere): constants,
        # predicates and functions are checked against them
        sections.sort(key=lambda section: section[0] != ":types")
        first_header: SList | None = None
        for key, node in sections:
            if key in (":types", ":constants", ":predicates", ":functions"):
                if key in once:
                    raise self.fail(f"a second '{key}' section", node)
                once.add(key)
                if key != ":types" and (first_header is None or node.start < first_header.start):
                    first_header = node
        for key, node in sections:
            if len(node.items) == 1 and key in (
                ":types",
                ":constants",
                ":predicates",
                ":functions",
            ):
                # valid, but the library's grammar wants at least one entry: leave it out
                info.edits.append((node.start, node.end, ""))
            elif key == ":requirements":
                info.requirements |= self.requirements(node)
                flag_sections.append(node)
            elif key == ":types":
                # the library's grammar wants them before the other header sections: moved there
                ahead = first_header is not None and first_header.start < node.start
                self.types(node, info, move_to=first_header.start if ahead else None)
            elif key == ":constants":
                for tok, typ in self.typed_list(node.items[1:], ":constants"):
                    self.name_not_reserved(tok, "a constant")
                    info.constants[tok.text] = typ
                    self.check_type(typ, info.types, tok, ":constants")
            elif key == ":predicates":
                self.predicates(node, info)
            elif key == ":functions":
                self.functions(node, info)
            elif key == ":action":
                actions.append(node)
            elif key in REFUSED_SECTIONS:
                raise self.refuse(REFUSED_SECTIONS[key], node)
            else:
                raise self.fail(f"unknown domain section '{key}'", node)
        if len(flag_sections) == 1 and len(flag_sections[0].items) == 1:
            # the flags come from the reading (PERMISSIVE_FLAGS in mega_sat.pddl.library), and
            # the grammar wants at least one; a second section stays for the library to refuse
            info.edits.append((flag_sections[0].start, flag_sections[0].end, ""))
        seen: set[str] = set()
        for node in actions:
            name = self.action(node, info)
            if name in seen:
                raise self.fail(f"action '{name}' is defined twice", node)
            seen.add(name)
        return info

    def types(self, node: SList, info: DomainInfo, *, move_to: int | None = None) -> None:
        """Check ``:types``; ``move_to``: the text position the section moves to (on one line,
        so that line numbers stay)."""
        declared: set[str] = set()
        rewrite = False  # 'object' or a type declared again: valid, the library refuses both
        for tok, parent in self.typed_list(node.items[1:], ":types"):
            t = tok.text
            if t != "object":
                self.name_not_reserved(tok, "a type")
            rewrite |= t == "object" or t in declared
            declared.add(t)
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
        if rewrite or move_to is not None:  # the same hierarchy, each type once, untyped last
            own = [f"{t} - {p}" for t, p in info.types.items() if p != "object"]
            own += [t for t, p in info.types.items() if p == "object"]
            text = f"(:types {' '.join(own)})" if own else ""
            if move_to is None:
                info.edits.append((node.start, node.end, text))
            else:
                info.edits += [(node.start, node.end, ""), (move_to, move_to, text + " ")]

    def predicates(self, node: SList, info: DomainInfo) -> None:
        declared = node.items[1:]
        for p in declared:
            if isinstance(p, SList) and p.head == "=" and len(p.items) > 1:
                # equality declared as a predicate (as some domains for Fast Downward do):
                # built in, so the declaration is left out
                whole = all(isinstance(q, SList) and q.head == "=" for q in declared)
                info.edits.append((node.start, node.end, "") if whole else (p.start, p.end, ""))
                if whole:
                    return
                continue
            if not isinstance(p, SList) or p.head is None:
                raise self.fail(f"malformed predicate declaration {show(p)}", p)
            self.name_not_reserved(p.items[0], "a predicate")
            args = self.typed_list(p.items[1:], f"predicate '{p.head}'", either_ok=True)
            for tok, typ in args:
                self.check_type(typ, info.types, tok, f"predicate '{p.head}'")
            self.rename_keyword_variables(p, [t.text for t, _ in args], info)
            if p.head in info.types:
                raise self.fail(
                    f"'{p.head}' is both a type and a predicate (types become predicates)", p
                )
            if p.head in info.predicates and info.predicates[p.head] != len(args):
                raise self.fail(f"predicate '{p.head}' is declared twice", p)
            info.predicates[p.head] = len(args)

    def functions(self, node: SList, info: DomainInfo) -> None:
        items = node.items[1:]
        i = 0
        while i < len(items):
            f = items[i]
            if isinstance(f, Tok) and f.text == "-":
                t = items[i + 1] if i + 1 < len(items) else None
                if not isinstance(t, Tok) or t.text != "number":
                    raise self.refuse("non-numeric function (object fluents)", t or f)
                i += 2
                continue
            if not isinstance(f, SList) or f.head is None:
                raise self.fail(f"malformed function declaration {show(f)}", f)
            if f.head != "total-cost":
                self.name_not_reserved(f.items[0], "a function")
            args = self.typed_list(f.items[1:], f"function '{f.head}'", either_ok=True)
            self.rename_keyword_variables(f, [t.text for t, _ in args], info)
            if f.head == "total-cost":
                if args:
                    raise self.fail("'total-cost' takes no arguments", f)
                info.uses_total_cost = True
            else:
                info.functions[f.head] = len(args)
            i += 1

    def action(self, node: SList, info: DomainInfo) -> str:
        items = node.items
        if len(items) < 2 or not isinstance(items[1], Tok) or items[1].text.startswith(":"):
            raise self.fail("expected an action name after ':action'", node)
        name = items[1].text
        self.name_not_reserved(items[1], "an action")
        what = f"action '{name}'"
        parts: dict[str, Node] = {}
        i = 2
        while i < len(items):
            key = items[i]
            if not isinstance(key, Tok) or key.text not in (
                ":parameters",
                ":precondition",
                ":effect",
            ):
                raise self.fail(f"unexpected {show(key)} in {what}", key)
            if i + 1 >= len(items):
                raise self.fail(f"missing value after '{key.text}' in {what}", key)
            parts[key.text] = items[i + 1]
            i += 2
        self.complete_action(node, parts, info)
        variables: set[str] = set()
        params = parts.get(":parameters")
        if params is not None:
            if not isinstance(params, SList):
                raise self.fail(f"expected a parameter list in {what}", params)
            for tok, typ in self.typed_list(params.items, f"the parameters of {what}"):
                if not tok.text.startswith("?"):
                    raise self.fail(f"parameter '{tok.text}' of {what} must start with '?'", tok)
                if tok.text in variables:
                    raise self.fail(f"duplicate parameter '{tok.text}' in {what}", tok)
                self.check_type(typ, info.types, tok, f"the parameters of {what}")
                variables.add(tok.text)
        if params is not None:
            self.rename_keyword_variables(
                node,
                [t.text for t in params.items if isinstance(t, Tok) and t.text.startswith("?")],
                info,
                name,
            )
        pre = parts.get(":precondition")
        if pre is not None:
            self.condition(pre, info, variables, f"the precondition of {what}")
        eff = parts.get(":effect")
        if eff is not None and self.effect(eff, info, variables, f"the effect of {what}") > 1:
            raise self.fail(f"more than one (increase (total-cost) ...) in {what}", eff)
        return name

    def complete_action(self, node: SList, parts: dict[str, Node], info: DomainInfo) -> None:
        """Schedule inserting omitted parts: the library's grammar needs ``:parameters``, and the
        parts in this order."""
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
        self, node: Node, info: DomainInfo, variables: set[str], what: str, *, goal=False
    ) -> None:
        if not isinstance(node, SList):
            raise self.fail(f"expected a condition in {what}, got {show(node)}", node)
        head = node.head
        if head == "and" or not node.items:
            for sub in node.items[1:]:
                self.condition(sub, info, variables, what, goal=goal)
        elif head == "not":
            if len(node.items) != 2 or not isinstance(node.items[1], SList):
                raise self.fail(f"malformed 'not' in {what}", node)
            sub = node.items[1]
            if sub.head == "=":
                if goal:
                    raise self.equality_or_comparison(sub, " in the goal")
                self.equality(sub, info, variables, what)
                return
            if sub.head in KEYWORDS or sub.head is None:
                raise self.refuse(f"negation of a compound condition '(not ({sub.head} ...))'", sub)
            self.atom(sub, info, variables, info.constants, what)
        elif head == "=":
            if goal:
                raise self.equality_or_comparison(node, " in the goal")
            self.equality(node, info, variables, what)
        elif head in CONDITION_REFUSALS:
            construct = CONDITION_REFUSALS[head]
            if goal and head in ("or", "imply", "forall", "exists"):
                construct = f"non-conjunctive goal ({construct})"
            raise self.refuse(construct, node)
        else:
            self.atom(node, info, variables, info.constants, what)

    def effect(
        self, node: Node, info: DomainInfo, variables: set[str], what: str, *, nested=False
    ) -> int:
        """Check an effect; return how many total-cost increases it has."""
        if not isinstance(node, SList):
            raise self.fail(f"expected an effect in {what}, got {show(node)}", node)
        head = node.head
        if head == "and" or not node.items:
            if nested:  # valid PDDL the library's grammar lacks: its parts join the outer 'and'
                opening = node.items[0].end if node.items else node.start + 1
                info.edits += [(node.start, opening, ""), (node.end - 1, node.end, "")]
            return sum(
                self.effect(sub, info, variables, what, nested=True) for sub in node.items[1:]
            )
        if head == "not":
            if len(node.items) != 2 or not isinstance(node.items[1], SList):
                raise self.fail(f"malformed 'not' in {what}", node)
            sub = node.items[1]
            if sub.head == "=":
                raise self.equality_or_comparison(sub, " in an effect")
            if sub.head in KEYWORDS or sub.head is None:
                raise self.fail(f"expected an atom inside 'not' in {what}", sub)
            self.atom(sub, info, variables, info.constants, what)
            return 0
        if head == "increase":
            self.increase(node, info, variables, what)
            return 1
        if head in EFFECT_REFUSALS:
            raise self.refuse(EFFECT_REFUSALS[head], node)
        if head == "=":
            raise self.equality_or_comparison(node, " in an effect")
        self.atom(node, info, variables, info.constants, what)
        return 0

    def increase(self, node: SList, info: DomainInfo, variables: set[str], what: str) -> None:
        if len(node.items) != 3:
            raise self.fail(f"malformed 'increase' in {what}", node)
        target, value = node.items[1], node.items[2]
        if not (isinstance(target, SList) and target.head == "total-cost"):
            raise self.refuse(
                f"numeric effect 'increase' of {show(target)} (numeric fluents)", node
            )
        if not info.uses_total_cost:
            raise self.fail("(total-cost) is used but not declared in :functions", node)
        # a cost effect without the flag (IPC 2011's floortile): read with its costs, as Fast
        # Downward reads it
        info.requirements.add(":action-costs")
        if isinstance(value, Tok):
            if not INT_RE.fullmatch(value.text) or value.text.startswith("-"):
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
