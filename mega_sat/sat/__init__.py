"""SAT: the sequential encoding of a model family and the OPT and JOINT oracles built on it."""
