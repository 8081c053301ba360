"""Small frictions of the user's view: library error texts, one alpha wording, messages of
runs without points, the install instructions."""

from __future__ import annotations

import json
from pathlib import Path

import pytest
from click.testing import CliRunner

from mega_sat import api
from mega_sat.cli.commands import main
from mega_sat.errors import PDDLError, UsageError

ROOT = Path(__file__).resolve().parent.parent
USAR = ROOT / "domains" / "usar-fetch" / "p1"


def run(*args: str):
    return CliRunner().invoke(main, [str(a) for a in args])


def test_library_errors_carry_no_cli_prefix():
    assert str(UsageError("bad value")) == "bad value"
    e = PDDLError("unknown section", path="d.pddl", where="line 3")
    assert str(e) == "d.pddl: line 3: unknown section"
    with pytest.raises(UsageError) as info:
        api.load_task_dir(ROOT / "no-such-folder")
    assert not str(info.value).startswith("error")


def test_cli_prints_the_prefix_once():
    res = run("diff", "--task", ROOT / "no-such-folder")
    assert res.exit_code == 2
    assert res.output.splitlines() == [
        f"error: {ROOT / 'no-such-folder'}: task directory not found"
    ]
    js = json.loads(run("diff", "--task", ROOT / "no-such-folder", "--json").stdout)
    assert js["error"] == f"{ROOT / 'no-such-folder'}: task directory not found"


@pytest.mark.parametrize("alpha", ["-1", "abc", "nan", "inf", ""])
def test_one_alpha_wording_in_cli_and_library(alpha):
    want = f"alpha must be a finite number >= 0, got {alpha!r}"
    res = run("solve", "--task", USAR, "--alpha", alpha)
    assert res.exit_code == 2 and res.output == f"error: {want}\n"
    task = api.load_task_dir(USAR)
    with pytest.raises(UsageError) as info:
        api.solve(task, alpha)
    assert str(info.value) == want
    fr = api.frontier(task)
    from mega_sat.results import choose

    with pytest.raises(UsageError) as info:
        choose(fr, alpha)
    assert str(info.value) == want


def test_numeric_alpha_in_the_library_is_shown_as_given():
    task = api.load_task_dir(USAR)
    with pytest.raises(UsageError, match=r"^alpha must be a finite number >= 0, got -1$"):
        api.solve(task, -1)


def test_bench_with_nothing_to_run_is_one_error_line(tmp_path):
    out = tmp_path / "res"
    domains = ROOT / "domains"
    res = run("bench", "--suite", "smoke", "--domains", domains, "--only", "nope", "--out", out)
    assert res.exit_code == 2
    (line,) = res.output.splitlines()
    assert line.startswith(
        f"error: nothing to run: suite 'smoke' has no instance in {domains} matching --only nope"
    )
    assert not out.exists()
    empty = tmp_path / "empty"
    empty.mkdir()
    res = run("bench", "--suite", "paper", "--domains", empty, "--out", out)
    assert res.exit_code == 2 and "nothing to run" in res.output and not out.exists()


def test_a_stop_before_the_first_point_words_its_bound_for_every_solution():
    from mega_sat.engines.progress import Progress

    pr = Progress()
    pr.start("sat", ("u1", "u2"))
    pr.robot_optimal_cost, pr.lower_bound = 4, 2
    fr = pr.frontier("time limit 1.0s reached: frontier incomplete")
    assert fr.notes[-1] == (
        "time limit 1.0s reached: frontier incomplete; no point found yet; "
        "any solution needs |E| >= 2"
    )
    assert "last point" not in " ".join(fr.notes)


class _ExpiredAfterStart:
    """A deadline with no clock limit that reports itself expired: the engine computes the
    robot optimum, then stops before its first candidate."""

    at = None
    seconds = 1.0
    limited = False

    def expired(self) -> bool:
        return True

    def check(self) -> None:
        pass

    def remaining(self) -> None:
        return None

    def cap(self, seconds):
        return seconds


def test_sat_engine_stopped_before_any_point_says_no_point():
    from mega_sat.engines.sat_loop import sat_frontier
    from mega_sat.ground.grounding import ground

    task = api.load_task_dir(USAR)
    fr = sat_frontier(task, ground(task), deadline=_ExpiredAfterStart())
    assert not fr.points and not fr.complete and fr.next_size_lower_bound == 0
    # a bound of 0 holds for every solution: the note does not offer it as news
    assert fr.notes[-1].endswith("frontier incomplete; no point found yet")
    assert "last point" not in " ".join(fr.notes) and ">= 0" not in " ".join(fr.notes)


def test_a_vacuous_bound_is_left_out_of_the_notes():
    from mega_sat.engines.progress import lower_bound_note

    assert lower_bound_note(0, True) == ""
    assert lower_bound_note(0, False) == "no point found yet"
    assert lower_bound_note(3, True).endswith("needs |E| >= 3")
    assert (
        lower_bound_note(2, False, weighted=True)
        == "no point found yet; any solution needs cost(E) >= 2"
    )


def test_api_docs_name_every_exported_function():
    text = (ROOT / "docs" / "api.md").read_text()
    missing = [
        n for n in api.__all__ if n.islower() and f"{n}(" not in text and f"api.{n}" not in text
    ]
    assert not missing, missing


def test_api_docs_describe_resolve_task_dir_as_the_dict_it_returns():
    from mega_sat.pddl.loading import resolve_task_dir

    text = (ROOT / "docs" / "api.md").read_text()
    (para,) = [p for p in text.split("\n\n") if p.startswith("`load_task_dir` loads")]
    got = resolve_task_dir(USAR)
    assert isinstance(got, dict) and "a dict" in para
    assert all(f"`{k}`" in para for k in got), para
    assert "returns the four paths" not in text


@pytest.mark.parametrize("doc", ["README.md", "docs/index.md"])
def test_install_docs_say_to_activate_the_venv(doc):
    assert "source .venv/bin/activate" in (ROOT / doc).read_text()


def test_readme_keeps_the_two_commands_ci_runs():
    text = (ROOT / "README.md").read_text()
    assert (
        "python3 -m venv .venv && .venv/bin/pip install -e '.[all]' && .venv/bin/mega-sat "
        "solve --task domains/usar-fetch/p1 --alpha 0.1"
    ) in text
    assert "\n.venv/bin/python -m pytest\n" in text


def test_sweep_figure_tick_labels_do_not_overlap(tmp_path, monkeypatch):
    import matplotlib

    matplotlib.use("Agg")
    import matplotlib.pyplot as plt

    from mega_sat.bench.harness import ALPHA_GRID, plot_sweeps

    figs = []
    monkeypatch.setattr(plt, "close", figs.append)
    rows = [
        {"domain": "d", "problem": p, "alpha": a, "E": 1, "explicability_cost": 2}
        for p in ("p1", "p2", "p3")
        for a in ALPHA_GRID
    ]
    plot_sweeps(rows, tmp_path)
    (fig,) = figs
    fig.set_dpi(120)  # as saved
    fig.canvas.draw()
    renderer = fig.canvas.get_renderer()
    for ax in fig.axes:
        boxes = [t.get_window_extent(renderer) for t in ax.get_xticklabels() if t.get_text()]
        assert len(boxes) == 7
        for a, b in zip(boxes, boxes[1:], strict=False):
            # at least 0.1 inch between two labels ("0.05" and "0.1" were 0.03 inch apart)
            assert b.x0 - a.x1 >= 12, [t.get_text() for t in ax.get_xticklabels()]


def _frontier(pairs, c_robot):
    """Points ``(|E|, robot cost)``, or ``(|E|, robot cost, cost(E))`` with update costs."""
    from mega_sat.results import Frontier, FrontierPoint

    pts = tuple(
        FrontierPoint(
            tuple(f"u{k}" for k in range(e)), frozenset(range(e)), (), c, c, *(w or (None,))
        )
        for e, c, *w in pairs
    )
    costs = (1,) * 9 if all(len(p) == 2 for p in pairs) else None
    weighted = {} if costs else {"update_costs": (3,) * 9}
    return Frontier("sat", c_robot, tuple(f"u{k}" for k in range(9)), pts, True, True, **weighted)


@pytest.mark.parametrize(
    ("pairs", "want"),
    [
        # blocksworld p2: |E| 0/1/2 at robot cost 12/8/6
        ([(0, 12), (1, 8), (2, 6)], [(0, "1/4"), ("1/4", "1/2"), ("1/2", None)]),
        # the middle point lies above the line of its neighbours: never chosen
        ([(0, 10), (1, 9), (3, 4)], [(0, "1/2"), None, ("1/2", None)]),
        # on that line: a tie at alpha = 1/2 for all three, won by the cheapest
        ([(0, 4), (1, 2), (2, 0)], [(0, "1/2"), None, ("1/2", None)]),
        ([(3, 4)], [(0, None)]),
        # update costs: the cuts follow cost(E) (1 and 6 here), not |E| (1 and 2)
        ([(1, 12, 1), (2, 6, 6)], [(0, "5/6"), ("5/6", None)]),
    ],
)
def test_alpha_ranges_match_choose(pairs, want):
    from fractions import Fraction

    from mega_sat.results import alpha_ranges, choose

    fr = _frontier(pairs, pairs[-1][1])
    got = alpha_ranges(fr)
    assert got == [
        None if w is None else (Fraction(w[0]), None if w[1] is None else Fraction(w[1]))
        for w in want
    ]
    for alpha in [0, 0.1, 0.25, 0.3, 0.5, 0.75, 1, 2.5, 10]:
        chosen = choose(fr, alpha).chosen
        a = Fraction(repr(float(alpha)))
        (k,) = [
            k
            for k, r in enumerate(got)
            if r is not None and r[0] <= a and (r[1] is None or a < r[1])
        ]
        assert fr.points[k] == chosen, (alpha, k)


BLOCKS = ROOT / "domains" / "blocksworld" / "p2"


@pytest.mark.parametrize(
    ("suffix", "magic"), [(".png", b"\x89PNG"), (".svg", b"<?xml"), (".pdf", b"%PDF")]
)
def test_frontier_plot_by_suffix_and_never_overwritten_without_force(tmp_path, suffix, magic):
    target = tmp_path / f"frontier{suffix}"
    res = run("frontier", "--task", BLOCKS, "--plot", target)
    assert res.exit_code == 0, res.output
    assert f"; wrote {target}" in res.stderr
    assert target.read_bytes().startswith(magic)
    before = target.read_bytes()
    res = run("frontier", "--task", BLOCKS, "--plot", target)
    assert res.exit_code == 2 and res.stdout == ""  # refused before solving
    assert res.stderr == f"error: {target}: file exists (use --force to replace it)\n"
    assert target.read_bytes() == before
    res = run("frontier", "--task", BLOCKS, "--plot", target, "--force")
    assert res.exit_code == 0 and target.read_bytes().startswith(magic)


def test_frontier_plot_svg_shows_alpha_ranges_and_robot_optimum(tmp_path):
    target = tmp_path / "f.svg"
    assert run("frontier", "--task", BLOCKS, "--plot", target).exit_code == 0
    svg = target.read_text()
    # text is drawn as glyph paths; the labels are kept in comments
    for text in ("0 ≤ α &lt; 0.25", "0.25 ≤ α &lt; 0.5", "α ≥ 0.5", "robot optimum"):
        assert text in svg, text


def test_plot_labels_a_point_no_alpha_picks():
    from mega_sat.cli.plotting import range_label
    from mega_sat.results import alpha_ranges

    fr = _frontier([(0, 10), (1, 9), (3, 4)], 4)
    assert [range_label(r) for r in alpha_ranges(fr)] == [
        "0 ≤ α < 0.5",
        "never chosen",
        "α ≥ 0.5",
    ]
    thirds = alpha_ranges(_frontier([(0, 4), (1, 1), (2, 0)], 0))
    assert [range_label(r) for r in thirds] == ["0 ≤ α < 1/3", "1/3 ≤ α < 1", "α ≥ 1"]


@pytest.mark.parametrize("name", ["f.jpg", "f", "f.png.txt"])
def test_frontier_plot_unsupported_suffix_is_one_line_before_solving(tmp_path, name):
    res = run("frontier", "--task", BLOCKS, "--plot", tmp_path / name)
    assert res.exit_code == 2 and res.stdout == ""
    (line,) = res.stderr.splitlines()
    assert line.startswith(f"error: --plot {tmp_path / name}: unsupported file type")
    assert line.endswith("(use .png, .svg or .pdf)")


def test_frontier_plot_without_matplotlib_is_one_line(tmp_path, monkeypatch):
    import sys

    monkeypatch.setitem(sys.modules, "matplotlib", None)  # import matplotlib fails
    res = run("frontier", "--task", BLOCKS, "--plot", tmp_path / "f.png")
    assert res.exit_code == 2 and res.stdout == ""
    assert res.stderr == (
        "error: --plot needs matplotlib, which is not installed (pip install 'mega-sat[bench]')\n"
    )
    assert not (tmp_path / "f.png").exists()


def test_plot_of_an_incomplete_frontier_says_so(tmp_path):
    import dataclasses

    from mega_sat.cli.plotting import frontier_figure

    fr = api.frontier(api.load_task_dir(BLOCKS))
    cut = dataclasses.replace(fr, points=fr.points[:2], complete=False, exact=False)
    assert "incomplete" not in frontier_figure(fr, "svg").decode()
    assert "(incomplete: α ranges among the points found so far)" in (
        frontier_figure(cut, "svg").decode()
    )


def test_plot_is_skipped_after_a_stop(tmp_path):
    from mega_sat.cli.app import _Run
    from mega_sat.cli.engine_commands import _plot
    from mega_sat.deadline import TimeLimitReached

    run = _Run(as_json=False)
    run.stopped = TimeLimitReached(1.0, forced=True)
    fr = api.frontier(api.load_task_dir(BLOCKS))
    assert _plot(run, fr, tmp_path / "f.png", False, "t") == ["--plot skipped: the run was stopped"]
    assert not (tmp_path / "f.png").exists()


def _error_line(res) -> str:
    lines = [ln for ln in res.stderr.splitlines() if ln.strip()]
    assert res.exit_code == 2 and len(lines) == 1 and "Traceback" not in res.stderr, res.output
    return lines[0]


def test_errors_name_the_file_they_are_about(tmp_path):
    """A plan file `explain` cannot run, and a cost term the problem does not define, are
    reported with the file's name."""
    plan = tmp_path / "fly.plan"
    plan.write_text("(fly p1 p6)\n")
    line = _error_line(run("explain", "--task", USAR, "--plan", plan))
    assert line == (
        f"error: {plan}: the plan is not executable in the robot model: "
        "step 1 (fly p1 p6): unknown action 'fly'"
    )
    domain = (ROOT / "domains/usar-fetch/robot-domain.pddl").read_text()
    domain = domain.replace(
        "(:functions (total-cost) - number)", "(:functions (total-cost) (dist ?a ?b) - number)"
    )
    domain = domain.replace(
        "(robot_at ?to) (increase (total-cost) 1)",
        "(robot_at ?to) (increase (total-cost) (dist ?from ?to))",
    )
    (tmp_path / "d.pddl").write_text(domain)
    problem = USAR / "robot-problem.pddl"
    line = _error_line(
        run("solve", "--robot-domain", tmp_path / "d.pddl", "--robot-problem", problem,
            "--human-domain", tmp_path / "d.pddl", "--alpha", "1")
    )  # fmt: skip
    # the line of the problem's :init, where the value is missing
    lines = problem.read_text().splitlines()
    init_line = next(n for n, text in enumerate(lines, 1) if "(:init" in text)
    assert line.startswith(f"error: {problem}: line {init_line}: cost function value (dist ")
    assert "is not defined: the cost of (move " in line
    assert "and :init gives it no value (add (= (dist " in line


def test_small_input_slips(tmp_path):
    """``--alpha -0`` is echoed as 0 (not -0.0); ``generate --time-budget nan`` is refused
    like ``--timeout nan``."""
    res = run("solve", "--task", USAR, "--alpha", "-0", "--json")
    assert res.exit_code == 0 and json.loads(res.stdout)["alpha"] == 0.0
    assert '"alpha": 0.0' in res.stdout
    line = _error_line(
        run("generate", "--robot-domain", ROOT / "domains/usar-fetch/robot-domain.pddl",
            "--robot-problem", USAR / "robot-problem.pddl", "--delta", "1",
            "--out", tmp_path / "g", "--time-budget", "nan")
    )  # fmt: skip
    assert line == "error: --time-budget must be a number of seconds >= 0, got nan"


def test_library_slips_are_usage_errors():
    """Wrong values given in code are one clear UsageError each, not a TypeError or an
    AttributeError from deep inside (found by an API sweep)."""
    from mega_sat.pddl.update_costs import load_update_costs

    task = api.load_task_dir(USAR)
    for alpha in (True, b"0.1", 10**400):
        with pytest.raises(UsageError, match="alpha must be a finite number >= 0"):
            api.solve(task, alpha)
    for bad in (None, 5, b"domains/usar-fetch/p1", ""):
        with pytest.raises(UsageError, match="task folder: expected a path"):
            api.load_task_dir(bad)
    with pytest.raises(UsageError, match="update costs file: expected a path"):
        load_update_costs(None)
    with pytest.raises(UsageError, match="deadline must be a mega_sat.deadline.Deadline"):
        api.MegaSolver(task, deadline=5)
    s = api.MegaSolver(task)
    with pytest.raises(UsageError, match="alpha must be"):
        s.partial_solution(-1, "stopped")  # checked before looking for points
    point = s.frontier().points[0]
    with pytest.raises(UsageError, match="unknown producer 'FD'"):
        s.verify(point, producer="FD")
    with pytest.raises(UsageError, match="use_val must be True or False"):
        s.verify(point, use_val="no")
    # api.verify hands the solver's arguments to the solver (timeout= was a TypeError)
    assert api.verify(task, point, timeout=60, hitting_set="ilp").ok


def test_a_time_limit_while_drawing_keeps_the_frontier(tmp_path, monkeypatch):
    """The limit reached inside --plot (matplotlib's import alone takes a second) once ended
    the run with exit 124 and nothing printed; the frontier is the answer, so it is printed
    (exit 0) and a note says the figure was not written (found by an output sweep)."""
    from mega_sat.cli import plotting
    from mega_sat.deadline import TimeLimitReached

    def late(*a, **k):
        raise TimeLimitReached(3.0, forced=True)

    monkeypatch.setattr(plotting, "write_plot", late)
    target = tmp_path / "f.svg"
    res = run("frontier", "--task", BLOCKS, "--plot", target, "--json")
    assert res.exit_code == 0, res.output
    d = json.loads(res.stdout)
    assert d["frontier"] and d["complete"] is False
    assert any("while drawing: --plot not written" in n for n in d["notes"])
    assert not target.exists()


def test_generate_names_a_robot_problem_without_a_plan(tmp_path):
    """The robot's problem is the file to mend, so the error names it, as ``plan`` does."""
    domain = ROOT / "domains" / "usar-fetch" / "robot-domain.pddl"
    problem = (USAR / "robot-problem.pddl").read_text()
    # a waypoint no road leads to: the robot can never be there
    problem = problem.replace("(:goal (and", "(:goal (and (robot_at p9)").replace(
        "p8 - waypoint", "p8 p9 - waypoint"
    )
    (tmp_path / "p.pddl").write_text(problem)
    res = run(
        "generate", "--robot-domain", domain, "--robot-problem", tmp_path / "p.pddl",
        "--delta", "2", "--out", tmp_path / "out",
    )  # fmt: skip
    assert res.exit_code == 3
    assert res.output.strip() == (
        f"error: {tmp_path / 'p.pddl'}: the robot problem has no plan; nothing to generate from"
    )
