"""Regenerate (or check) the command outputs embedded in the Markdown docs.

A block to keep current looks like this in any ``.md`` file::

    <!-- run: mega-sat solve --task domains/usar-fetch/p1 --alpha 0.1 -->
    ```console
    $ mega-sat solve --task domains/usar-fetch/p1 --alpha 0.1
    ...output...
    ```

A table generated from the code sits between ``<!-- table: NAME -->`` and
``<!-- /table -->``; ``NAME`` is one of :data:`TABLES` (``options``: the knobs of
``mega_sat.options.Options``).

``python docs/sync.py`` re-runs every such command from the repository root and rewrites each
block whose output changed beyond its timings (blocks marked ``<!-- run (slow): ... -->`` only with ``--slow``: they take minutes); ``python docs/sync.py --check`` fails if any block differs from a fresh run (timings,
memory and paths under /tmp are masked), so documented output cannot silently rot.
"""

from __future__ import annotations

import argparse
import os
import re
import shlex
import subprocess
import sys
from concurrent.futures import ThreadPoolExecutor
from pathlib import Path

ROOT = Path(__file__).resolve().parent.parent
BLOCK = re.compile(
    r"(<!-- run(?P<slow> \(slow\))?: (?P<cmd>.+?) -->\n)```console\n(?P<body>.*?)```\n", re.S
)
MASKS = [
    (re.compile(r"\d+\.\d+s\b"), "<T>s"),
    (re.compile(r'"time_s": [0-9.e-]+'), '"time_s": <T>'),
    (re.compile(r'"(\w*time\w*)": [0-9.e-]+'), r'"\1": <T>'),
]
TABLE = re.compile(r"(<!-- table: (?P<name>[\w-]+) -->\n)(?P<body>.*?)(<!-- /table -->\n)", re.S)
TABLES = {"options": "from mega_sat.options import markdown_table; print(markdown_table(), end='')"}
_CLI = "import sys; sys.argv[0] = 'mega-sat'; from mega_sat.cli.commands import main; main()"
DEFAULT_FILES = ["README.md", "docs/*.md", "domains/*/README.md"]


def mask(text: str) -> str:
    for rx, rep in MASKS:
        text = rx.sub(rep, text)
    return text


def run_command(cmd: str) -> str:
    """Run ``cmd`` from the repository root; ``mega-sat`` and ``python`` mean the current
    interpreter (so the venv need not be on PATH)."""
    argv = shlex.split(cmd)
    if argv[0] == "mega-sat":
        # not ``-m mega_sat.cli.commands``: click would then print "python -m mega_sat.cli.commands" in usage lines
        argv = [sys.executable, "-c", _CLI, *argv[1:]]
    elif argv[0] in ("python", "python3"):
        argv = [sys.executable, *argv[1:]]  # the same interpreter, even if no venv is active
    env = dict(os.environ, COLUMNS="100")
    res = subprocess.run(argv, cwd=ROOT, capture_output=True, text=True, env=env, timeout=600)
    out = res.stdout + res.stderr
    if res.returncode not in (0, 1):
        out += f"[exit code {res.returncode}]\n"
    return out


def render(cmd: str) -> str:
    return f"$ {cmd}\n{run_command(cmd)}"


def files(patterns: list[str]) -> list[Path]:
    out: list[Path] = []
    for p in patterns:
        out += sorted(ROOT.glob(p))
    return out


def sync(path: Path, check: bool, slow: bool = False) -> list[str]:
    """Rewrite (or check) one file; returns the commands whose output differs."""
    text = path.read_text()
    stale: list[str] = []

    def repl(m: re.Match) -> str:
        cmd = m.group("cmd").strip()
        if m.group("slow") and not slow:
            return m.group(0)  # long-running: only regenerated (and checked) with --slow
        fresh = render(cmd)
        if mask(fresh) == mask(m.group("body")):
            return m.group(0)  # only timings differ: keep the block, so diffs show real changes
        stale.append(cmd)
        return f"{m.group(1)}```console\n{fresh}```\n"

    def table(m: re.Match) -> str:
        name = m.group("name")
        code = TABLES[name]
        res = subprocess.run(
            [sys.executable, "-c", code], cwd=ROOT, capture_output=True, text=True, check=True
        )
        if res.stdout == m.group("body"):
            return m.group(0)
        stale.append(f"table {name}")
        return f"{m.group(1)}{res.stdout}{m.group(4)}"

    new = TABLE.sub(table, BLOCK.sub(repl, text))
    if not check and new != text:
        path.write_text(new)
    return stale


_SHARED = re.compile(r"/tmp/[\w.-]+|\bexp\.dat\b|\bfinal_plan\.sol\b")


def _lanes(targets: list[Path], n: int) -> list[list[Path]]:
    """The files in ``n`` lanes run side by side: files whose commands name a common output
    (a /tmp path, the working directory's exp.dat) share a lane, in the order given, so no
    two commands write one file at once; lanes are balanced by their number of blocks."""
    cmds = {f: [m.group("cmd") for m in BLOCK.finditer(f.read_text())] for f in targets}
    groups: list[tuple[set[str], list[Path]]] = []
    for f in targets:
        outs = {o for c in cmds[f] for o in _SHARED.findall(c)}
        joined = [g for g in groups if g[0] & outs]
        merged = (outs.union(*(g[0] for g in joined)), [p for g in joined for p in g[1]] + [f])
        groups = [g for g in groups if g not in joined] + [merged]
    lanes: list[list[Path]] = [[] for _ in range(n)]
    load = [0] * n
    for _, fs in sorted(groups, key=lambda g: -sum(len(cmds[f]) for f in g[1])):
        k = load.index(min(load))
        lanes[k] += sorted(fs, key=targets.index)
        load[k] += sum(len(cmds[f]) for f in fs)
    return [lane for lane in lanes if lane]


def main() -> int:
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--check", action="store_true", help="Fail on stale blocks; write nothing.")
    ap.add_argument(
        "--slow",
        action="store_true",
        help="Also run blocks marked '<!-- run (slow): ... -->' (minutes each).",
    )
    ap.add_argument("files", nargs="*", help="Markdown files (default: README, docs, domains).")
    args = ap.parse_args()
    targets = [Path(f).resolve() for f in args.files] or files(DEFAULT_FILES)
    with ThreadPoolExecutor(max_workers=2) as ex:  # the commands are processes: 2 cores
        lanes = list(
            ex.map(
                lambda lane: [(f, sync(f, args.check, args.slow)) for f in lane],
                _lanes(targets, 2),
            )
        )
    done = dict(pair for lane in lanes for pair in lane)
    bad = 0
    for f in targets:
        for cmd in done[f]:
            bad += 1
            print(f"{f.relative_to(ROOT)}: {'stale' if args.check else 'updated'}: {cmd}")
    return 1 if (args.check and bad) else 0


if __name__ == "__main__":
    sys.exit(main())
