"""mega-sat: exact, fast MEGA (balancing explicability and explanations) with SAT and ILP."""

__version__ = "0.1.0"
