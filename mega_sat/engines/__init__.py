"""Engines: the sat hitting-set loop, the A* baseline, MCE, MME and verification."""
