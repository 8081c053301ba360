"""mega-sat: exact, fast MEGA (balancing explicability and explanations) with SAT and ILP.

The pipeline, one subpackage a stage: ``pddl`` (read and write models) → ``model`` (lifted
models, the model difference) → ``ground`` (one ground family for every ``human + E``) →
``analysis`` (relaxations, h^2, invariants, lower bounds) → ``search`` (explicit-state planning)
| ``sat`` (encodings and the OPT/JOINT oracles) → ``planners`` (one optimal call per model) →
``engines`` (the hitting-set loop, the A* baseline, MCE, MME, verification) → ``api`` → ``cli``.
"""

from mega_sat import _moved

__version__ = "0.1.0"

_moved.install()
