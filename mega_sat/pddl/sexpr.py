"""PDDL files as s-expressions whose nodes remember their line, for :mod:`mega_sat.pddl.check`.

A file the ``pddl`` library parses is turned into s-expressions from the library's own tokens
(:func:`from_tokens`), so a valid file is read once.  Only a file the library rejects is read
from its text (:func:`read_sexpr`), which also says where a parenthesis went missing.
"""

from __future__ import annotations

import re
from collections.abc import Iterable
from dataclasses import dataclass

from mega_sat.errors import PDDLError


@dataclass(frozen=True)
class Tok:
    text: str
    line: int
    end: int


@dataclass(frozen=True)
class SList:
    items: tuple[Tok | SList, ...]
    line: int
    start: int
    end: int

    @property
    def head(self) -> str | None:
        if self.items and isinstance(self.items[0], Tok):
            return self.items[0].text
        return None


Node = Tok | SList
_TOKEN_RE = re.compile(r"\(|\)|[^\s()]+")
_COMMENT_RE = re.compile(r";[^\n]*")
_BLANK_RE = re.compile(r"\s*")


def normalise_text(text: str) -> str:
    """Lower-case ``text`` and blank out ``;`` comments and a leading byte-order mark, keeping
    every offset and line."""
    if text.startswith("\ufeff"):
        text = " " + text[1:]
    return _COMMENT_RE.sub(lambda m: " " * len(m.group()), text.lower())


def show(node: Node | None) -> str:
    """A node as messages quote it."""
    if node is None:
        return "nothing"
    if isinstance(node, Tok):
        return f"'{node.text}'"
    return f"'({node.head or ''} ...)'" if node.items else "'()'"


def from_tokens(text: str, tokens: Iterable) -> SList | None:
    """The s-expression of a file the library parsed, built from its tokens in text order.

    The library's grammar drops the ``?`` of a variable, so a ``?`` right before a name is put
    back.  None when the tokens do not match the whitespace-separated reading of
    :func:`read_sexpr` (text between tokens, two tokens touching): then the caller reads the text
    itself, so that both readings always check the same s-expressions.
    """
    stack: list[tuple[int, int, list[Node]]] = [(0, 0, [])]
    prev_end, prev_paren = 0, True
    for tok in tokens:
        start, value = tok.start_pos, str(tok)
        is_paren = value in ("(", ")")
        gap_end = start
        if tok.type == "NAME" and start > 0 and text[start - 1] == "?":
            gap_end, value = start - 1, "?" + value
        if not _BLANK_RE.fullmatch(text, prev_end, gap_end):
            return None
        if gap_end == prev_end and not (prev_paren or is_paren):
            return None
        if value == "(":
            stack.append((tok.line, start, []))
        elif value == ")":
            line, open_at, items = stack.pop()
            stack[-1][2].append(SList(tuple(items), line, open_at, tok.end_pos))
        else:
            stack[-1][2].append(Tok(value, tok.line, tok.end_pos))
        prev_end, prev_paren = tok.end_pos, is_paren
    top = stack[0][2]
    if len(stack) != 1 or len(top) != 1 or not isinstance(top[0], SList):
        return None
    return top[0]


def _indent(text: str, pos: int) -> int:
    """Column of the first non-blank character of the line holding ``pos``."""
    start = text.rfind("\n", 0, pos) + 1
    line = text[start:pos]
    return len(line) - len(line.lstrip())


def read_sexpr(text: str, path: str) -> SList:
    """The single top-level list of a normalised PDDL file."""
    stack: list[tuple[int, int, list[Node]]] = []
    top: list[Node] = []
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
            node = SList(tuple(items), l0, s0, m.end())
            (stack[-1][2] if stack else top).append(node)
        else:
            if suspect is None and tok.startswith(":") and stack and stack[-1][2]:
                head = stack[-1][2][0]  # a list never starts with a list in PDDL
                if isinstance(head, SList) or (
                    not head.text.startswith(":") and head.text != "define"
                ):
                    suspect = (stack[-1][0], f"'{tok}'", line)
            (stack[-1][2] if stack else top).append(Tok(tok, line, m.end()))
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
    if not isinstance(top[0], SList):
        raise PDDLError("expected '(define ...)'", path=path, where=f"line {top[0].line}")
    return top[0]
