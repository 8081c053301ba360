"""Analyses of a ground family that are not search: relaxations, h^2, invariants, abstractions,
operator-counting bounds."""
