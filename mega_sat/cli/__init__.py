"""The mega-sat command line (the entry point is :func:`mega_sat.cli.commands.main`)."""
