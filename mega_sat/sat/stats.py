"""What the SAT oracles did, in named counters: :class:`OracleStats`.

The engine copies :meth:`OracleStats.as_dict` into its result's ``stats`` (keys ``sat_*``), so
the JSON of ``mega-sat frontier`` shows where the oracles' time went.
"""

from __future__ import annotations

from dataclasses import dataclass, fields


@dataclass
class OracleStats:
    """Counters and seconds of one :class:`mega_sat.sat.oracles.SatOracles`.

    The fields up to ``joint_horizon`` are always reported; the others are ``None`` (and left
    out of :meth:`as_dict`) until the work they count first happens, so a run's stats show
    which mechanisms it used at all, in the order the run first used them.
    """

    opt_calls: int = 0
    joint_calls: int = 0
    solver_calls: int = 0
    solve_time_s: float = 0.0
    opt_time_s: float = 0.0
    joint_time_s: float = 0.0
    core_min_calls: int = 0
    encode_time_s: float = 0.0
    max_call_time_s: float = 0.0
    cost_bits: int = 0
    """How cost bounds are encoded: 0 = unary units, else bits per step (binary)."""
    grow_time_s: float = 0.0
    opt_vars: int = 0
    opt_clauses: int = 0
    opt_horizon: int = 0
    joint_vars: int = 0
    joint_clauses: int = 0
    joint_horizon: int = 0
    facts_time_s: float | None = None
    counting_calls: int | None = None
    counting_time_s: float | None = None
    search_time_s: float | None = None
    search_hits: int | None = None
    search_misses: int | None = None
    search_steps_saved: int | None = None
    """Horizon steps the lowered-cost searches' hits removed, in all."""
    step_queries: int | None = None
    step_bounds: int | None = None
    opt_by_search: int | None = None
    opt_by_reachability: int | None = None
    opt_by_invariant: int | None = None
    joint_hint_used: int | None = None
    joint_by_dominance: int | None = None
    joint_by_human_dominance: int | None = None
    joint_core_reused: int | None = None
    joint_by_search: int | None = None
    plan_within_calls: int | None = None
    plan_within_found: int | None = None
    plan_within_time_s: float | None = None

    def __setattr__(self, name: str, value: object) -> None:
        if value is not None and name in _OPTIONAL and getattr(self, name, None) is None:
            self.__dict__.setdefault("_first_used", []).append(name)
        super().__setattr__(name, value)

    def as_dict(self) -> dict[str, int | float]:
        """``{"sat_<field>": value}`` for every field that is set: the fixed ones in
        declaration order, then the others in the order they were first used."""
        names = [n for n in _FIXED] + self.__dict__.get("_first_used", [])
        return {f"sat_{n}": getattr(self, n) for n in names}


_FIXED = tuple(f.name for f in fields(OracleStats) if f.default is not None)
_OPTIONAL = frozenset(f.name for f in fields(OracleStats) if f.default is None)


def bump(value: int | None, by: int = 1) -> int:
    """``value + by`` for a counter that is ``None`` before its first use."""
    return by if value is None else value + by


def add_seconds(value: float | None, seconds: float) -> float:
    """``value + seconds`` for a timing that is ``None`` before its first use."""
    return seconds if value is None else value + seconds
