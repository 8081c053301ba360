"""Writes that cannot half-happen (mega_sat/output.py)."""

from __future__ import annotations

import errno
import os
from pathlib import Path

import pytest

from mega_sat.errors import UsageError
from mega_sat.output import OutputError, OutputFolder, check_target, write_file
from mega_sat.pddl.writer import write_text


def _leftovers(folder):
    return sorted(p.name for p in folder.iterdir() if p.name.startswith("."))


def test_write_file_refuses_an_existing_file_unless_forced(tmp_path):
    target = tmp_path / "plan.ipc"
    write_file(target, "old\n")
    with pytest.raises(UsageError, match="file exists"):
        write_file(target, "new\n")
    assert target.read_text() == "old\n"
    write_file(target, "new\n", force=True)
    assert target.read_text() == "new\n"
    assert _leftovers(tmp_path) == []


def test_a_full_disk_leaves_the_old_file_and_no_temporary(tmp_path, monkeypatch):
    target = tmp_path / "domain.pddl"
    target.write_text("old\n")
    real = os.fdopen

    class Full:
        def __init__(self, f):
            self.f = f

        def __enter__(self):
            return self

        def __exit__(self, *exc):
            self.f.close()

        def write(self, text):
            raise OSError(errno.ENOSPC, "No space left on device")

        def flush(self):
            pass

    monkeypatch.setattr(os, "fdopen", lambda fd, *a, **k: Full(real(fd, *a, **k)))
    with pytest.raises(OutputError, match="No space left on device") as info:
        write_text(target, "new\n", overwrite=True)
    assert str(info.value).startswith(f"{target}: cannot write file")
    assert target.read_text() == "old\n"
    assert _leftovers(tmp_path) == []


def test_an_interrupt_while_writing_leaves_no_temporary(tmp_path, monkeypatch):
    def interrupted(*a, **k):
        raise KeyboardInterrupt

    monkeypatch.setattr(os, "replace", interrupted)
    with pytest.raises(KeyboardInterrupt):
        write_file(tmp_path / "x.txt", "text")
    assert list(tmp_path.iterdir()) == []


def test_check_target_refuses_early(tmp_path):
    (tmp_path / "out").mkdir()
    (tmp_path / "out" / "old.txt").write_text("x")
    with pytest.raises(UsageError, match="folder exists"):
        OutputFolder(tmp_path / "out")
    (tmp_path / "afile").write_text("x")
    with pytest.raises(UsageError, match="not a folder"):
        OutputFolder(tmp_path / "afile", force=True)
    with pytest.raises(UsageError, match="is not a folder"):
        check_target(tmp_path / "afile" / "inner" / "x.txt", force=False)
    assert OutputFolder(tmp_path / "empty-is-fine").target.name == "empty-is-fine"


def test_force_replaces_the_earlier_folder_as_a_whole(tmp_path):
    target = tmp_path / "models"
    with OutputFolder(target) as out:
        for k in range(3):
            write_file(out.path / f"point-{k}" / "plan.ipc", f"{k}\n")
        out.commit()
    assert sorted(p.name for p in target.iterdir()) == ["point-0", "point-1", "point-2"]
    with OutputFolder(target, force=True) as out:
        write_file(out.path / "point-0" / "plan.ipc", "new\n")
        out.commit()
    assert sorted(p.name for p in target.iterdir()) == ["point-0"]
    assert (target / "point-0" / "plan.ipc").read_text() == "new\n"
    assert _leftovers(tmp_path) == []


@pytest.mark.parametrize("failure", [RuntimeError, KeyboardInterrupt])
def test_a_failure_before_commit_leaves_the_target_untouched(tmp_path, failure):
    target = tmp_path / "models"
    target.mkdir()
    (target / "keep.txt").write_text("earlier run")
    with pytest.raises(failure), OutputFolder(target, force=True) as out:
        write_file(out.path / "half.txt", "x")
        raise failure
    assert [p.name for p in target.iterdir()] == ["keep.txt"]
    assert _leftovers(tmp_path) == []


def _cli(*args):
    import subprocess
    import sys
    from pathlib import Path

    root = Path(__file__).resolve().parent.parent
    return subprocess.run(
        [sys.executable, "-m", "mega_sat.cli.commands", *args],
        capture_output=True,
        text=True,
        cwd=root,
    )


def test_write_model_refuses_an_existing_folder_before_solving(tmp_path):
    target = tmp_path / "models"
    target.mkdir()
    (target / "old.txt").write_text("x")
    r = _cli("frontier", "--task", "domains/rover-martian/p3", "--write-model", str(target))
    assert r.returncode == 2
    assert r.stderr == f"error: {target}: folder exists (use --force to replace it)\n"
    assert r.stdout == ""  # refused before any solving: nothing was computed or printed
    assert [p.name for p in target.iterdir()] == ["old.txt"]


def test_write_model_force_replaces_an_earlier_task_as_a_whole(tmp_path):
    target = tmp_path / "models"
    r = _cli("frontier", "--task", "domains/usar-fetch/p1", "--write-model", str(target))
    assert r.returncode == 0, r.stderr
    assert sorted(p.name for p in target.iterdir()) == ["point-0-E1", "point-1-E3"]
    r = _cli(
        "frontier", "--task", "docs/examples/courier/p1", "--write-model", str(target), "--force"
    )
    assert r.returncode == 0, r.stderr
    names = sorted(p.name for p in target.iterdir())
    assert names == ["point-0-E0", "point-1-E1", "point-2-E3"]  # none of the earlier task's
    steps = (target / "point-2-E3" / "plan.ipc").read_text().splitlines()
    assert [s for s in steps if not s.startswith(";")][0] == "(pick p1 a)"
    assert _leftovers(tmp_path) == []


def test_encode_refuses_an_existing_folder_before_grounding(tmp_path):
    target = tmp_path / "enc"
    r = _cli("encode", "--task", "domains/usar-fetch/p1", "--out", str(target))
    assert r.returncode == 0, r.stderr
    assert sorted(p.name for p in target.iterdir()) == ["opt.cnf", "opt.vars.json", "opt.wcnf"]
    r = _cli("encode", "--task", "domains/usar-fetch/p1", "--out", str(target), "--kind", "joint")
    assert r.returncode == 2 and "folder exists" in r.stderr
    r = _cli("encode", "--task", "domains/usar-fetch/p1", "--out", str(target), "--kind", "joint",
             "--force")  # fmt: skip
    assert r.returncode == 0, r.stderr
    assert sorted(p.name for p in target.iterdir()) == [
        "joint.cnf",
        "joint.vars.json",
        "joint.wcnf",
    ]
    assert _leftovers(tmp_path) == []


def test_written_files_and_folders_follow_the_umask(tmp_path):
    old = os.umask(0o022)
    try:
        f = write_file(tmp_path / "plan.ipc", "x\n")
        b = write_file(tmp_path / "figure.png", b"\x89PNG")
        with OutputFolder(tmp_path / "out") as out:
            write_file(out.path / "a.txt", "a\n")
            out.commit()
    finally:
        os.umask(old)
    assert b.read_bytes() == b"\x89PNG"
    assert (f.stat().st_mode & 0o777, b.stat().st_mode & 0o777) == (0o644, 0o644)
    assert (tmp_path / "out").stat().st_mode & 0o777 == 0o755
    assert (tmp_path / "out" / "a.txt").stat().st_mode & 0o777 == 0o644


def test_special_files_are_never_targets(tmp_path):
    """A FIFO (or a device) in place of an output is refused, with --force too: a folder
    target once listed it (NotADirectoryError), a file target replaced it."""
    fifo = tmp_path / "fifo"
    os.mkfifo(fifo)
    for force in (False, True):
        with pytest.raises(UsageError, match="exists and is not a folder"):
            OutputFolder(fifo, force=force)
        with pytest.raises(UsageError, match="exists and is not a regular file"):
            check_target(fifo, force=force)
    assert fifo.exists() and not fifo.is_file()
    (tmp_path / "afile").write_text("x")
    with pytest.raises(UsageError, match="exists and is not a folder"):
        OutputFolder(tmp_path / "afile")  # not "folder exists (use --force)" first
    with pytest.raises(UsageError, match="is a folder, expected a file"):
        check_target(tmp_path, force=False)


def test_a_folder_no_file_can_be_made_in_is_an_output_error(tmp_path, monkeypatch):
    """Where the permission check passes but no file can be created (/proc, an immutable
    folder as root, a read-only file system): one error line and exit 74, no traceback."""
    import tempfile

    def refuse(*a, **k):
        raise OSError(errno.EROFS, os.strerror(errno.EROFS))

    monkeypatch.setattr(tempfile, "mkstemp", refuse)
    with pytest.raises(OutputError, match="cannot write file: Read-only file system"):
        write_file(tmp_path / "x.txt", "text")
    assert list(tmp_path.iterdir()) == []


def test_generate_checks_its_targets_first_and_reports_write_errors(tmp_path, monkeypatch):
    import shutil

    from mega_sat.bench.generate import write_instance

    root = Path(__file__).resolve().parent.parent / "domains" / "usar-fetch"
    args = (root / "robot-domain.pddl", root / "p1" / "robot-problem.pddl", 1, 0)
    (tmp_path / "taken").mkdir()
    (tmp_path / "taken" / "human-problem.pddl").write_text("x")
    calls = []
    monkeypatch.setattr("mega_sat.bench.generate.generate_human", lambda *a, **k: calls.append(a))
    with pytest.raises(UsageError, match="human-problem.pddl: file exists"):
        write_instance(*args, tmp_path / "taken")
    assert calls == []  # refused before any draw
    monkeypatch.undo()

    def full(*a, **k):
        raise OSError(errno.ENOSPC, os.strerror(errno.ENOSPC), str(a[1]))

    monkeypatch.setattr(shutil, "copyfile", full)
    with pytest.raises(OutputError, match="robot-domain.pddl: cannot write: No space left"):
        write_instance(*args, tmp_path / "new")
