"""bench/README.md, "Run-level limits": time ``ground(task)`` on the 8-parameter regression task
of tests/test_signature.py (a robot-only schema with 8 typed parameters over 20 objects of 5
types).  Run from the repository root: ``python bench/ground_eight.py [RUNS]``."""

import sys
import tempfile
import time
from pathlib import Path

sys.path.insert(0, str(Path(__file__).resolve().parents[1] / "tests"))

from test_signature import _load_dir, _write_eight_parameter_task  # noqa: E402

from mega_sat.ground.grounding import ground  # noqa: E402

runs = int(sys.argv[1]) if len(sys.argv) > 1 else 5
with tempfile.TemporaryDirectory() as tmp:
    task = _load_dir(_write_eight_parameter_task(Path(tmp) / "tpp8", per_type=4))
    import numpy  # noqa: F401  - imported once, outside the timed runs, as in a long run

    for _ in range(runs):
        t, c = time.perf_counter(), time.process_time()
        fam = ground(task)
        print(
            f"ground: {time.perf_counter() - t:.2f} s wall, {time.process_time() - c:.2f} s CPU; "
            f"{len(fam.actions)} ground actions, {len(fam.atoms)} atoms"
        )
