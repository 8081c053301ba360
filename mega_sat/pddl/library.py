"""The ``pddl`` library's side of reading PDDL: its grammar, its transformers, its errors.

A lark parser for domains and one for problems are built from the library's grammar and kept
for the process, and on disk for the next one (:mod:`mega_sat.pddl.parser_cache`), since
building one takes about a twentieth of a second.  Each parses a text into a
tree, and a new instance of the library's transformer turns each tree into a ``pddl`` Domain or
Problem.  The library's own ``DomainParser`` runs one long-lived transformer inside the parser,
and a failed parse leaves that transformer's per-file state behind; a tree per file avoids that
and also gives the tokens with their positions, from which
:func:`mega_sat.pddl.sexpr.from_tokens` builds the s-expressions the check walks, so a valid file
is parsed once.
"""

from __future__ import annotations

import functools
from collections.abc import Iterator

from mega_sat.errors import PDDLError

PERMISSIVE_FLAGS = (
    ":strips",
    ":typing",
    ":negative-preconditions",
    ":action-costs",
    ":numeric-fluents",
    ":equality",
)
"""The flags every domain is read with.  The library refuses a domain that uses types or
functions without declaring their flags; mega-sat tolerates missing flags as Fast Downward does,
and :mod:`mega_sat.pddl.check` vets the flags a file declares."""


@functools.cache
def _parser(kind: str):
    """The parser of ``kind``, built as the library builds its own but without a transformer.

    One parser per start symbol, as in the library: lark keeps only the terminals a start
    symbol reaches, and those decide how a syntax error is worded.
    """
    from lark import Lark
    from pddl.parser import GRAMMAR_FILE, PARSERS_DIRECTORY

    from mega_sat.pddl.parser_cache import cached_parser

    grammar = _lenient(GRAMMAR_FILE.read_text())
    return cached_parser(
        grammar,
        kind,
        lambda: Lark(grammar, parser="lalr", import_paths=[PARSERS_DIRECTORY], start=kind),
    )


_HEADER_ORDER = "[constants] [predicates] [functions] structure_def*"


def _lenient(grammar: str) -> str:
    """The library's grammar with a domain's ``:constants``, ``:predicates`` and ``:functions``
    in any order after ``:types``, as Fast Downward reads them (the BNF fixes their order, and
    domains written by hand often differ).  The transformer does not depend on their order,
    only on the types coming first.  A grammar without the expected rule stays as it is."""
    if _HEADER_ORDER not in grammar:
        return grammar
    rule = "\n_domain_header: constants | predicates | functions\n"
    return grammar.replace(_HEADER_ORDER, "_domain_header* structure_def*") + rule


@functools.cache
def _transformers():
    from pddl.parser.domain import DomainTransformer
    from pddl.parser.problem import ProblemTransformer

    class Domain(DomainTransformer):
        """The library's domain transformer, reading the domain with :data:`PERMISSIVE_FLAGS`
        and ``- object`` as no type (see :func:`_any_type`)."""

        def typed_list_name(self, args):
            return _any_type(super().typed_list_name(args))

        def typed_list_variable(self, args):
            return _any_type(super().typed_list_variable(args))

        def f_typed_list_atomic_function_skeleton(self, args):
            return _any_type(super().f_typed_list_atomic_function_skeleton(args))

        def domain_def(self, args):
            # the name comes first in every domain, so the flags are in place for what follows
            flags = super().requirements(["(", ":requirements", *PERMISSIVE_FLAGS, ")"])
            return {**super().domain_def(args), **flags}

        def requirements(self, args):
            return None  # the domain's own flags: checked by mega-sat, replaced by the above

    class Problem(ProblemTransformer):
        """The library's problem transformer; the domain's flags are the ones that count, and
        ``- object`` is no type."""

        def typed_list_name(self, args):
            return _any_type(super().typed_list_name(args))

        def requirements(self, args):
            return None

    return {"domain": Domain, "problem": Problem}


def _any_type(typed):
    """A typed list of the library with ``object`` read as no type at all.

    ``object`` is PDDL's root type, declared or not, but the library refuses it as the type of
    a parameter, predicate argument, function argument, constant or object ("not in available
    types").  An untyped entry means the same: any object.  ``typed`` is a name-to-type dict or a tuple of
    (variable, type set) pairs; a type set holding ``object`` (``(either object t)``) is any
    object too."""
    if isinstance(typed, dict):
        return {k: None if v == "object" else v for k, v in typed.items()}
    return tuple((v, set() if "object" in types else types) for v, types in typed)


def parse_tree(text: str, kind: str):
    """The library's parse tree of a normalised ``kind`` ('domain' or 'problem') text; raises
    the library's exception for a text its grammar does not accept."""
    return _parser(kind).parse(text)


def tokens(tree) -> Iterator:
    """The tokens of a parse tree in text order."""
    from lark import Tree

    stack = [iter(tree.children)]
    while stack:
        for child in stack[-1]:
            if isinstance(child, Tree):
                stack.append(iter(child.children))
                break
            if child is not None:  # an absent optional section
                yield child
        else:
            stack.pop()


def transform(tree, kind: str):
    """The ``pddl`` Domain or Problem of a parse tree; raises the library's exception."""
    return _transformers()[kind]().transform(tree)


def parse(text: str, kind: str, path: str):
    """Parse and transform; every exception becomes a one-line :class:`PDDLError`."""
    try:
        tree = parse_tree(text, kind)
    except Exception as e:  # anything the library raises is a problem of the file
        raise wrap_error(_transform_error_before(e, kind) or e, path) from None
    try:
        return transform(tree, kind)
    except Exception as e:
        raise wrap_error(e, path) from None


def _transform_error_before(e: Exception, kind: str) -> Exception | None:
    """The transformer's error on the text before a syntax error ``e``, if any.

    The library's own parser transforms each rule as soon as it is complete, so such an error is
    the one the library reports for the file; lark keeps the rules completed so far on the value
    stack of the parser state it attaches to its error.
    """
    from lark import Tree

    state = getattr(getattr(e, "interactive_parser", None), "parser_state", None)
    transformer = _transformers()[kind]()
    try:
        for item in getattr(state, "value_stack", None) or ():
            if isinstance(item, Tree):
                transformer.transform(item)
    except Exception as inner:  # the library's error, as parse() words it
        return inner
    return None


def wrap_error(e: Exception, path: str) -> PDDLError:
    """The one-line :class:`PDDLError` of an exception of the library or of lark."""
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


def repair(text: str, edits: list[tuple[int, int, str]]) -> str:
    """``text`` with the edits (start, end, replacement) of the check applied, each keeping the
    line count so that the library's line numbers stay right."""
    for start, end, replacement in sorted(edits, reverse=True):
        text = text[:start] + replacement + "\n" * text.count("\n", start, end) + text[end:]
    return text
