"""The files of a ``mega-sat bench`` output folder: ``results.json``, ``results.csv``,
``table.md`` (:func:`mega_sat.bench.tables.render_markdown`) and, for sweeps, ``sweep.csv`` and
``sweep-<domain>.png``."""

from __future__ import annotations

import json
from collections.abc import Sequence
from pathlib import Path
from typing import Any

from mega_sat.bench.common import output_files, problem_key, write_csv
from mega_sat.bench.tables import disagreements, render_markdown

# the columns of results.csv, in order (results.json has every key of a record)
CSV_FIELDS = (
    "suite",
    "domain",
    "problem",
    "delta",
    "engine",
    "planner",
    "status",
    "error",
    "time_limit_s",
    "seconds",
    "engine_time_s",
    "ground_s",
    "load_s",
    "process_s",
    "delta_size",
    "ground_atoms",
    "ground_actions",
    "E_ropt",
    "E_alpha1",
    "robot_cost_alpha1",
    "objective_alpha1",
    "robot_optimal_cost",
    "frontier_points",
    "exact",
    "complete",
    "next_size_lower_bound",
    "peak_rss_mb",
    "peak_rss_children_mb",
    "nodes_expanded",
    "planner_calls",
    "planner_time_s",
    "iterations",
    "opt_calls",
    "joint_calls",
    "learned",
    "learned_literals",
    "robot_call_builtin_s",
    "robot_call_sat_s",
    "robot_call_fd_s",
    "ratio_sat_vs_builtin_call",
    "ratio_sat_vs_sat_call",
    "ratio_sat_vs_fd_call",
    "task_dir",
)
SWEEP_FIELDS = (
    "domain",
    "problem",
    "alpha",
    "E",
    "explicability_cost",
    "robot_cost",
    "robot_optimal_cost",
    "objective",
    "exact",
)


def plot_sweeps(rows: Sequence[dict[str, Any]], out_dir: Path) -> list[Path]:
    """One PNG per domain, one subplot per problem: |E| and explicability cost vs alpha."""
    import matplotlib

    matplotlib.use("Agg")
    import matplotlib.pyplot as plt

    written = []
    for dom in sorted({r["domain"] for r in rows}):
        probs = sorted({r["problem"] for r in rows if r["domain"] == dom}, key=problem_key)
        fig, axes = plt.subplots(1, len(probs), figsize=(4.2 * len(probs), 3.4), squeeze=False)
        for ax, prob in zip(axes[0], probs, strict=True):
            rs = sorted(
                (r for r in rows if r["domain"] == dom and r["problem"] == prob),
                key=lambda r: r["alpha"],
            )
            xs = [r["alpha"] for r in rs]
            ax.plot(xs, [r["E"] for r in rs], "o-", label="explanation cost |E|")
            ax.plot(xs, [r["explicability_cost"] for r in rs], "s--", label="explicability cost")
            # linear up to 0.1: 0, 0.05 and 0.1 get as much room as a factor 3 above it, so
            # the labels "0.05" and "0.1" do not overlap (they do with linthresh=0.05)
            ax.set_xscale("symlog", linthresh=0.1, linscale=1.0)
            ticks = [t for t in (0, 0.05, 0.1, 0.3, 1, 3, 10) if t <= max(xs)]
            ax.set_xticks(ticks, [f"{t:g}" for t in ticks])
            ax.yaxis.get_major_locator().set_params(integer=True)
            ax.set_xlabel("alpha")
            ax.set_title(f"{dom} {prob}")
            ax.grid(True, alpha=0.3)
        axes[0][0].set_ylabel("cost")
        axes[0][-1].legend(fontsize=8)
        fig.tight_layout()
        p = out_dir / f"sweep-{dom}.png"
        fig.savefig(p, dpi=120)
        plt.close(fig)
        written.append(p)
    return written


def write_outputs(
    out_dir: Path,
    records: Sequence[dict[str, Any]],
    machine: dict[str, Any],
    sweep_rows: Sequence[dict[str, Any]],
    generation: Sequence[dict[str, Any]] = (),
) -> dict[str, Path]:
    """``results.json`` (machine, records, sweep rows, generation log, disagreements),
    ``results.csv``, ``table.md`` and, with sweep rows, ``sweep.csv`` and one
    ``sweep-<domain>.png`` per domain; returns the written files by name."""
    files = output_files(out_dir)
    data = {
        "machine": machine,
        "records": list(records),
        "sweep": list(sweep_rows),
        "generation": list(generation),
        "disagreements": disagreements(records),
    }
    files["json"].write_text(json.dumps(data, indent=1, default=str))
    write_csv(files["csv"], records, CSV_FIELDS)
    files["md"].write_text(render_markdown(records, machine, sweep_rows, generation))
    if sweep_rows:
        files["sweep_csv"] = out_dir / "sweep.csv"
        write_csv(files["sweep_csv"], sweep_rows, SWEEP_FIELDS)
        for p in plot_sweeps(sweep_rows, out_dir):
            files[p.stem] = p
    return files


__all__ = ["CSV_FIELDS", "SWEEP_FIELDS", "plot_sweeps", "write_outputs"]
