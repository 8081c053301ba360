"""The benchmark harness, used by the CLI through the engine's public interfaces."""
