"""What both benchmark commands share (``mega-sat bench`` in :mod:`mega_sat.bench.harness`,
``mega-sat bench-calls`` in :mod:`mega_sat.bench.oracle_calls`).

* the worker side of a measurement: :func:`write_json`, :func:`failure_record`,
  :func:`peak_rss_mb`;
* the parent side: :func:`run_worker` runs ``python -m <module> _run ...`` in its own process
  group, so a time limit really stops it (Fast Downward included), and :func:`dispatch` is the
  ``__main__`` of such a module;
* the output folder: :func:`output_files`, :func:`previous_results` (re-runs keep the other
  records), :func:`write_csv`, :func:`errors_section`, :func:`machine_info`;
* the command line: :data:`domains_option`, :data:`fresh_option`, :func:`echo_files`.
"""

from __future__ import annotations

import contextlib
import csv
import datetime as _dt
import json
import os
import platform
import signal
import subprocess
import sys
import tempfile
import time
from collections.abc import Callable, Iterable, Sequence
from dataclasses import dataclass
from pathlib import Path
from typing import Any

import click

# --------------------------------------------------------------------------- worker (child)


def peak_rss_mb() -> tuple[float, float]:
    """Peak resident memory (MB) of this process and of its largest child."""
    import resource

    self_kb = resource.getrusage(resource.RUSAGE_SELF).ru_maxrss
    child_kb = resource.getrusage(resource.RUSAGE_CHILDREN).ru_maxrss
    return round(self_kb / 1024, 1), round(child_kb / 1024, 1)


def write_json(path: str, data: dict[str, Any]) -> None:
    """Write ``data`` to ``path`` through a temporary file, so a reader (the parent, after a
    kill) never sees half a record."""
    tmp = path + ".tmp"
    Path(tmp).write_text(json.dumps(data, indent=1, default=str))
    os.replace(tmp, path)


def failure_record(e: Exception) -> dict[str, Any]:
    """The record of a worker whose measurement raised ``e`` (call it in the ``except``)."""
    import traceback

    return {
        "status": "error",
        "error": f"{type(e).__name__}: {e}",
        "traceback": traceback.format_exc(limit=8),
    }


# --------------------------------------------------------------------------- parent side


def _vm_hwm_mb(pid: int) -> float | None:
    try:
        for line in Path(f"/proc/{pid}/status").read_text().splitlines():
            if line.startswith("VmHWM:"):
                return round(int(line.split()[1]) / 1024, 1)
    except (OSError, ValueError, IndexError):
        return None
    return None


@dataclass(frozen=True)
class WorkerResult:
    """What one worker process left behind (:func:`run_worker`)."""

    rec: dict[str, Any]  # the JSON it wrote to ``--out``; {} if none
    killed: bool  # killed at the hard limit
    seconds: float
    peak_mb: float  # largest VmHWM seen; 0.0 unless watched
    exit_error: str  # "worker exited <code>: <stderr tail>"


def run_worker(
    module: str,
    args: Sequence[str],
    hard_limit: float,
    *,
    prefix: str = "mega-bench-",
    watch_memory: bool = False,
    collect: Callable[[str, dict[str, Any]], None] | None = None,
) -> WorkerResult:
    """Run ``python -m <module> _run <args> --out FILE`` in its own session and a temporary
    folder; kill its process group at ``hard_limit`` seconds.  ``watch_memory`` polls its
    VmHWM every 0.05 s; ``collect(FILE, rec)`` runs before the folder is removed."""
    with tempfile.TemporaryDirectory(prefix=prefix) as tmp:
        out = os.path.join(tmp, "result.json")
        err_path = os.path.join(tmp, "stderr.txt")
        cmd = [sys.executable, "-m", module, "_run", *args, "--out", out]
        t0 = time.perf_counter()
        peak = 0.0
        killed = False
        with open(err_path, "w") as err:
            proc = subprocess.Popen(
                cmd, stdout=subprocess.DEVNULL, stderr=err, start_new_session=True
            )
            try:
                if not watch_memory:
                    try:
                        proc.wait(timeout=hard_limit)
                    except subprocess.TimeoutExpired:
                        killed = True
                while watch_memory and proc.poll() is None:
                    hwm = _vm_hwm_mb(proc.pid)
                    if hwm is not None:
                        peak = max(peak, hwm)
                    if time.perf_counter() - t0 > hard_limit:
                        killed = True
                        break
                    time.sleep(0.05)
            finally:
                # time limit, or the harness itself interrupted: never leave the group behind
                if proc.poll() is None:
                    with contextlib.suppress(ProcessLookupError):
                        os.killpg(proc.pid, signal.SIGKILL)
                    proc.wait()
        elapsed = time.perf_counter() - t0
        rec: dict[str, Any] = {}
        if Path(out).is_file():
            rec = json.loads(Path(out).read_text())
        if collect is not None:
            collect(out, rec)
        tail = Path(err_path).read_text()[-2000:]
        return WorkerResult(rec, killed, elapsed, peak, f"worker exited {proc.returncode}: {tail}")


def dispatch(
    argv: list[str] | None, worker: click.Command, command: click.Command, prog: str
) -> None:
    """``python -m <prog> _run ...`` runs the hidden worker, anything else the command."""
    argv = sys.argv[1:] if argv is None else argv
    if argv[:1] == ["_run"]:
        worker.main(argv[1:], prog_name=f"{prog} _run")
    else:
        command.main(argv, prog_name=prog)


# --------------------------------------------------------------------------- the output folder


def problem_key(p: str) -> tuple:
    """Sort key of a problem name: ``p2`` before ``p10``."""
    digits = "".join(c for c in p if c.isdigit())
    return (int(digits) if digits else 0, p)


def machine_info() -> dict[str, Any]:
    """Where the numbers were measured (they only compare within one machine)."""
    from importlib import metadata

    from mega_sat.planners.fast_downward import fd_available

    cpu = platform.processor() or "unknown"
    try:
        for line in Path("/proc/cpuinfo").read_text().splitlines():
            if line.startswith("model name"):
                cpu = line.split(":", 1)[1].strip()
                break
    except OSError:
        pass
    ram_gb = None
    try:
        for line in Path("/proc/meminfo").read_text().splitlines():
            if line.startswith("MemTotal:"):
                ram_gb = round(int(line.split()[1]) / 1024 / 1024, 1)
    except OSError:
        pass

    def ver(name: str) -> str | None:
        try:
            return metadata.version(name)
        except metadata.PackageNotFoundError:
            return None

    return {
        "cpu": cpu,
        "cores": os.cpu_count(),
        "ram_gb": ram_gb,
        "python": platform.python_version(),
        "platform": platform.platform(),
        "packages": {
            n: ver(n)
            for n in ("mega-sat", "python-sat", "PuLP", "up_fast_downward", "click", "numpy")
        },
        "fast_downward": fd_available(),
        "date": _dt.datetime.now().astimezone().isoformat(timespec="seconds"),
    }


def run_machine_info(jobs: int, last_run: dict[str, Any]) -> dict[str, Any]:
    """:func:`machine_info` plus how the last run was made."""
    machine = machine_info()
    machine["jobs"] = jobs
    machine["last_run"] = last_run
    return machine


def output_files(out_dir: Path) -> dict[str, Path]:
    """``results.json``, ``results.csv`` and ``table.md`` in ``out_dir`` (created)."""
    out_dir.mkdir(parents=True, exist_ok=True)
    return {
        "json": out_dir / "results.json",
        "csv": out_dir / "results.csv",
        "md": out_dir / "table.md",
    }


def previous_results(out_dir: Path, fresh: bool) -> dict[str, Any]:
    """The earlier ``results.json`` in ``out_dir``; {} if ``fresh``, absent or unreadable."""
    pj = out_dir / "results.json"
    if pj.is_file() and not fresh:
        with contextlib.suppress(OSError, json.JSONDecodeError):
            return json.loads(pj.read_text())
    return {}


def write_csv(path: Path, rows: Sequence[dict[str, Any]], fields: Sequence[str]) -> None:
    """``rows`` as CSV with the columns ``fields`` (missing and ``None`` cells empty)."""
    with path.open("w", newline="") as f:
        w = csv.DictWriter(f, fieldnames=list(fields), extrasaction="ignore")
        w.writeheader()
        for r in rows:
            w.writerow({k: ("" if r.get(k) is None else r.get(k)) for k in fields})


def errors_section(
    records: Iterable[dict[str, Any]], name: Callable[[dict[str, Any]], str]
) -> list[str]:
    """``## Errors``: one line per record with status ``error`` (none: no section)."""
    errors = [r for r in records if r.get("status") == "error"]
    if not errors:
        return []
    lines = [f"- {name(r)}: {str(r.get('error', ''))[:300]}" for r in errors]
    return ["## Errors", "", *lines, ""]


# --------------------------------------------------------------------------- the command line

domains_option = click.option(
    "--domains", "domains_dir", type=click.Path(), default="domains", show_default=True
)
fresh_option = click.option("--fresh", is_flag=True, help="Discard earlier records in --out.")


def echo_files(files: dict[str, Path], t0: float) -> None:
    """The written files, then the wall time since ``t0``."""
    for name, p in files.items():
        click.echo(f"{name}: {p}")
    click.echo(f"wall time {time.perf_counter() - t0:.1f}s")


__all__ = [
    "WorkerResult",
    "dispatch",
    "domains_option",
    "echo_files",
    "errors_section",
    "failure_record",
    "fresh_option",
    "machine_info",
    "output_files",
    "peak_rss_mb",
    "previous_results",
    "problem_key",
    "run_machine_info",
    "run_worker",
    "write_csv",
    "write_json",
]
