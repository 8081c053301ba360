#!/bin/bash
# `mega-sat ARGS...` with the mega_sat of source tree TREE (e.g. an older commit's worktree)
# and this repository's .venv. Run it from a directory without a mega_sat folder, so that the
# current directory does not shadow TREE.
# usage: bench/mega-sat-from.sh TREE ARGS...
set -u
tree=$(realpath "$1"); shift
py=$(dirname "$(realpath "$0")")/../.venv/bin/python
PYTHONPATH=$tree exec "$py" -W ignore -c "import sys; sys.argv[0] = 'mega-sat'
try:
    from mega_sat.cli.commands import main
except ImportError:  # trees from before the cli package was split
    from mega_sat.cli import main
main()" "$@"
