"""pytest options of the suite: ``--fuzz-long`` runs the fuzz and property tests with the long budget.

The interrupt tests send SIGINT to the processes they start, and to this one.  A shell starts
a background job (``bash .ci/run &``, ``nohup``) with SIGINT ignored, and an ignored signal
stays ignored across ``exec``: the processes under test would never see it.  So the suite
gives itself Python's own SIGINT handler back; its children then start with the default.
"""

from __future__ import annotations

import os
import signal

if signal.getsignal(signal.SIGINT) is signal.SIG_IGN:
    signal.signal(signal.SIGINT, signal.default_int_handler)


def pytest_addoption(parser):
    parser.addoption(
        "--fuzz-long",
        action="store_true",
        help="fuzz and property tests with the long budget (same as MEGA_SAT_FUZZ_LONG=1)",
    )


def pytest_configure(config):
    if config.getoption("--fuzz-long"):
        os.environ["MEGA_SAT_FUZZ_LONG"] = "1"
