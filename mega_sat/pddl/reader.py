"""Read PDDL domain + problem files into a normalised :class:`~mega_sat.model.lifted.Model`.

Every refusal is a one-line :class:`PDDLError` naming the file, the line and the construct,
never a raw library traceback.  The steps, each in its own module:

1. :func:`~mega_sat.pddl.sexpr.normalise_text` lower-cases the text (PDDL is case-insensitive)
   and blanks out ``;`` comments, keeping every offset and line.
2. The ``pddl`` library parses each file once into a tree (:mod:`mega_sat.pddl.library`).
3. :mod:`mega_sat.pddl.check` and :mod:`mega_sat.pddl.check_problem` walk the s-expressions of
   the files and refuse what mega-sat does not support, with file, line and construct.  They are
   built from the library's tokens; only a file the library's grammar rejects is read from its
   text (:mod:`mega_sat.pddl.sexpr`), so that its error is worded and located like any other.
4. The library's transformer turns the trees into ``pddl`` objects, and
   :mod:`mega_sat.pddl.normalise` turns those into a :class:`Model`.

Some valid PDDL is outside the library's grammar (an empty section, an action without
``:parameters``).  For such a file, and to word an error only the library finds, the check's
edits repair the text and the library parses the repaired text (:func:`_parse_repaired`).
"""

from __future__ import annotations

from pathlib import Path

from mega_sat.errors import PDDLError
from mega_sat.model.lifted import Model
from mega_sat.pddl.check import Checker, DomainInfo
from mega_sat.pddl.check_problem import PDDLWarning, ProblemChecker
from mega_sat.pddl.library import parse, parse_tree, repair, tokens, transform
from mega_sat.pddl.normalise import to_model
from mega_sat.pddl.sexpr import SList, from_tokens, normalise_text, read_sexpr

__all__ = [
    "PDDLError",
    "PDDLWarning",
    "normalise_text",
    "parse_model",
    "read_model",
    "read_text",
]


def _try_parse(text: str, kind: str):
    """The library's parse tree, or None when its grammar rejects the text."""
    try:
        return parse_tree(text, kind)
    except Exception:  # the check or the repaired parse words the problem
        return None


def _sexpr(text: str, tree, path: str) -> SList:
    """The s-expression the check walks: from the library's tokens when there are any."""
    root = from_tokens(text, tokens(tree)) if tree is not None else None
    return root if root is not None else read_sexpr(text, path)


def _parse_repaired(
    dtext: str, ptext: str, info: DomainInfo, drop: list[SList], domain_path: str, problem_path: str
):
    """Parse the texts with the check's edits applied; library errors become PDDLErrors."""
    domain = parse(repair(dtext, info.edits), "domain", domain_path)
    problem = parse(repair(ptext, [(n.start, n.end, "") for n in drop]), "problem", problem_path)
    return domain, problem


def parse_model(
    domain_text: str,
    problem_text: str,
    *,
    domain_path: str = "<domain>",
    problem_path: str = "<problem>",
    borrowed_problem: bool = False,
) -> Model:
    """Parse a domain and a problem into a normalised :class:`Model`.

    ``borrowed_problem``: the problem is another model's (the robot's, read as the human's);
    cost-function values and a metric this domain does not declare are left out.

    Raises :class:`PDDLError` (file, line, construct) for malformed or unsupported PDDL.
    """
    dtext = normalise_text(domain_text)
    ptext = normalise_text(problem_text)
    dtree, ptree = _try_parse(dtext, "domain"), _try_parse(ptext, "problem")
    info = Checker(domain_path).domain(_sexpr(dtext, dtree, domain_path))
    checker = ProblemChecker(problem_path, borrowed=borrowed_problem)
    drop = checker.problem(_sexpr(ptext, ptree, problem_path), info)
    parsed = None
    # what a borrowed problem leaves out must not reach the library's reading
    if dtree is not None and ptree is not None and not checker.left_out:
        try:
            parsed = transform(dtree, "domain"), transform(ptree, "problem")
        except Exception:  # the repaired parse below words it as the library states it
            parsed = None
    if parsed is None:
        parsed = _parse_repaired(dtext, ptext, info, drop, domain_path, problem_path)
    return to_model(*parsed, info, domain_path, problem_path)


def as_path(value: object, what: str) -> Path:
    """``value`` as a path, or a :class:`~mega_sat.errors.UsageError` for what is none (None,
    a number, bytes, an empty string) instead of ``pathlib``'s TypeError or a read of
    the current folder."""
    import os

    from mega_sat.errors import UsageError

    if not isinstance(value, str | os.PathLike) or str(value) == "":
        raise UsageError(f"{what}: expected a path (str or Path), got {value!r}")
    return Path(value)


def read_text(path: str | Path, what: str) -> str:
    """Read a text file; a missing or unreadable file is a :class:`PDDLError` naming it."""
    path = as_path(path, f"{what} file")
    try:
        return path.read_text(encoding="utf-8")
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
