"""Fuzzing the readers: mutated PDDL, plan and explanation texts end in a model or in one clear
``MegaSatError`` line, never in another exception.

The budget is small by default, with a fixed seed (``tests/fuzzing.py``); ``--fuzz-long`` or
``MEGA_SAT_FUZZ_LONG=1`` runs many more cases for release checks.
"""

from __future__ import annotations

from pathlib import Path

import pytest
from helpers.fuzzing import FUZZ
from hypothesis import given
from hypothesis import strategies as st

from mega_sat.errors import MegaSatError
from mega_sat.pddl.loading import load_task_from_strings
from mega_sat.pddl.planio import parse_plan
from mega_sat.pddl.reader import parse_model

pytestmark = pytest.mark.filterwarnings("ignore::mega_sat.pddl.reader.PDDLWarning")

ROOT = Path(__file__).resolve().parent.parent
SOURCES = sorted(
    p
    for pattern in ("domains/*/*.pddl", "domains/*/p1/*.pddl", "docs/examples/*/*.pddl")
    for p in ROOT.glob(pattern)
)
DOMAIN = (ROOT / "domains/usar-fetch/robot-domain.pddl").read_text()
PROBLEM = (ROOT / "domains/usar-fetch/p1/robot-problem.pddl").read_text()
HUMAN = (ROOT / "domains/usar-fetch/human-domain.pddl").read_text()
TOKENS = ["(", ")", "(", ")", "-", "?x", "and", "not", ":action", ":effect", "either",
          "(increase (total-cost) 3)", "object", ";", "\n", "\t", "\ufeff", "\x00", "é", "="]  # fmt: skip


@st.composite
def mutated(draw, text: str) -> str:
    """``text`` with a few random token-level edits: deletions, duplications, insertions,
    truncation, random characters."""
    parts = text.split(" ")
    for _ in range(draw(st.integers(1, 4))):
        if not parts:
            break
        k = draw(st.integers(0, len(parts) - 1))
        op = draw(st.sampled_from(["delete", "duplicate", "insert", "truncate", "chars"]))
        if op == "delete":
            del parts[k]
        elif op == "duplicate":
            parts.insert(k, parts[k])
        elif op == "insert":
            parts.insert(k, draw(st.sampled_from(TOKENS)))
        elif op == "truncate":
            parts = parts[:k]
        else:
            parts[k] = draw(st.text(max_size=6))
    return " ".join(parts)


def _clean(e: MegaSatError) -> None:
    text = str(e)
    assert text and not text.startswith("error: ") and "\n" not in text and "Traceback" not in text


@FUZZ
@given(data=st.data())
def test_mutated_domains_and_problems(data):
    source = data.draw(st.sampled_from(SOURCES))
    text = data.draw(mutated(source.read_text()))
    is_problem = "(problem" in source.read_text()
    try:
        if is_problem:
            parse_model(DOMAIN, text, domain_path="d.pddl", problem_path="p.pddl")
        else:
            parse_model(text, PROBLEM, domain_path="d.pddl", problem_path="p.pddl")
    except MegaSatError as e:
        _clean(e)


@FUZZ
@given(text=st.text(max_size=200))
def test_random_text_as_pddl(text):
    try:
        parse_model(text, PROBLEM)
    except MegaSatError as e:
        _clean(e)


@FUZZ
@given(data=st.data())
def test_mutated_human_domains_form_a_task_or_fail_cleanly(data):
    text = data.draw(mutated(HUMAN))
    try:
        load_task_from_strings(DOMAIN, PROBLEM, text)
    except MegaSatError as e:
        _clean(e)


@FUZZ
@given(text=st.text(max_size=120))
def test_random_plans(text):
    try:
        parse_plan(text)
    except MegaSatError as e:
        _clean(e)


def test_binary_file_as_pddl_and_plan(tmp_path):
    from mega_sat.pddl.loading import load_task
    from mega_sat.pddl.planio import read_plan

    blob = tmp_path / "blob.bin"
    blob.write_bytes(bytes(range(256)) * 4)
    with pytest.raises(MegaSatError, match="not UTF-8 text") as info:
        read_plan(blob)
    _clean(info.value)
    files = [ROOT / "domains/usar-fetch/robot-domain.pddl", blob]
    with pytest.raises(MegaSatError, match="not UTF-8 text"):
        load_task(*files, files[0])
    with pytest.raises(MegaSatError, match="is a directory"):
        read_plan(tmp_path)
