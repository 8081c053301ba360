"""pytest options of the suite: ``--fuzz-long`` runs the fuzz tests with the long budget."""

from __future__ import annotations

import os


def pytest_addoption(parser):
    parser.addoption(
        "--fuzz-long",
        action="store_true",
        help="fuzz tests with the long budget (same as MEGA_SAT_FUZZ_LONG=1)",
    )


def pytest_configure(config):
    if config.getoption("--fuzz-long"):
        os.environ["MEGA_SAT_FUZZ_LONG"] = "1"
