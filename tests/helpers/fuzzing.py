"""The fuzz suites' budget: small and seeded by default, large with ``--fuzz-long``.

Not a test file.  ``pytest --fuzz-long`` (see ``conftest.py``) or the environment variable
``MEGA_SAT_FUZZ_LONG=1`` selects the long budget for release checks.
"""

from __future__ import annotations

import os

from hypothesis import HealthCheck, settings

LONG = os.environ.get("MEGA_SAT_FUZZ_LONG", "") not in ("", "0")
EXAMPLES = 2000 if LONG else 60
"""Cases per fuzz test."""

FUZZ = settings(
    max_examples=EXAMPLES,
    derandomize=not LONG,  # a fixed seed keeps the default suite reproducible
    deadline=None,
    suppress_health_check=[HealthCheck.too_slow, HealthCheck.filter_too_much],
)
"""The hypothesis settings every fuzz test uses."""
