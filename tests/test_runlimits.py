"""Run limits: one time limit for the whole run, and interrupts (issue 18 items 3-4).

The subprocess tests run a separate interpreter, since signals only show there; each bounds its
own wait so that a regression fails instead of hanging.
"""

from __future__ import annotations

import signal
import subprocess
import sys
import time
from pathlib import Path

import pytest

from mega_sat.deadline import MAX_TIMEOUT, NO_DEADLINE, Deadline, TimeLimitReached, parse_timeout
from mega_sat.errors import UsageError

ROOT = Path(__file__).resolve().parent.parent
USAR = ROOT / "domains" / "usar-fetch" / "p1"
WAIT = 30.0
"""Seconds a subprocess test waits before it kills the child and fails."""


def _finish(proc: subprocess.Popen) -> tuple[int, str, str]:
    try:
        out, err = proc.communicate(timeout=WAIT)
    except subprocess.TimeoutExpired:
        proc.kill()
        out, err = proc.communicate()
        pytest.fail(f"still running after {WAIT} s; stderr: {err[-2000:]}")
    return proc.returncode, out, err


@pytest.fixture
def big_grounding(tmp_path) -> Path:
    """A task whose grounding alone takes many seconds: a robot-only action of 5 untyped
    parameters without preconditions over 14 objects (537,824 ground actions)."""
    params = " ".join(f"?p{i}" for i in range(5))
    common = """ (:predicates (at ?x) (road ?x ?y) (done))
 (:action go :parameters (?x ?y) :precondition (and (at ?x) (road ?x ?y))
  :effect (and (not (at ?x)) (at ?y)))"""
    (tmp_path / "robot-domain.pddl").write_text(
        f"(define (domain big) (:requirements :strips)\n{common}\n"
        f" (:action big :parameters ({params}) :precondition () :effect (done)))\n"
    )
    (tmp_path / "human-domain.pddl").write_text(
        f"(define (domain big) (:requirements :strips)\n{common})\n"
    )
    objects = " ".join(f"o{i}" for i in range(14))
    (tmp_path / "robot-problem.pddl").write_text(
        f"(define (problem p) (:domain big) (:objects {objects})"
        " (:init (at o0) (road o0 o1)) (:goal (at o1)))\n"
    )
    return tmp_path


# --------------------------------------------------------------------------- the deadline


def test_timeout_values():
    assert parse_timeout(None) is None
    assert parse_timeout("2.5") == 2.5 and parse_timeout(3) == 3.0
    for unlimited in ("inf", "1e308", "1e10", float("inf"), MAX_TIMEOUT * 2):
        assert parse_timeout(unlimited) is None
    for bad in ("nan", "0", "-1", "-inf", "abc", "", "0x10", float("nan")):
        with pytest.raises(UsageError):
            parse_timeout(bad)


def test_deadline_checks():
    assert Deadline.after(None) is NO_DEADLINE and Deadline.after("inf") is NO_DEADLINE
    NO_DEADLINE.check()
    assert NO_DEADLINE.remaining() is None and NO_DEADLINE.cap(2.0) == 2.0
    d = Deadline.after(60)
    assert 59 < d.remaining() <= 60 and d.cap(2.0) == 2.0 and d.cap(None) <= 60
    d.check()
    late = Deadline.after(60, elapsed=61)  # started 61 s ago
    assert late.expired() and late.remaining() == 0
    with pytest.raises(TimeLimitReached):
        late.check()


def test_api_time_limit_covers_grounding(big_grounding):
    """MegaSolver(timeout=...) counts from its creation and grounding checks the deadline."""
    from mega_sat.api import MegaSolver
    from mega_sat.loading import load_task, resolve_task_dir

    task = load_task(**resolve_task_dir(str(big_grounding)))
    t0 = time.perf_counter()
    solver = MegaSolver(task, timeout=1.0)
    with pytest.raises(TimeLimitReached):
        solver.frontier()
    assert time.perf_counter() - t0 < 2.0
    assert solver.partial_frontier("stopped") is None  # no robot optimum yet


def test_api_partial_frontier_after_an_interrupt(monkeypatch):
    """The points proven before an interrupt (here KeyboardInterrupt in the second JOINT call
    after the first point) stay available, marked incomplete."""
    from mega_sat.api import MegaSolver
    from mega_sat.loading import load_task, resolve_task_dir
    from mega_sat.oracles import SatOracles

    joint = SatOracles.joint
    found = []

    def joint_then_ctrl_c(self, *args, **kw):
        if found:
            raise KeyboardInterrupt
        res = joint(self, *args, **kw)
        if res.plan is not None:
            found.append(res)
        return res

    monkeypatch.setattr(SatOracles, "joint", joint_then_ctrl_c)
    solver = MegaSolver(load_task(**resolve_task_dir(str(USAR))))
    with pytest.raises(KeyboardInterrupt):
        solver.frontier()
    fr = solver.partial_frontier("interrupted")
    assert not fr.complete and not fr.exact and fr.notes[-1].startswith("interrupted")
    assert [(p.size, p.robot_cost) for p in fr.points] == [(1, found[0].robot_cost)]
    assert fr.robot_optimal_cost == 4 and fr.next_size_lower_bound is not None
    assert solver.partial_solution(10, "interrupted").chosen.size == 1


# --------------------------------------------------------------------------- interrupts


SAT_CALL = """
import sys
sys.path.insert(0, {tests!r})
from test_oracles import _add_pigeonhole, _chain
from mega_sat.oracles import SatOracles
orc = SatOracles(_chain(3), solver="cadical195")
act = _add_pigeonhole(orc, 12, 11)
print("solving", flush=True)
try:
    orc._solve(orc._joint_solver, [act])
except KeyboardInterrupt:
    print("KeyboardInterrupt")
except Exception as e:
    print(type(e).__module__, type(e).__name__, e)
"""


def test_ctrl_c_during_a_sat_call_is_an_ordinary_interrupt():
    """python-sat catches SIGINT inside CaDiCaL and raised 'pysolvers.error: Caught keyboard
    interrupt' (leaving SIGINT blocked); the oracles turn it back into the process's SIGINT."""
    proc = subprocess.Popen(
        [sys.executable, "-c", SAT_CALL.format(tests=str(ROOT / "tests"))],
        cwd=ROOT,
        stdout=subprocess.PIPE,
        stderr=subprocess.PIPE,
        text=True,
    )
    assert proc.stdout.readline().strip() == "solving"
    time.sleep(0.5)
    proc.send_signal(signal.SIGINT)
    _, out, err = _finish(proc)
    assert out.strip() == "KeyboardInterrupt", (out, err)
