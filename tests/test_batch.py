"""``mega-sat batch`` and the executor it shares with ``bench``: one line per task, the same
frontier as ``frontier --json``, resumption after any stop, and runs on a Dask cluster where a
dying worker loses nothing already written."""

from __future__ import annotations

import json
import os
import signal
import subprocess
import sys
import time
from pathlib import Path

import pytest

from mega_sat.cli.batch import find_task_dirs, read_done, read_task
from mega_sat.errors import MegaSatError
from mega_sat.executor import completed

ROOT = Path(__file__).resolve().parents[1]
USAR = ["domains/usar-fetch/p1", "domains/usar-fetch/p2", "domains/usar-fetch/p3"]
CLI = [sys.executable, "-c", "import sys; from mega_sat.cli.commands import main; sys.exit(main())"]


def _batch(*args: str, **kw) -> subprocess.CompletedProcess:
    return subprocess.run(
        [*CLI, "batch", *args], cwd=ROOT, capture_output=True, text=True, timeout=300, **kw
    )


def _lines(path: Path) -> list[dict]:
    return [json.loads(x) for x in path.read_text().splitlines() if x.strip()]


def _points(result: dict) -> list:
    return [
        (p["explanation"], p["plan"], p["robot_cost"], p["human_cost"]) for p in result["frontier"]
    ]


@pytest.fixture(scope="module")
def usar_frontiers() -> dict[str, dict]:
    out = {}
    for t in USAR:
        r = subprocess.run(
            [*CLI, "frontier", "--task", t, "--json"], cwd=ROOT, capture_output=True, text=True
        )
        out[t] = json.loads(r.stdout)
    return out


def test_find_task_dirs(tmp_path):
    assert find_task_dirs([ROOT / "domains/usar-fetch/p1"]) == [ROOT / "domains/usar-fetch/p1"]
    below = find_task_dirs([ROOT / "domains/usar-fetch"])
    assert ROOT / "domains/usar-fetch/p2" in below and len(below) == 21
    assert below == sorted(below)
    for bad, message in [
        (tmp_path / "none", "not found"),
        (ROOT / "README.md", "is not a folder"),
        (tmp_path, "no task folder"),
    ]:
        with pytest.raises(MegaSatError, match=message):
            find_task_dirs([bad])


def test_batch_writes_the_frontier_of_every_task(tmp_path, usar_frontiers):
    out = tmp_path / "r.jsonl"
    r = _batch(*USAR, "--out", str(out), "--jobs", "2", "--task-timeout", "60", "--json")
    assert r.returncode == 0, r.stderr
    summary = json.loads(r.stdout)
    assert summary == {
        "out": str(out),
        "tasks": 3,
        "already_done": 0,
        "written": 3,
        "failed": [],
        "complete": True,
        "stopped": None,
    }
    lines = _lines(out)
    assert sorted(x["task"] for x in lines) == USAR
    for x in lines:
        assert x["exit_code"] == 0
        expected = usar_frontiers[x["task"]]
        assert _points(x["result"]) == _points(expected)
        assert (
            x["result"]["exact"] and x["result"]["model_difference"] == expected["model_difference"]
        )
    assert r.stderr.count("exit 0,") == 3  # one progress line per task


def test_a_task_with_several_human_models_is_one_task(tmp_path):
    """``batch domains/`` meets usar-two-commanders: its human-K folders make one task, run as
    ``frontier`` runs it, with the user's file names in the result."""
    task = "domains/usar-two-commanders"
    assert find_task_dirs([ROOT / "domains"]).count(ROOT / task) == 1
    out = tmp_path / "r.jsonl"
    r = _batch(task, "--out", str(out))
    assert r.returncode == 0, r.stderr
    (line,) = _lines(out)
    direct = subprocess.run(
        [*CLI, "frontier", "--task", task, "--json"], cwd=ROOT, capture_output=True, text=True
    )
    expected = json.loads(direct.stdout)
    assert line["exit_code"] == 0 and line["result"]["engine"] == "multi-human"
    assert line["result"]["frontier"] == expected["frontier"] != []
    assert [h["problem"] for h in line["result"]["human_models"]] == [
        f"{task}/human-1/human-problem.pddl",
        f"{task}/human-2/human-problem.pddl",
    ]


def test_human_k_folders_are_part_of_their_task(tmp_path):
    """A human-K folder that also holds a robot problem is no task of its own, and human-01
    beside human-1 is an error naming both (which one is meant would be a guess)."""
    import shutil

    task = tmp_path / "A"
    shutil.copytree(ROOT / "domains/usar-two-commanders", task)
    shutil.copy(task / "robot-problem.pddl", task / "human-2" / "robot-problem.pddl")
    assert find_task_dirs([tmp_path]) == [task]
    shutil.copytree(task / "human-1", task / "human-01")
    with pytest.raises(MegaSatError, match="human-01/ and human-1/ both number human model 1"):
        read_task(task)


def test_messages_name_the_users_files(tmp_path):
    bad = tmp_path / "bad"
    bad.mkdir()
    (bad / "robot-problem.pddl").write_text((ROOT / USAR[0] / "robot-problem.pddl").read_text())
    for f in ("robot-domain.pddl", "human-domain.pddl"):
        (bad / f).write_text("(define (domain usar-fetch) (:action")
    out = tmp_path / "r.jsonl"
    r = _batch(str(bad), "--out", str(out))
    assert r.returncode == 0, r.stderr
    (line,) = _lines(out)
    assert line["exit_code"] == 2
    assert line["result"]["error"].startswith(str(bad / "robot-domain.pddl") + ": line 1")


def test_resume_skips_written_tasks_and_drops_a_cut_line(tmp_path):
    out = tmp_path / "r.jsonl"
    kept = {"task": USAR[1], "exit_code": 0, "result": {"marker": "kept as it is"}}
    out.write_text(json.dumps(kept) + '\n{"task": "domains/usar-fetch/p3", "exit')
    r = _batch(*USAR, "--out", str(out))
    assert r.returncode == 0, r.stderr
    assert "2 task(s) written now, 1 already there, 0 failed, of 3" in r.stdout
    lines = _lines(out)
    assert lines[0] == kept
    assert sorted(x["task"] for x in lines) == USAR
    r = _batch(*USAR, "--out", str(out))  # nothing left to do
    assert "0 task(s) written now, 3 already there" in r.stdout
    assert len(_lines(out)) == 3


def test_a_foreign_file_is_refused_unless_forced(tmp_path):
    out = tmp_path / "r.jsonl"
    out.write_text("my notes\nmore notes\n")
    r = _batch(USAR[0], "--out", str(out))
    assert r.returncode == 2
    assert r.stderr.strip() == (
        f"error: {out}: line 1: not a line of mega-sat batch results "
        "(use --force to start the file afresh)"
    )
    assert out.read_text() == "my notes\nmore notes\n"
    r = _batch(USAR[0], "--out", str(out), "--force")
    assert r.returncode == 0 and [x["task"] for x in _lines(out)] == [USAR[0]]
    with pytest.raises(MegaSatError, match="line 2"):
        (tmp_path / "x.jsonl").write_text('{"task": "a"}\n[1]\n{"task": "b"}\n')
        read_done(tmp_path / "x.jsonl")


def _slow_tasks(tmp_path: Path, n: int) -> list[str]:
    """``n`` copies of a task that runs until its time limit (rover-martian at Δ = 30: no point within a minute)."""
    src = ROOT / "domains/rover-martian/delta/30/p2"
    dirs = []
    for k in range(n):
        d = tmp_path / f"slow{k}"
        d.mkdir()
        for f in src.iterdir():
            (d / f.name).write_text(f.read_text())
        dirs.append(str(d))
    return dirs


def _wait_for_lines(out: Path, n: int, proc: subprocess.Popen, limit: float = 120) -> None:
    t0 = time.time()
    while time.time() - t0 < limit:
        if out.exists() and out.read_text().count("\n") >= n:
            return
        assert proc.poll() is None, proc.communicate()
        time.sleep(0.1)
    raise AssertionError("no lines written in time")


def _children(pid: int) -> list[int]:
    r = subprocess.run(["pgrep", "-P", str(pid)], capture_output=True, text=True)
    return [int(x) for x in r.stdout.split()]


def _running(pid: int) -> bool:
    try:
        state = Path(f"/proc/{pid}/stat").read_text().rsplit(")", 1)[1].split()[0]
    except OSError:
        return False
    return state != "Z"


def test_sigint_keeps_the_written_lines_and_ends_the_tasks(tmp_path):
    out = tmp_path / "r.jsonl"
    tasks = [USAR[0], *_slow_tasks(tmp_path, 2)]
    proc = subprocess.Popen(
        [*CLI, "batch", *tasks, "--out", str(out), "--task-timeout", "60", "--json"],
        cwd=ROOT,
        stdout=subprocess.PIPE,
        stderr=subprocess.PIPE,
        text=True,
    )
    _wait_for_lines(out, 1, proc)
    time.sleep(1.0)  # the first slow task is running now
    tasks_running = _children(proc.pid)
    assert tasks_running
    proc.send_signal(signal.SIGINT)
    stdout, stderr = proc.communicate(timeout=30)
    assert proc.returncode == 130, stderr
    summary = json.loads(stdout)
    assert summary["written"] == 1 and not summary["complete"]
    assert summary["stopped"] == "interrupted by SIGINT"
    assert [x["task"] for x in _lines(out)] == [USAR[0]]
    time.sleep(0.5)
    assert not any(map(_running, tasks_running))  # the running task's process was ended


def test_a_killed_batch_resumes_where_it_stopped(tmp_path):
    out = tmp_path / "r.jsonl"
    tasks = [USAR[0], USAR[1], *_slow_tasks(tmp_path, 1)]
    proc = subprocess.Popen(
        [*CLI, "batch", *tasks, "--out", str(out), "--task-timeout", "3"],
        cwd=ROOT,
        stdout=subprocess.DEVNULL,
        stderr=subprocess.DEVNULL,
    )
    _wait_for_lines(out, 2, proc)
    proc.kill()  # no handler runs: what is in the file is all there is
    proc.wait()
    assert len(_lines(out)) == 2
    r = _batch(*tasks, "--out", str(out), "--task-timeout", "3")
    assert r.returncode == 0, r.stderr
    assert "1 task(s) written now, 2 already there" in r.stdout
    lines = _lines(out)
    assert sorted(x["task"] for x in lines) == sorted(tasks)
    slow = lines[-1]["result"]
    # its own time limit, before its first point (and on a slow machine before the robot
    # optimum): 124 and the timeout object, with the empty frontier once the optimum is known
    assert lines[-1]["exit_code"] == 124 and slow["status"] == "timeout"
    assert slow["complete"] is False and slow.get("frontier", []) == []


def test_batch_time_limit_stops_with_what_is_written(tmp_path):
    out = tmp_path / "r.jsonl"
    t0 = time.time()
    r = _batch(USAR[0], *_slow_tasks(tmp_path, 2), "--out", str(out), "--timeout", "8")
    assert time.time() - t0 < 8 + 5
    assert r.returncode == 0, r.stderr
    assert "incomplete: time limit 8.0s reached; run again to resume" in r.stdout
    assert [x["task"] for x in _lines(out)] == [USAR[0]]


def test_bad_options_are_one_line(tmp_path):
    out = str(tmp_path / "x.jsonl")
    r = _batch(USAR[0], "--out", out, "--task-timeout", "soon")
    assert r.returncode == 2 and r.stderr.strip().startswith("error: --task-timeout must be")
    r = _batch(USAR[0], "--out", out, "--scheduler", "nowhere")
    assert r.returncode == 2 and "tcp://HOST:8786" in r.stderr
    assert len(r.stderr.strip().splitlines()) == 1


def test_local_executor_reports_errors_per_call():
    def f(x):
        if x == 2:
            raise ValueError("two")
        return x * 10

    got = {o.index: (o.value, o.error) for o in completed(f, [(0,), (1,), (2,), (3,)], jobs=2)}
    assert {i: v for i, (v, e) in got.items() if e is None} == {0: 0, 1: 10, 3: 30}
    assert isinstance(got[2][1], ValueError)


# ------------------------------------------------------------------------------ Dask cluster
distributed = pytest.importorskip("distributed")


@pytest.fixture(scope="module")
def cluster():
    import dask

    with (
        dask.config.set({"distributed.scheduler.allowed-failures": 1}),
        distributed.LocalCluster(
            n_workers=2, threads_per_worker=1, processes=True, dashboard_address=None
        ) as c,
    ):
        yield c


def _exit_on(x: int) -> int:
    if x == 1:
        os._exit(1)  # the worker process dies
    return x


def test_dask_executor_survives_a_dying_worker(cluster):
    with distributed.Client(cluster) as client:
        got = {o.index: o for o in completed(_exit_on, [(0,), (1,), (2,)], scheduler=client)}
    assert got[0].value == 0 and got[2].value == 2
    assert type(got[1].error).__name__ == "KilledWorker"


def test_batch_on_a_dask_cluster(tmp_path, cluster, usar_frontiers):
    out = tmp_path / "r.jsonl"
    r = _batch(*USAR, "--out", str(out), "--scheduler", cluster.scheduler_address, "--json")
    assert r.returncode == 0, r.stderr
    assert json.loads(r.stdout)["complete"] is True
    for x in _lines(out):
        assert _points(x["result"]) == _points(usar_frontiers[x["task"]])


def test_a_worker_killed_mid_batch_loses_nothing(tmp_path, cluster):
    out = tmp_path / "r.jsonl"
    tasks = [*USAR, *_slow_tasks(tmp_path, 2)]
    proc = subprocess.Popen(
        [*CLI, "batch", *tasks, "--out", str(out), "--task-timeout", "4"]
        + ["--scheduler", cluster.scheduler_address],
        cwd=ROOT,
        stdout=subprocess.PIPE,
        stderr=subprocess.PIPE,
        text=True,
    )
    _wait_for_lines(out, 3, proc)
    before = out.read_text()
    victim = next(iter(cluster.workers.values()))
    os.kill(victim.process.pid, signal.SIGKILL)  # a worker dies while slow tasks run
    stdout, stderr = proc.communicate(timeout=120)
    text = out.read_text()
    assert text.startswith(before)  # nothing written before was lost
    done = [x["task"] for x in _lines(out)]
    assert len(done) == len(set(done))
    failed = set(tasks) - set(done)
    # a task on the dead worker is retried elsewhere, or reported and left for the next run
    assert proc.returncode == (4 if failed else 0), stderr
    for t in failed:
        assert f"error: {t}: not run to the end" in stderr
    r = _batch(*tasks, "--out", str(out), "--task-timeout", "4")
    assert r.returncode == 0 and sorted(x["task"] for x in _lines(out)) == sorted(tasks)


def test_bench_runs_on_the_cluster(tmp_path, cluster):
    r = subprocess.run(
        [
            *CLI,
            "bench",
            "--suite",
            "smoke",
            "--out",
            str(tmp_path / "b"),
            "--no-progress",
            "--scheduler",
            cluster.scheduler_address,
        ],
        cwd=ROOT,
        capture_output=True,
        text=True,
        timeout=300,
    )
    assert r.returncode == 0, r.stderr
    records = json.loads((tmp_path / "b" / "results.json").read_text())["records"]
    assert {x["engine"] for x in records} == {"astar", "sat"}
    assert all(x["status"] == "ok" for x in records)


def test_a_results_file_that_cannot_be_opened_is_an_output_error(tmp_path, monkeypatch):
    """``batch --out`` into a place no file can be made in: exit 74's error, no traceback."""
    import builtins
    import errno

    from mega_sat.cli.batch import ResultsFile
    from mega_sat.output import OutputError

    real_open = builtins.open

    def refuse(path, *a, **k):
        if str(path).endswith("r.jsonl"):
            raise OSError(errno.EROFS, os.strerror(errno.EROFS), str(path))
        return real_open(path, *a, **k)

    monkeypatch.setattr(builtins, "open", refuse)
    with pytest.raises(OutputError, match="r.jsonl: cannot write file: Read-only file system"):
        ResultsFile(tmp_path / "r.jsonl", [], restart=False)


def test_a_last_line_without_its_newline_is_not_glued_to_the_next(tmp_path):
    """A results file whose last line is whole but lacks "\\n" (an editor, ``head``): the
    next result was appended onto it, two objects on one line, and the file could no longer
    be resumed (found by an output sweep)."""
    from mega_sat.cli.batch import ResultsFile

    lines = ['{"task": "a"}', '{"task": "b"}']
    out = tmp_path / "r.jsonl"
    out.write_text("\n".join(lines))  # no final newline
    f = ResultsFile(out, lines, restart=False)
    f.append({"task": "c"})
    f.close()
    got = out.read_text().splitlines()
    assert [json.loads(line)["task"] for line in got] == ["a", "b", "c"]
