"""Built PDDL parsers kept on disk between processes.

Building the two lark parsers (domain, problem) from the ``pddl`` library's grammar costs
about 90 ms, a quarter of a small task's whole run; loading a saved one costs about 5 ms.  A
saved parser is found by a key over everything that shapes it (the grammar text, the start
symbol, the lark, ``pddl`` and Python versions), so a changed grammar or library never loads
a stale one.

The directory is ``$MEGA_SAT_CACHE_DIR`` if set (empty: no cache), else
``$XDG_CACHE_HOME/mega-sat`` or ``~/.cache/mega-sat``.  Saved parsers are pickles, so the
cache is used only in a directory this user owns that no one else can write to.  A file is
written under a temporary name and renamed into place, so a process never reads another's
half-written file.  Any failure (read-only home, a damaged file) falls back to building the
parser: the cache only saves time, it never changes a parse.
"""

from __future__ import annotations

import hashlib
import os
import stat
import sys
import tempfile
from pathlib import Path

CACHE_ENV = "MEGA_SAT_CACHE_DIR"


def cache_dir() -> Path | None:
    """Where built parsers are kept, or ``None`` when the cache is off."""
    given = os.environ.get(CACHE_ENV)
    if given is not None:
        return Path(given).expanduser() if given.strip() else None
    base = os.environ.get("XDG_CACHE_HOME") or os.path.join(os.path.expanduser("~"), ".cache")
    return Path(base) / "mega-sat"


def parser_key(grammar: str, start: str) -> str:
    """The file-name key of a parser: a digest over what decides the built parser."""
    import lark
    import pddl

    python = ".".join(map(str, sys.version_info[:2]))
    parts = (grammar, start, lark.__version__, getattr(pddl, "__version__", ""), python)
    return hashlib.sha256("\0".join(parts).encode()).hexdigest()[:24]


def _private(d: Path) -> bool:
    """``d`` is a directory of this user that no other user can write to."""
    try:
        st = d.stat()
    except OSError:
        return False
    owner_ok = not hasattr(os, "getuid") or st.st_uid == os.getuid()
    return stat.S_ISDIR(st.st_mode) and owner_ok and not st.st_mode & (stat.S_IWGRP | stat.S_IWOTH)


def cached_parser(grammar: str, start: str, build):
    """The parser ``build()`` makes for ``grammar`` and ``start``, loaded from the cache when
    a saved one is there, else built and saved for the next process."""
    from lark import Lark

    d = cache_dir()
    if d is None:
        return build()
    path = d / f"pddl-{start}-{parser_key(grammar, start)}.lark"
    if _private(d):
        try:
            with open(path, "rb") as f:
                return Lark.load(f)
        except Exception:  # missing or damaged: build it again below
            pass
    parser = build()
    try:
        d.mkdir(mode=0o700, parents=True, exist_ok=True)
        if not _private(d):
            return parser
        fd, tmp = tempfile.mkstemp(dir=d, prefix=path.name, suffix=".tmp")
        try:
            with os.fdopen(fd, "wb") as f:
                parser.save(f)
            os.replace(tmp, path)
        except BaseException:
            os.unlink(tmp)
            raise
    except Exception:  # an unwritable cache only costs the next process the build
        pass
    return parser
