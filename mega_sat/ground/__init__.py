"""Grounding: one ground family that stands for every model human + E, and plan simulation."""
