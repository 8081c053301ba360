"""The ``mega-sat`` command: the ``main`` group with every command registered.

The commands live by what they do: :mod:`~mega_sat.cli.model_commands` (models and plans),
:mod:`~mega_sat.cli.engine_commands` (solve, frontier, explain, verify) and
:mod:`~mega_sat.cli.tool_commands` (generators, batch, mmp, benchmarks); what they share
(the run, its limits, signals and exit codes) is :mod:`~mega_sat.cli.app`.
"""

from mega_sat.cli import engine_commands, model_commands, tool_commands
from mega_sat.cli.app import main

__all__ = ["main"]
_COMMANDS = (model_commands, engine_commands, tool_commands)  # imported for registration

if __name__ == "__main__":  # pragma: no cover
    main()
