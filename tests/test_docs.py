"""Documented command output is generated, and must match what the commands print today."""

from __future__ import annotations

import subprocess
import sys
from pathlib import Path

import pytest

from mega_sat.planners.fast_downward import fd_available
from mega_sat.planners.val import val_available

ROOT = Path(__file__).resolve().parent.parent


@pytest.mark.skipif(
    not (fd_available() and val_available()),
    reason="docs are generated with the fd and val extras installed",
)
def test_embedded_outputs_are_current():
    res = subprocess.run(
        [sys.executable, str(ROOT / "docs" / "sync.py"), "--check"],
        cwd=ROOT,
        capture_output=True,
        text=True,
        timeout=900,
    )
    assert res.returncode == 0, "stale docs (run python docs/sync.py):\n" + res.stdout + res.stderr
