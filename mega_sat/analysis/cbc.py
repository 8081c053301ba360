"""CBC through PuLP, leaving nothing behind: no CBC process, no temporary files.

CBC stopped by its time limit may write "Integer infeasible" into its solution file, which
PuLP reports as ``LpStatusInfeasible``: a claim of infeasibility is taken as a proof only when
the solve ended before the time limit could have stopped it (CBC counts elapsed time, and its
clock starts after ours), else the status becomes ``LpStatusNotSolved``.

PuLP runs CBC as a child process (``subprocess.Popen`` then ``wait()``) on ``*-pulp.mps`` and
``*-pulp.sol`` files in a shared temporary folder, and removes them only when CBC returns
normally.  When an interrupt or the run's time limit unwinds through ``wait()``, CBC would run
on as an orphan and its files would stay.  Here each solve gets a private temporary folder,
removed in ``finally``, and any CBC child still working on files in that folder is killed on
the way out (found through ``/proc``: PuLP does not hand out its ``Popen``; elsewhere than
Linux only the folder is removed).
"""

from __future__ import annotations

import contextlib
import os
import signal
import tempfile
import time
import warnings
from pathlib import Path


def solve_cbc(prob, *, time_limit: float | None = None, **options) -> int:
    """``prob.solve(PULP_CBC_CMD(msg=False, timeLimit=time_limit, **options))``; returns PuLP's
    status."""
    import pulp

    with warnings.catch_warnings():
        # PuLP 3.x announces API changes for 4.0 on every call; the calls below work in both
        warnings.simplefilter("ignore", DeprecationWarning)
        cmd = getattr(pulp, "PULP_CBC_CMD", None) or pulp.COIN_CMD
        solver = cmd(
            msg=False, timeLimit=time_limit, timeMode="elapsed", keepFiles=False, **options
        )
        with tempfile.TemporaryDirectory(prefix="mega-sat-cbc-") as tmp:
            solver.tmpDir = tmp
            t0 = time.perf_counter()
            try:
                status = prob.solve(solver)
            except BaseException:
                kill_children_using(tmp)
                raise
    if (
        status == pulp.LpStatusInfeasible
        and time_limit is not None
        and not time.perf_counter() - t0 < time_limit  # nan too: no proof
    ):
        prob.status = status = pulp.LpStatusNotSolved  # perhaps cut short: no proof
    return status


def kill_children_using(path: str) -> list[int]:
    """SIGKILL every child process of this process whose command line mentions ``path``, and
    reap it; returns their ids (empty where ``/proc`` is not available)."""
    me = os.getpid()
    killed = []
    try:
        entries = os.listdir("/proc")
    except OSError:
        return killed
    for entry in entries:
        if not entry.isdigit():
            continue
        pid = int(entry)
        try:
            stat = Path(f"/proc/{pid}/stat").read_text()
            ppid = int(stat.rsplit(")", 1)[1].split()[1])
            if ppid != me or path not in Path(f"/proc/{pid}/cmdline").read_bytes().decode(
                errors="replace"
            ):
                continue
        except (OSError, ValueError, IndexError):
            continue
        with contextlib.suppress(ProcessLookupError):
            os.kill(pid, signal.SIGKILL)
        with contextlib.suppress(ChildProcessError):
            os.waitpid(pid, 0)
        killed.append(pid)
    return killed
