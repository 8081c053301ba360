"""Run limits: one time limit for the whole run, interrupts, one exit-code table, and a
stdout that cannot be written (issue 18 items 3-5, issue 19).

The subprocess tests run the real ``mega-sat`` program, since signals, the backstop timer, the
interpreter's start-up (inside the time limit) and closed or full file descriptors only show
there; each bounds its own wait so that a regression fails instead of hanging.
"""

from __future__ import annotations

import json
import os
import re
import signal
import subprocess
import sys
import time
from pathlib import Path

import pytest
from click.testing import CliRunner

from mega_sat.cli.commands import main
from mega_sat.deadline import MAX_TIMEOUT, NO_DEADLINE, Deadline, TimeLimitReached, parse_timeout
from mega_sat.errors import EXIT_CODES, UsageError
from mega_sat.planners.val import val_available

ROOT = Path(__file__).resolve().parent.parent
USAR = ROOT / "domains" / "usar-fetch" / "p1"
LONG_FRONTIERS = {
    # the hitting-set loop: several seconds, its first point within about a second
    "hitting set": [
        "--task",
        str(ROOT / "domains" / "usar-fetch" / "delta" / "30" / "p1"),
        "--option",
        "counterexample_loop_updates=0",
    ],
    # the counterexample loop: over a minute, no point within the first seconds
    "counterexamples": ["--task", str(ROOT / "domains" / "rover-martian" / "delta" / "30" / "p3")],
}

PROGRAM = [
    sys.executable,
    "-c",
    "import sys; from mega_sat.cli.commands import main; sys.exit(main())",
]
WAIT = 30.0
"""Seconds a subprocess test waits before it kills the child and fails."""


def _runner() -> CliRunner:
    try:
        return CliRunner(mix_stderr=False)  # type: ignore[call-arg]
    except TypeError:
        return CliRunner()


def run(*args):
    return _runner().invoke(main, [str(a) for a in args])


def _spawn(args, **kw) -> subprocess.Popen:
    return subprocess.Popen(
        [*PROGRAM, *map(str, args)],
        cwd=ROOT,
        stdout=subprocess.PIPE,
        stderr=subprocess.PIPE,
        text=True,
        **kw,
    )


def _finish(proc: subprocess.Popen) -> tuple[int, str, str]:
    try:
        out, err = proc.communicate(timeout=WAIT)
    except subprocess.TimeoutExpired:
        proc.kill()
        out, err = proc.communicate()
        pytest.fail(f"still running after {WAIT} s; stderr: {err[-2000:]}")
    return proc.returncode, out, err


def _one_error_line(stderr: str) -> str:
    lines = [ln for ln in stderr.splitlines() if ln.strip() and not ln.startswith(";")]
    assert "Traceback" not in stderr, stderr
    assert len(lines) == 1 and lines[0].startswith("error: "), stderr
    return lines[0]


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
    from mega_sat.pddl.loading import load_task, resolve_task_dir

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
    from mega_sat.pddl.loading import load_task, resolve_task_dir
    from mega_sat.sat.oracles import SatOracles

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


@pytest.mark.parametrize("value", ["nan", "-1", "0", "abc"])
def test_bad_timeout_is_one_line_and_exit_2(value):
    res = run("frontier", "--task", USAR, "--timeout", value)
    assert res.exit_code == 2
    assert "--timeout" in _one_error_line(res.stderr)
    js = run("frontier", "--task", USAR, "--timeout", value, "--json")
    assert js.exit_code == 2 and json.loads(js.stdout)["exit_code"] == 2


@pytest.mark.parametrize("value", ["inf", "1e308", "1e10"])
def test_huge_timeout_means_no_limit(value):
    """These overflowed the oracles' threading.Timer: a traceback from the timer thread."""
    code, out, err = _finish(_spawn(["frontier", "--task", USAR, "--timeout", value, "--json"]))
    assert code == 0 and "Traceback" not in err and "Error" not in err, err
    assert json.loads(out)["complete"] is True


# --------------------------------------------------------------------------- exit codes


def test_exit_code_table_is_documented():
    """docs/cli.md lists exactly the codes of mega_sat.errors.EXIT_CODES."""
    text = (ROOT / "docs" / "cli.md").read_text()
    section = text.split("## Exit codes and errors", 1)[1]
    documented = {int(c) for c in re.findall(r"^\| (\d+) \|", section, re.M)}
    assert documented == set(EXIT_CODES)


COMMANDS = {
    "diff": [],
    "apply": ["--explanation", ROOT / "docs/examples/empty.explanation", "--out", "{tmp}/m"],
    "plan": ["--json"],
    "validate": ["--plan", ROOT / "docs/examples/usar-p1-explicable.plan", "--json"],
    "encode": ["--out", "{tmp}/e"],
    "solve": ["--alpha", "1", "--json"],
    "frontier": ["--json"],
    "explain": ["--json"],
    "verify": [
        "--plan",
        ROOT / "docs/examples/usar-p1-explicable.plan",
        "--explanation",
        ROOT / "docs/examples/usar-p1-low-alpha.explanation",
        "--json",
    ],
}


def _args(cmd, tmp_path, *extra):
    return [cmd, "--task", USAR, *(str(a).format(tmp=tmp_path) for a in COMMANDS[cmd]), *extra]


@pytest.mark.parametrize("cmd", sorted(COMMANDS))
def test_every_command_follows_the_table(cmd, tmp_path):
    """For each command: 0 with an answer, 2 for bad input, 124 when the time limit leaves
    nothing to report; with --json exactly one JSON object on stdout in every case."""
    as_json = "--json" in COMMANDS[cmd]
    ok = run(*_args(cmd, tmp_path, "--timeout", "60"))
    assert ok.exit_code == 0, ok.output
    if as_json:
        json.loads(ok.stdout)
    bad = run(*_args(cmd, tmp_path, "--robot-domain", "nowhere.pddl"))
    assert bad.exit_code == 2 and _one_error_line(bad.stderr)
    late = run(*_args(cmd, tmp_path, "--timeout", "1e-9"))
    assert late.exit_code == 124 and "time limit" in _one_error_line(late.stderr)
    for res, code in ((bad, 2), (late, 124)):
        if as_json:
            d = json.loads(res.stdout)
            assert d["exit_code"] == code and d["error"]
            if code == 124:
                assert d["complete"] is False and d["status"] == "timeout"
        else:
            assert res.stdout == ""


def test_json_errors_are_one_object():
    for args, code in (
        (["solve", "--task", USAR, "--alpha", "-1", "--json"], 2),
        (["frontier", "--task", USAR, "--json", "--nonsense"], 2),
        (["frontier", "--json"], 2),
    ):
        res = run(*args)
        assert res.exit_code == code
        assert json.loads(res.stdout) == {"error": res.stderr.strip()[7:], "exit_code": code}


def _sleep_past_deadline_after_first_point(monkeypatch):
    """JOINT answers as usual, but after the first frontier point the clock runs out."""
    from mega_sat.sat.oracles import SatOracles

    joint = SatOracles.joint

    def slow_joint(self, *args, **kw):
        res = joint(self, *args, **kw)
        if res.plan is not None and self.deadline.limited:
            time.sleep(self.deadline.remaining() + 0.01)
        return res

    monkeypatch.setattr(SatOracles, "joint", slow_joint)


@pytest.mark.parametrize("cmd", [["frontier"], ["solve", "--alpha", "0.1"]])
def test_time_limit_with_a_partial_answer_is_exit_0(cmd, monkeypatch):
    _sleep_past_deadline_after_first_point(monkeypatch)
    res = run(*cmd, "--task", USAR, "--timeout", "1", "--json")
    assert res.exit_code == 0, res.output
    d = json.loads(res.stdout)
    assert d["complete"] is False and d["exact"] is False
    assert [len(p["explanation"]) for p in d["frontier"]] == [1]
    assert 1 <= d["next_size_lower_bound"] <= 3  # the missing point has |E| = 3
    assert any(n.startswith("time limit 1.0s reached") for n in d["notes"])
    if cmd[0] == "solve":
        assert d["chosen"]["robot_cost"] == 8


def _slow_first_point(monkeypatch, engine):
    """The robot optimum comes as usual, then the clock runs out before the first point: the
    sat engine's JOINT calls, or the astar engine's per-node planner calls, wait past the
    deadline."""
    if engine == "sat":
        from mega_sat.sat.oracles import SatOracles

        joint = SatOracles.joint

        def slow_joint(self, *args, **kw):
            if self.deadline.limited:
                time.sleep(self.deadline.remaining() + 0.01)
            return joint(self, *args, **kw)

        monkeypatch.setattr(SatOracles, "joint", slow_joint)
    else:
        from mega_sat.planners.node_planner import NodePlanner

        optimal = NodePlanner.optimal

        def slow_node(self, selection):
            if selection != self.family.robot_selection and self.deadline.limited:
                time.sleep(self.deadline.remaining() + 0.01)
            return optimal(self, selection)

        monkeypatch.setattr(NodePlanner, "optimal", slow_node)


@pytest.mark.parametrize("engine", ["sat", "astar"])
@pytest.mark.parametrize("cmd", [["frontier"], ["solve", "--alpha", "1"]])
def test_time_limit_before_the_first_point_is_exit_124(cmd, engine, monkeypatch, tmp_path):
    """Stopped after the robot optimum but before any point, ``frontier`` has no point to
    report and ``solve`` none to choose from: 124 (an empty frontier with exit 0 read as
    success), with what was proven on the error line (the robot optimum, the lower bound),
    and with ``--json`` the timeout object followed by the frontier object's keys; 3 would
    claim an unsolvable robot problem.  ``--write-model --force`` leaves an earlier folder as
    it was instead of emptying it."""
    _slow_first_point(monkeypatch, engine)
    earlier = tmp_path / "out"
    earlier.mkdir()
    (earlier / "kept.txt").write_text("an earlier run\n")
    args = [*cmd, "--engine", engine, "--task", USAR, "--timeout", "1"]
    res = run(*args, "--json", "--write-model", earlier, "--force")
    assert res.exit_code == 124, res.output
    line = _one_error_line(res.stderr)
    assert line.startswith(
        "error: time limit 1.0s reached before the first frontier point was found "
        "(robot optimal cost 4"
    )
    d = json.loads(res.stdout)
    assert list(d)[:4] == ["complete", "status", "error", "exit_code"]
    assert d["complete"] is False and d["status"] == "timeout" and d["exit_code"] == 124
    assert d["error"] == line.removeprefix("error: ")
    assert d["engine"] == engine and d["robot_optimal_cost"] == 4
    assert d["frontier"] == [] and d["exact"] is False and len(d["model_difference"]) == 3
    bound = d["next_size_lower_bound"]
    if bound:
        assert line.endswith(f"; any solution needs |E| >= {bound})")
    else:
        assert line.endswith("(robot optimal cost 4)")
    assert [p.name for p in earlier.iterdir()] == ["kept.txt"]
    text = run(*args)
    assert text.exit_code == 124 and text.stdout == "", text.output
    assert _one_error_line(text.stderr).startswith(line.split(" (")[0])


def test_a_backstop_stop_before_the_first_point_is_exit_124(monkeypatch, tmp_path):
    """The backstop timer stopping the run between the robot optimum and the first point (the
    engine returns nothing; the CLI takes what it published): the same 124, here with the
    lower bound on cost(E) under update costs (the first candidate, E = {}, has no point)."""
    from mega_sat.sat.oracles import SatOracles

    joint = SatOracles.joint
    calls = []

    def forced_on_the_second_call(self, *args, **kw):
        calls.append(1)
        if len(calls) == 2:
            raise TimeLimitReached(60.0, forced=True)
        return joint(self, *args, **kw)

    monkeypatch.setattr(SatOracles, "joint", forced_on_the_second_call)
    costs = tmp_path / "costs.txt"
    delta = run("diff", "--task", USAR).stdout.splitlines()
    costs.write_text("".join(f"{u} 5\n" for u in delta))
    res = run("frontier", "--task", USAR, "--timeout", "60", "--update-costs", costs, "--json")
    assert res.exit_code == 124, res.output
    d = json.loads(res.stdout)
    assert d["status"] == "timeout" and d["frontier"] == [] and d["next_cost_lower_bound"] == 5
    assert d["error"] == (
        "time limit 60.0s reached before the first frontier point was found "
        "(robot optimal cost 4; any solution needs cost(E) >= 5)"
    )


def test_choose_from_an_empty_frontier():
    """An empty frontier cut short by the time limit raises the stop, with the bound proven;
    a complete empty one (no solution at all) is an unsolvable request."""
    from mega_sat.errors import UnsolvableError
    from mega_sat.results import Frontier, choose

    cut = Frontier("sat", 5, ("u",), (), False, False, next_cost_lower_bound=2)
    with pytest.raises(TimeLimitReached, match=r"any solution needs \|E\| >= 2") as got:
        choose(cut, 1.0)
    assert got.value.detail == "any solution needs |E| >= 2"
    with pytest.raises(UnsolvableError, match="no MEGA solution found"):
        choose(Frontier("sat", 5, ("u",), (), True, True), 1.0)


def test_time_limit_during_verify_keeps_the_answer(monkeypatch):
    """A limit reached while --verify checks a finished frontier: the frontier stays exact,
    the reports made so far are printed, and the run is marked incomplete (exit 0)."""
    import mega_sat.api as api

    verify_pair = api.verify_pair
    calls = []

    def slow_second_check(*args, **kw):
        calls.append(1)
        if len(calls) == 2:
            time.sleep(kw["deadline"].remaining() + 0.01)
        return verify_pair(*args, **kw)

    monkeypatch.setattr(api, "verify_pair", slow_second_check)
    args = ["frontier", "--task", ROOT / "domains/blocksworld/p2", "--verify", "--timeout", "3"]
    res = run(*args, "--json")
    assert res.exit_code == 0, res.output
    d = json.loads(res.stdout)
    assert d["exact"] is True and d["complete"] is False
    assert len(d["frontier"]) == 3 and len(d["verify"]) == 1 and d["verify"][0]["ok"]
    assert d["notes"] == ["time limit 3.0s reached during --verify: 1 of 3 point(s) checked"]
    calls.clear()
    text = run(*args).stdout
    assert "exact: yes" in text and text.count("verify: not checked") == 2
    assert "incomplete: time limit 3.0s reached during --verify" in text


@pytest.mark.parametrize(
    "cmd", [["frontier"], ["solve", "--alpha", "1"], ["explain"], ["plan"], ["verify"]]
)
def test_time_limit_during_grounding(cmd, big_grounding):
    """The limit bounds grounding too: these ran for minutes (frontier exited 4, solve 3,
    explain 2 once the engines gave up), now each stops within max(1 s, 5 %) with 124."""
    if cmd == ["verify"]:
        (big_grounding / "e.txt").write_text("")
        (big_grounding / "x.plan").write_text("(go o0 o1)\n")
        cmd += ["--explanation", big_grounding / "e.txt", "--plan", big_grounding / "x.plan"]
    t0 = time.perf_counter()
    code, out, err = _finish(_spawn([*cmd, "--task", big_grounding, "--timeout", "1.5", "--json"]))
    elapsed = time.perf_counter() - t0
    assert code == 124, err
    assert "time limit 1.5s" in _one_error_line(err)
    assert json.loads(out) == {
        "complete": False,
        "status": "timeout",
        "error": "time limit 1.5s reached before anything could be reported",
        "exit_code": 124,
    }
    assert elapsed < 1.5 + 1.0, f"stopped after {elapsed:.2f} s"


def test_large_grounding_stops_within_the_slack(big_grounding):
    t0 = time.perf_counter()
    code, _, err = _finish(_spawn(["frontier", "--task", big_grounding, "--timeout", "3"]))
    elapsed = time.perf_counter() - t0
    assert code == 124 and "Traceback" not in err
    assert 2.9 < elapsed < 3.0 + 1.0, f"stopped after {elapsed:.2f} s"


# --------------------------------------------------------------------------- interrupts


@pytest.mark.parametrize("loop", sorted(LONG_FRONTIERS))
@pytest.mark.parametrize("sig, code", [(signal.SIGINT, 130), (signal.SIGTERM, 143)])
def test_interrupt_prints_the_partial_frontier(sig, code, loop):
    proc = _spawn(["frontier", *LONG_FRONTIERS[loop], "--json"])
    time.sleep(3.0)
    assert proc.poll() is None, "the frontier ended before the signal"
    proc.send_signal(sig)
    exit_code, out, err = _finish(proc)
    assert exit_code == code, err
    assert "Traceback" not in err and "Aborted" not in err, err
    d = json.loads(out)
    assert d["complete"] is False
    if "status" in d:  # stopped before the robot optimum was known
        assert d["status"] == "interrupted" and d["exit_code"] == code
    else:
        assert d["exact"] is False and any("interrupted by" in n for n in d["notes"])


def test_interrupt_keeps_the_points_found(monkeypatch):
    """SIGINT once the first point is proven: that point is printed, then exit 130."""
    from mega_sat.sat.oracles import SatOracles

    joint = SatOracles.joint
    found = []

    def joint_then_ctrl_c(self, *args, **kw):
        if found:
            os.kill(os.getpid(), signal.SIGINT)
        res = joint(self, *args, **kw)
        if res.plan is not None:
            found.append(res)
        return res

    monkeypatch.setattr(SatOracles, "joint", joint_then_ctrl_c)
    res = run("frontier", "--task", USAR, "--json")
    assert res.exit_code == 130, res.output
    d = json.loads(res.stdout)
    assert d["complete"] is False and len(d["frontier"]) == 1
    assert d["frontier"][0]["robot_cost"] == found[0].robot_cost
    assert signal.getsignal(signal.SIGINT) is signal.default_int_handler  # handlers restored


SAT_CALL = """
import sys
sys.path.insert(0, {tests!r})
from test_oracles import _add_pigeonhole, _chain
from mega_sat.sat.oracles import SatOracles
orc = SatOracles(_chain(3), solver="cadical195")
act = _add_pigeonhole(orc, 12, 11)
print("solving", flush=True)
try:
    orc.solving.solve(orc.solving.joint_solver, [act])
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


FAKE_CBC = """#!{python}
import time
time.sleep(120)
"""


@pytest.mark.parametrize("sig, code", [(signal.SIGINT, 130), (signal.SIGTERM, 143)])
def test_interrupt_ends_cbc_and_removes_its_files(sig, code, tmp_path):
    """CBC (here a stand-in that never answers) must not outlive mega-sat, and PuLP's
    temporary *-pulp.mps/.sol files must go with it."""
    fake = tmp_path / "fake-cbc"
    fake.write_text(FAKE_CBC.format(python=sys.executable))
    fake.chmod(0o755)
    tmp = tmp_path / "tmp"
    tmp.mkdir()
    patch = f"import pulp; pulp.PULP_CBC_CMD.pulp_cbc_path = {str(fake)!r}; "
    proc = subprocess.Popen(
        [sys.executable, "-c", patch + PROGRAM[2]]
        + ["frontier", "--task", str(USAR), "--hitting-set", "ilp", "--json"],
        cwd=ROOT,
        stdout=subprocess.PIPE,
        stderr=subprocess.PIPE,
        text=True,
        env={**os.environ, "TMPDIR": str(tmp), "TMP": str(tmp)},
    )
    cbc = None
    try:
        for _ in range(200):
            cbc = _child_running(proc.pid, str(fake))
            if cbc is not None or proc.poll() is not None:
                break
            time.sleep(0.05)
        assert cbc is not None, "the stand-in CBC never started"
        proc.send_signal(sig)
        exit_code, out, err = _finish(proc)
        assert exit_code == code and "Traceback" not in err, err
        assert json.loads(out)["complete"] is False
        assert not _alive(cbc), "CBC outlived mega-sat"
        assert list(tmp.rglob("*")) == [], "temporary files left behind"
    finally:
        if cbc is not None and _alive(cbc):
            os.kill(cbc, signal.SIGKILL)


FAKE_FD = """import subprocess, sys, time
subprocess.Popen([sys.executable, "-c", "import time; time.sleep(120)", {marker!r}])
time.sleep(120)
"""


@pytest.mark.parametrize("sig, code", [(signal.SIGINT, 130), (signal.SIGTERM, 143)])
def test_interrupt_ends_fast_downward(sig, code, tmp_path):
    """Fast Downward (here a stand-in driver with a search child) runs in its own session, so
    no signal reaches it but the one mega-sat sends: its whole group must end with mega-sat."""
    marker = str(tmp_path / "fake-fd-search")
    fake = tmp_path / "fake-fast-downward.py"
    fake.write_text(FAKE_FD.format(marker=marker))
    patch = (
        "import mega_sat.planners.fast_downward as fd, pathlib; "
        f"fd.fd_script = lambda: pathlib.Path({str(fake)!r}); "
    )
    proc = subprocess.Popen(
        [sys.executable, "-c", patch + PROGRAM[2]]
        + ["plan", "--task", str(USAR), "--planner", "fd", "--json"],
        cwd=ROOT,
        stdout=subprocess.PIPE,
        stderr=subprocess.PIPE,
        text=True,
    )
    search = None
    try:
        for _ in range(200):
            search = _process_with(marker)
            if search is not None or proc.poll() is not None:
                break
            time.sleep(0.05)
        assert search is not None, "the stand-in search never started"
        proc.send_signal(sig)
        exit_code, out, err = _finish(proc)
        assert exit_code == code and "Traceback" not in err, err
        assert json.loads(out)["status"] == "interrupted"
        time.sleep(0.2)
        assert not _alive(search), "Fast Downward's search outlived mega-sat"
    finally:
        if search is not None and _alive(search):
            os.kill(search, signal.SIGKILL)


def _process_with(marker: str) -> int | None:
    for entry in os.listdir("/proc"):
        if entry.isdigit():
            try:
                cmdline = Path(f"/proc/{entry}/cmdline").read_bytes().decode(errors="replace")
            except OSError:
                continue
            if marker in cmdline and _alive(int(entry)):
                return int(entry)
    return None


def _child_running(parent: int, marker: str) -> int | None:
    for entry in os.listdir("/proc"):
        if not entry.isdigit():
            continue
        try:
            stat = Path(f"/proc/{entry}/stat").read_text()
            cmdline = Path(f"/proc/{entry}/cmdline").read_bytes().decode(errors="replace")
        except OSError:
            continue
        if int(stat.rsplit(")", 1)[1].split()[1]) == parent and marker in cmdline:
            return int(entry)
    return None


def _alive(pid: int) -> bool:
    try:
        state = Path(f"/proc/{pid}/stat").read_text().rsplit(")", 1)[1].split()[0]
    except OSError:
        return False
    return state != "Z"


# --------------------------------------------------------------------------- stdout


def test_full_disk_on_stdout_is_an_error():
    with open("/dev/full", "w") as full:
        proc = subprocess.Popen(
            [*PROGRAM, "solve", "--task", str(USAR), "--alpha", "1"],
            cwd=ROOT,
            stdout=full,
            stderr=subprocess.PIPE,
            text=True,
        )
        _, err = proc.communicate(timeout=WAIT)
    assert proc.returncode == 74
    assert "No space left" in _one_error_line(err)


@pytest.mark.parametrize("args", [["diff", "--task", str(USAR)], ["solve", "--help"]])
def test_closed_stdout_is_an_error(args):
    proc = subprocess.Popen(
        [*PROGRAM, *args],
        cwd=ROOT,
        stdout=subprocess.PIPE,
        stderr=subprocess.PIPE,
        text=True,
        preexec_fn=lambda: os.close(1),
    )
    _, err = proc.communicate(timeout=WAIT)
    assert proc.returncode == 74
    assert "standard output" in _one_error_line(err)


def test_verify_cut_short_by_the_limit_reports_the_checks_it_finished(monkeypatch):
    """The two validity checks are done before the optimum of human + E is re-derived; a time
    limit there says what was checked instead of nothing."""
    from mega_sat import api
    from mega_sat.deadline import TimeLimitReached
    from mega_sat.planners.node_planner import NodePlanner

    task = api.load_task_dir(ROOT / "domains/usar-fetch/p1")
    point = api.MegaSolver(task).frontier().points[0]

    def slow(self, selection):
        raise TimeLimitReached(3.0, forced=True)

    monkeypatch.setattr(NodePlanner, "optimal", slow)
    with pytest.raises(TimeLimitReached) as info:
        api.MegaSolver(task).verify(point)
    assert info.value.forced and info.value.partial
    assert info.value.detail.startswith("checked: valid in robot model: ok (cost ")
    assert "valid in human + E: ok" in info.value.detail
    assert "; not checked: optimal in human + E (by " in info.value.detail
    names = [c.name for c in info.value.checks]
    assert names == ["valid in robot model", "robot cost as reported", "valid in human + E",
                     "human cost as reported"]  # fmt: skip
    assert info.value.pending.startswith("optimal in human + E (by ")


VERIFY_ARGS = [
    "verify",
    "--task",
    USAR,
    "--plan",
    ROOT / "docs/examples/usar-p1-explicable.plan",
    "--explanation",
    ROOT / "docs/examples/usar-p1-low-alpha.explanation",
]
VALID = [
    {"name": "valid in robot model", "ok": True, "detail": "cost 8"},
    {"name": "valid in human + E", "ok": True, "detail": "cost 8"},
]


def test_verify_json_cut_short_lists_the_checks_it_finished(monkeypatch):
    """``verify --json`` stopped by the limit while re-deriving the optimum: the checks done
    are ``checks_done`` of the timeout object, the same objects as the complete report's
    ``checks`` (they were only inside the ``error`` text); the text run has one error line."""
    from mega_sat.planners.node_planner import NodePlanner

    def late(self, selection):
        raise TimeLimitReached(60.0, forced=True)

    monkeypatch.setattr(NodePlanner, "optimal", late)
    res = run(*VERIFY_ARGS, "--checker", "builtin", "--timeout", "60", "--json")
    assert res.exit_code == 124, res.output
    d = json.loads(res.stdout)
    assert list(d) == ["complete", "status", "error", "exit_code", "checks_done"]
    assert d["complete"] is False and d["status"] == "timeout" and d["exit_code"] == 124
    assert d["checks_done"] == VALID
    assert d["error"] == (
        "time limit 60.0s reached before the answer was complete; checked: valid in robot "
        "model: ok (cost 8); valid in human + E: ok (cost 8); not checked: optimal in human + E "
        "(by builtin)" + (" and the VAL checks" if val_available() else "")
    )
    assert _one_error_line(res.stderr) == "error: " + d["error"]
    text = run(*VERIFY_ARGS, "--checker", "builtin", "--timeout", "60")
    assert text.exit_code == 124 and text.stdout == "" and _one_error_line(text.stderr)


@pytest.mark.skipif(not val_available(), reason="needs VAL")
def test_verify_cut_short_in_val_keeps_the_checks_before_it(monkeypatch):
    """A limit reached while VAL runs (it once went up as 'before anything could be
    reported', dropping the finished checks): the optimum's check is among ``checks_done``."""
    import mega_sat.planners.val as val

    def late(*args, **kw):
        raise TimeLimitReached(60.0)

    monkeypatch.setattr(val, "val_validate", late)
    res = run(*VERIFY_ARGS, "--checker", "builtin", "--timeout", "60", "--json")
    assert res.exit_code == 124, res.output
    d = json.loads(res.stdout)
    optimal = {
        "name": "optimal in human + E",
        "ok": True,
        "detail": "optimum of human + E by builtin: 8; plan: 8",
    }
    assert d["checks_done"] == [*VALID, optimal]
    assert d["error"].startswith("time limit 60.0s reached before the answer was complete; ")
    assert d["error"].endswith("; not checked: VAL: valid in robot model")
