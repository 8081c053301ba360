"""``frontier --plot``: the frontier as a step chart of robot cost against |E|.

Each point is labelled with the alphas for which MEGA picks it
(:func:`mega_sat.results.alpha_ranges`), so one figure answers every alpha as the frontier
does; a dashed line marks the robot optimum.  matplotlib (the ``bench`` extra) is imported only
when a figure is drawn; :func:`check_plot_target` refuses a bad request before any solving.
"""

from __future__ import annotations

import io
from fractions import Fraction
from pathlib import Path

from mega_sat.errors import UsageError
from mega_sat.output import check_target, write_file
from mega_sat.results import Frontier, alpha_ranges

FORMATS = {".png": "png", ".svg": "svg", ".pdf": "pdf"}
"""File suffixes ``--plot`` accepts and the matplotlib format each one means."""


def check_plot_target(path: str | Path, *, force: bool) -> Path:
    """The figure's path, refused now (before solving) when its suffix is not one of
    :data:`FORMATS`, matplotlib is missing, or the file exists without ``force``."""
    p = Path(path)
    if p.suffix.lower() not in FORMATS:
        raise UsageError(
            f"--plot {p}: unsupported file type '{p.suffix or p.name}' (use .png, .svg or .pdf)"
        )
    try:
        import matplotlib  # noqa: F401
    except ImportError:
        raise UsageError(
            "--plot needs matplotlib, which is not installed (pip install 'mega-sat[bench]')"
        ) from None
    return check_target(p, force=force)


def _num(x: Fraction) -> str:
    """An alpha bound as the user would type it: a decimal when it is one, else ``a/b``."""
    d = x.denominator
    while d % 2 == 0:
        d //= 2
    while d % 5 == 0:
        d //= 5
    return f"{float(x):g}" if d == 1 else f"{x.numerator}/{x.denominator}"


def range_label(r: tuple[Fraction, Fraction | None] | None) -> str:
    """``0 ≤ α < 0.25``, ``α ≥ 0.5``, or ``never chosen``."""
    if r is None:
        return "never chosen"
    lo, hi = r
    if hi is None:
        return "any α" if lo == 0 else f"α ≥ {_num(lo)}"
    return f"{_num(lo)} ≤ α < {_num(hi)}"


def frontier_figure(fr: Frontier, fmt: str, title: str = "") -> bytes:
    """The figure of ``fr`` in ``fmt`` (``png``, ``svg`` or ``pdf``) as bytes."""
    import matplotlib

    matplotlib.use("Agg")
    import matplotlib.pyplot as plt
    from matplotlib.ticker import MaxNLocator

    pts = fr.points
    weighted = fr.update_costs is not None
    xs = [p.explanation_cost for p in pts]  # cost(E) with update costs, else |E|
    ys = [p.robot_cost for p in pts]
    fig, ax = plt.subplots(figsize=(7.0, 4.4))
    try:
        most = sum(fr.update_costs) if weighted else len(fr.model_difference)
        right = max([most if fr.complete else 0, *xs, 1])
        if pts:
            # robot cost reachable with at most x updates: flat until the next point
            ax.step([*xs, right], [*ys, ys[-1]], where="post", color="C0", label="frontier")
            ax.plot(xs, ys, "o", color="C0")
        ax.axhline(
            fr.robot_optimal_cost,
            color="C3",
            linestyle="--",
            linewidth=1,
            label=f"robot optimum $C^*_R$ = {fr.robot_optimal_cost}",
        )
        for k, (p, r) in enumerate(zip(pts, alpha_ranges(fr), strict=True)):
            ax.annotate(
                f"[{k}] {'cost(E)' if weighted else '|E|'} = {p.explanation_cost}, "
                f"cost {p.robot_cost}\n{range_label(r)}",
                (p.explanation_cost, p.robot_cost),
                textcoords="offset points",
                xytext=(7, 7),
                fontsize=8.5,
                color="black" if r is not None else "gray",
            )
        ax.set_xlim(-0.4, right + 0.9)
        top = max([*ys, fr.robot_optimal_cost])
        span = max(top - fr.robot_optimal_cost, 1)
        ax.set_ylim(fr.robot_optimal_cost - 0.12 * span, top + 0.3 * span)
        ax.xaxis.set_major_locator(MaxNLocator(integer=True))
        ax.yaxis.set_major_locator(MaxNLocator(integer=True))
        ax.set_xlabel("explanation cost cost(E)" if weighted else "explanation size |E|")
        ax.set_ylabel("robot plan cost")
        # a point missed by an early stop can take over part of any range
        status = "" if fr.complete else "\n(incomplete: α ranges among the points found so far)"
        ax.set_title(f"MEGA frontier{': ' + title if title else ''}{status}", fontsize=11)
        ax.grid(True, alpha=0.3)
        ax.legend(loc="upper right", fontsize=8.5)
        fig.tight_layout()
        buf = io.BytesIO()
        fig.savefig(buf, format=fmt, dpi=120)
    finally:
        plt.close(fig)
    return buf.getvalue()


def write_plot(fr: Frontier, path: Path, *, force: bool, title: str = "") -> Path:
    """Draw ``fr`` and write it to ``path`` atomically (format from the suffix)."""
    data = frontier_figure(fr, FORMATS[path.suffix.lower()], title)
    return write_file(path, data, force=force)
