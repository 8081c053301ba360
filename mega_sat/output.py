"""Writes that cannot half-happen: a file or a whole folder appears complete or not at all.

Every command that writes results (``apply``, ``plan --out``, ``encode --out``, ``solve`` and
``frontier --write-model``, ``frontier --plot``, ``generate``) goes through these two helpers:

* :func:`write_file` writes a temporary file beside the target and renames it into place, so a
  full disk or an interrupt leaves the old file (or none), never a truncated one.
* :class:`OutputFolder` is checked when it is created, before any solving, so an existing
  target is refused at once instead of after a long run.  Its files are written into a
  temporary sibling folder that :meth:`OutputFolder.commit` renames into place; with ``force``
  the earlier folder is replaced as a whole (none of its files stay mixed in).  Leaving the
  ``with`` block any other way (an error, Ctrl-C, a time limit) removes the temporary folder.

``mega-sat batch`` is the one writer that appends instead (:class:`mega_sat.cli.batch.ResultsFile`):
its file grows by one whole, synced line per finished task, so that a stop keeps every task
already done; a line cut short by a crash is dropped when the file is resumed.
"""

from __future__ import annotations

import os
import shutil
import tempfile
from pathlib import Path
from types import TracebackType

from mega_sat.errors import EXIT_OUTPUT, MegaSatError, UsageError


class OutputError(MegaSatError):
    """An output that cannot be written (no space left, no permission, ...)."""

    exit_code = EXIT_OUTPUT


def _io_error(action: str, path: Path, e: OSError) -> OutputError:
    return OutputError(f"cannot {action}: {e.strerror or e}", path=str(path))


def check_target(path: str | Path, *, force: bool, folder: bool = False) -> Path:
    """Refuse, before any work, a target that exists (unless ``force``) or whose parent folder
    cannot be written."""
    p = Path(path)
    if p.exists():
        # what the target is comes first: a FIFO or a device is never replaced, not even
        # with --force (that would turn /dev/... into a regular file)
        if folder and not p.is_dir():
            raise UsageError("exists and is not a folder", path=str(p))
        if not folder and p.is_dir():
            raise UsageError("is a folder, expected a file", path=str(p))
        if not folder and not p.is_file():
            raise UsageError("exists and is not a regular file", path=str(p))
        if not force and (not folder or any(p.iterdir())):
            raise UsageError(
                f"{'folder' if folder else 'file'} exists (use --force to replace it)", path=str(p)
            )
    parent = _existing_ancestor(p.parent)
    if not parent.is_dir():
        raise UsageError("is not a folder", path=str(parent))
    if not os.access(parent, os.W_OK | os.X_OK):
        raise OutputError("folder is not writable", path=str(parent))
    return p


def _existing_ancestor(p: Path) -> Path:
    p = p.absolute()
    while not p.exists() and p != p.parent:
        p = p.parent
    return p


def write_file(path: str | Path, text: str | bytes, *, force: bool = False) -> Path:
    """Write ``text`` (or binary data, e.g. a figure) to ``path`` atomically (temporary file,
    then rename)."""
    p = check_target(path, force=force)
    try:
        p.parent.mkdir(parents=True, exist_ok=True)
    except OSError as e:
        raise _io_error("create folder", p.parent, e) from None
    try:
        fd, tmp = tempfile.mkstemp(dir=p.parent, prefix=f".{p.name}.", suffix=".tmp")
    except OSError as e:  # a folder no file can be made in (/proc, immutable, read-only fs)
        raise _io_error("write file", p, e) from None
    try:
        os.chmod(tmp, 0o666 & ~_umask())  # as open() would create it (mkstemp makes 0600)
        if isinstance(text, bytes):
            with os.fdopen(fd, "wb") as fb:
                fb.write(text)
        else:
            with os.fdopen(fd, "w", encoding="utf-8") as f:
                f.write(text)
        os.replace(tmp, p)
    except OSError as e:
        _remove(Path(tmp))
        raise _io_error("write file", p, e) from None
    except BaseException:
        _remove(Path(tmp))
        raise
    return p


def _umask() -> int:
    """The process's file-creation mask (read by setting it and putting it back)."""
    mask = os.umask(0o022)
    os.umask(mask)
    return mask


def _remove(p: Path) -> None:
    try:
        if p.is_dir() and not p.is_symlink():
            shutil.rmtree(p)
        else:
            p.unlink()
    except FileNotFoundError:
        pass
    except OSError:
        pass  # best effort on the way out; the caller reports the real error


class OutputFolder:
    """A folder of results that appears complete or not at all (see the module docstring).

    Usage::

        out = OutputFolder(target, force=force)    # checked now, before solving
        ...                                        # long work
        with out:
            write_file(out.path / "a.pddl", text)  # into the temporary folder
            out.commit()                           # rename into place
    """

    def __init__(self, target: str | Path, *, force: bool = False):
        self.target = check_target(target, force=force, folder=True)
        self.force = force
        self._tmp: Path | None = None

    @property
    def path(self) -> Path:
        """Where to write now: the temporary folder inside the ``with`` block."""
        if self._tmp is None:
            raise RuntimeError("OutputFolder.path is only available inside 'with'")
        return self._tmp

    def __enter__(self) -> OutputFolder:
        parent = self.target.parent
        try:
            parent.mkdir(parents=True, exist_ok=True)
            self._tmp = Path(tempfile.mkdtemp(dir=parent, prefix=f".{self.target.name}.tmp-"))
            os.chmod(self._tmp, 0o777 & ~_umask())  # as mkdir would (mkdtemp makes 0700)
        except OSError as e:
            raise _io_error("create folder", parent, e) from None
        return self

    def commit(self) -> Path:
        """Put the written folder in place of the target (replacing it as a whole)."""
        tmp = self.path
        old: Path | None = None
        try:
            if self.target.exists():
                check_target(self.target, force=self.force, folder=True)  # appeared meanwhile?
                old = Path(
                    tempfile.mkdtemp(dir=self.target.parent, prefix=f".{self.target.name}.old-")
                )
                os.rmdir(old)
                os.replace(self.target, old)
            os.replace(tmp, self.target)
        except OSError as e:
            if old is not None and not self.target.exists():
                os.replace(old, self.target)  # put the earlier output back
                old = None
            raise _io_error("write folder", self.target, e) from None
        self._tmp = None
        if old is not None:
            _remove(old)
        return self.target

    def __exit__(
        self,
        exc_type: type[BaseException] | None,
        exc: BaseException | None,
        tb: TracebackType | None,
    ) -> None:
        if self._tmp is not None:
            _remove(self._tmp)
            self._tmp = None
