"""Built PDDL parsers kept on disk: a loaded parser reads and rejects files exactly as a built
one, and no cache problem (off, damaged, foreign, unwritable) ever stops a parse."""

from __future__ import annotations

import os
from pathlib import Path

import pytest

from mega_sat.errors import PDDLError
from mega_sat.pddl import library, parser_cache
from mega_sat.pddl.reader import read_model

DATA = Path(__file__).parent / "data" / "frontend"
DOMAINS = Path(__file__).parent.parent / "domains"


@pytest.fixture
def fresh(monkeypatch, tmp_path):
    """The process-wide parsers forgotten (before and after), the cache in ``tmp_path/c``."""
    d = tmp_path / "c"
    monkeypatch.setenv(parser_cache.CACHE_ENV, str(d))
    library._parser.cache_clear()
    yield d
    library._parser.cache_clear()


def _builds(monkeypatch) -> list[str]:
    """Record every parser built from the grammar (a load from the cache builds none)."""
    built: list[str] = []
    real = parser_cache.cached_parser

    def counting(grammar, start, build):
        def b():
            built.append(start)
            return build()

        return real(grammar, start, b)

    monkeypatch.setattr(parser_cache, "cached_parser", counting)
    return built


def _outcomes() -> list:
    """What the reader makes of every malformed test file and of two shipped tasks: an error
    message or a model."""
    out: list = []
    for bad in sorted((DATA / "malformed").glob("*.pddl")):
        for dom, prob in ((bad, DATA / "base-problem.pddl"), (DATA / "base-domain.pddl", bad)):
            try:
                out.append(read_model(dom, prob))
            except PDDLError as e:
                out.append(str(e))
    for task in ("blocksworld/delta/2/p1", "rover-martian/delta/10/p3"):
        d = DOMAINS / task
        out.append(read_model(d / "human-domain.pddl", d / "human-problem.pddl"))
    return out


def test_a_loaded_parser_reads_and_rejects_exactly_as_a_built_one(fresh, monkeypatch):
    monkeypatch.setenv(parser_cache.CACHE_ENV, "")
    built_here = _outcomes()
    library._parser.cache_clear()
    monkeypatch.setenv(parser_cache.CACHE_ENV, str(fresh))
    built = _builds(monkeypatch)
    first = _outcomes()  # builds both parsers and saves them
    assert sorted(built) == ["domain", "problem"]
    assert sorted(p.name.split("-")[1] for p in fresh.iterdir()) == ["domain", "problem"]
    assert not any(p.name.endswith(".tmp") for p in fresh.iterdir())
    library._parser.cache_clear()
    loaded = _outcomes()  # loads both
    assert sorted(built) == ["domain", "problem"], "a saved parser was built again"
    assert built_here == first == loaded
    errors = [o for o in loaded if isinstance(o, str)]
    assert len(errors) >= 19 and any("syntax error" in e for e in errors)


def test_an_empty_variable_turns_the_cache_off(fresh, monkeypatch, tmp_path):
    monkeypatch.setenv(parser_cache.CACHE_ENV, "")
    assert parser_cache.cache_dir() is None
    built = _builds(monkeypatch)
    read_model(DATA / "base-domain.pddl", DATA / "base-problem.pddl")
    assert sorted(built) == ["domain", "problem"] and not fresh.exists()


def test_the_default_place_follows_xdg(monkeypatch, tmp_path):
    monkeypatch.delenv(parser_cache.CACHE_ENV, raising=False)
    monkeypatch.setenv("XDG_CACHE_HOME", str(tmp_path))
    assert parser_cache.cache_dir() == tmp_path / "mega-sat"
    monkeypatch.delenv("XDG_CACHE_HOME")
    monkeypatch.setenv("HOME", str(tmp_path / "home"))
    assert parser_cache.cache_dir() == tmp_path / "home" / ".cache" / "mega-sat"


def test_a_damaged_file_is_built_again_and_replaced(fresh, monkeypatch):
    built = _builds(monkeypatch)
    read_model(DATA / "base-domain.pddl", DATA / "base-problem.pddl")
    for p in fresh.iterdir():
        p.write_bytes(p.read_bytes()[:100])
    library._parser.cache_clear()
    assert read_model(DATA / "base-domain.pddl", DATA / "base-problem.pddl").schemas
    assert len(built) == 4  # both rebuilt
    library._parser.cache_clear()
    read_model(DATA / "base-domain.pddl", DATA / "base-problem.pddl")
    assert len(built) == 4  # and saved whole again


@pytest.mark.skipif(not hasattr(os, "getuid") or os.getuid() == 0, reason="root writes anywhere")
def test_an_unwritable_cache_still_parses(fresh, monkeypatch, tmp_path):
    locked = tmp_path / "locked"
    locked.mkdir(mode=0o500)
    monkeypatch.setenv(parser_cache.CACHE_ENV, str(locked / "c"))
    assert read_model(DATA / "base-domain.pddl", DATA / "base-problem.pddl").schemas


def test_a_cache_path_that_is_a_file_still_parses(fresh, monkeypatch, tmp_path):
    f = tmp_path / "a-file"
    f.write_text("not a directory")
    monkeypatch.setenv(parser_cache.CACHE_ENV, str(f))
    assert read_model(DATA / "base-domain.pddl", DATA / "base-problem.pddl").schemas
    assert f.read_text() == "not a directory"


def test_a_directory_others_can_write_is_neither_read_nor_written(fresh, monkeypatch):
    read_model(DATA / "base-domain.pddl", DATA / "base-problem.pddl")  # saved
    fresh.chmod(0o777)
    before = {p.name: p.stat().st_mtime_ns for p in fresh.iterdir()}
    library._parser.cache_clear()
    built = _builds(monkeypatch)
    read_model(DATA / "base-domain.pddl", DATA / "base-problem.pddl")
    assert sorted(built) == ["domain", "problem"], "a parser was loaded from a shared directory"
    assert len(before) == 2 and before == {p.name: p.stat().st_mtime_ns for p in fresh.iterdir()}


def test_the_key_covers_the_grammar_and_the_start_symbol():
    k = parser_cache.parser_key("grammar", "domain")
    assert k == parser_cache.parser_key("grammar", "domain")
    assert k != parser_cache.parser_key("grammar!", "domain")
    assert k != parser_cache.parser_key("grammar", "problem")


def test_the_key_covers_the_python_version(monkeypatch):
    k = parser_cache.parser_key("grammar", "domain")
    monkeypatch.setattr(parser_cache.sys, "version_info", (3, 99, 0))
    other = parser_cache.parser_key("grammar", "domain")
    monkeypatch.undo()
    assert k != other
