"""Lifted models: STRIPS schemas with costs, the model difference Delta, the two-model task."""

from mega_sat.model.lifted import (
    Atom,
    CostTerm,
    Model,
    PlanStep,
    Schema,
    atom_pddl,
    atom_str,
    step_str,
)

__all__ = ["Atom", "CostTerm", "Model", "PlanStep", "Schema", "atom_pddl", "atom_str", "step_str"]
