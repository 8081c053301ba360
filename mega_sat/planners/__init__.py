"""Planners: one optimal planning call on one model of the family, by a chosen method."""
