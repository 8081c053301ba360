"""The fuzz and property suites' budget: small and seeded by default, large with ``--fuzz-long``.

Not a test file.  ``pytest --fuzz-long`` (see ``conftest.py``) or the environment variable
``MEGA_SAT_FUZZ_LONG=1`` selects the long budget for release checks: the fuzz tests of the
readers and the CLI run :data:`EXAMPLES` unseeded cases, and the property tests against an
oracle (brute force, explicit search) :data:`ORACLE_SCALE` times their own number, unseeded,
so every long run draws new random tasks.
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

ORACLE_SCALE = 10 if LONG else 1
"""How many times its own number of cases a property test runs (:func:`oracle_settings`)."""


def oracle_settings(max_examples: int, **overrides) -> settings:
    """Settings of a property test checked against an oracle: ``max_examples`` seeded cases
    (reproducible), or :data:`ORACLE_SCALE` times as many unseeded ones with the long budget;
    no deadline and no health checks unless ``overrides`` says otherwise."""
    kw = {
        "deadline": None,
        "derandomize": not LONG,
        "suppress_health_check": list(HealthCheck),
        **overrides,
    }
    return settings(max_examples=max_examples * ORACLE_SCALE, **kw)
