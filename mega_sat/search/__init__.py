"""Explicit-state search: the built-in optimal planner and the paired-state JOINT search."""
