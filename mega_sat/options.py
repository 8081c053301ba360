"""Every tuning knob of mega-sat, with its default and what it trades, in one place.

A knob changes how fast an answer comes, never which answer: frontiers are the same for every
setting (a budget that runs out falls back to a complete method, or the result says it is not
proven).  ``MegaSolver(options=Options(...))`` and ``mega-sat ... --option key=value`` set them.
"""

from __future__ import annotations

import dataclasses
import math
import numbers
from collections.abc import Iterable
from dataclasses import dataclass, field, fields

from mega_sat.errors import UsageError


@dataclass(frozen=True)
class Options:
    """The knobs.  Each field's ``metadata["doc"]`` is the sentence docs/cli.md lists;
    ``metadata["zero"]`` marks a number that may be 0 (its doc says what 0 means)."""

    horizon_cap: int = field(
        default=200,
        metadata={"doc": "largest SAT horizon; past it OPT/JOINT fall back to explicit search"},
    )
    core_calls: int = field(
        default=64, metadata={"doc": "SAT calls spent shrinking one JOINT core before it is used"}
    )
    core_conflict_budget: int = field(
        default=5000, metadata={"doc": "conflicts per core-shrinking SAT call"}
    )
    dominance_conflict_budget: int = field(
        default=3000,
        metadata={"doc": "conflicts spent proving a JOINT core by human-cost dominance"},
    )
    fallback_node_limit: int = field(
        default=200_000,
        metadata={"doc": "nodes of the explicit search that answers past the horizon cap"},
    )
    opt_reachability_steps: int = field(
        default=32,
        metadata={
            "doc": "once SAT OPT finds no plan of this many steps (and knows none), it "
            "tries to prove the model unsolvable, by exhausting its reachable states and by "
            "an inductive invariant (IC3) in turns"
        },
    )
    opt_reachability_nodes: int = field(
        default=2_000_000,
        metadata={"doc": "states that reachability check of SAT OPT may expand"},
    )
    opt_side_proof_states: int = field(
        default=50_000,
        metadata={
            "doc": "reachable states of the first turn once no plan fits "
            "opt_reachability_steps steps; each turn doubles it (up to "
            "opt_reachability_nodes) and IC3 gets its share"
        },
    )
    opt_side_proof_ic3_per_1000: int = field(
        default=25,
        metadata={
            "doc": "SAT calls of IC3 per 1000 reachable states in those turns (about the "
            "same time on the shipped domains)"
        },
    )
    opt_side_proof_min_share: float = field(
        default=0.0625,
        metadata={
            "doc": "least share of its rate that a side proof of SAT OPT keeps on a task "
            "where it rarely proves a model unsolvable: the probe alongside SAT and IC3 in "
            "the turns run at min(1, 2 (proofs + 1) / (calls + 1)) of their rate, not below "
            "this"
        },
    )
    opt_reachability_conflicts: int = field(
        default=10_000,
        metadata={
            "doc": "conflicts SAT OPT spends looking for a first plan before it starts "
            "exhausting the model's reachable states alongside (a proof it has none)"
        },
    )
    opt_reachability_probe_rate: int = field(
        default=40,
        metadata={
            "doc": "reachable states that check may expand per conflict SAT has spent (at "
            "most opt_reachability_nodes)"
        },
    )
    opt_invariant_probe_rate: int = field(
        default=1,
        metadata={
            "zero": True,
            "doc": "SAT calls of the inductive-invariant proof (IC3) that SAT OPT may spend "
            "per conflict of its search for a first plan, alongside the reachability check "
            "(0: IC3 only past the horizon cap)",
        },
    )
    pdr_queries: int = field(
        default=500_000,
        metadata={
            "doc": "SAT calls of the inductive-invariant proof (IC3) that OPT tries once no "
            "plan fits the horizon cap and the explicit search gave up"
        },
    )
    ic3_seed_lemmas: int = field(
        default=20_000,
        metadata={
            "zero": True,
            "doc": "clauses of the latest IC3 invariants kept to seed IC3 on later models "
            "(each checked before use; 0: IC3 starts from nothing)",
        },
    )
    solve_chunk: int = field(
        default=5000,
        metadata={"doc": "conflicts per SAT solve chunk (the deadline is checked between chunks)"},
    )
    first_chunk: int = field(
        default=1000,
        metadata={"doc": "conflicts of the first chunk; chunk i gets min(solve_chunk, i * this)"},
    )
    extra_node_limit: int = field(
        default=10_000,
        metadata={"doc": "nodes of the search for the robot's extra cost above N * c_min"},
    )
    opt_probe_budget: int = field(
        default=3000, metadata={"doc": "conflicts of OPT's first cost probe at a horizon"}
    )
    opt_extra_node_limit: int = field(
        default=20_000,
        metadata={"doc": "nodes of OPT's search for the extra cost above N * c_min"},
    )
    counting_time_limit: float = field(
        default=2.0,
        metadata={"doc": "seconds per operator-counting integer program (a lower bound)"},
    )
    step_first: bool = field(
        default=True,
        metadata={"doc": "OPT asks for a step bound before its cost bounds"},
    )
    partial_order: bool = field(
        default=False,
        metadata={
            "doc": "partial-order reduction in the SAT encodings (adjacent independent actions "
            "in index order); off: its role variables and clauses grow every step"
        },
    )
    plan_below_robot_conflicts: int = field(
        default=10_000,
        metadata={
            "doc": "conflicts of the SAT call that looks for a human plan cheaper than the "
            "robot optimum, which rules a model out without OPT when no action costs the "
            "human less than the robot (0: never)",
            "zero": True,
        },
    )
    plan_below_robot_nodes: int = field(
        default=3000,
        metadata={
            "doc": "expansions of the search pruned at the robot optimum that looks for that "
            "cheaper human plan before the SAT call (its plan is the model's optimum, an "
            "exhausted search proves there is none); halves after each miss, doubles after "
            "each hit (0: SAT only)",
            "zero": True,
        },
    )
    plan_below_robot_with_fd: bool = field(
        default=True,
        metadata={
            "doc": "look for that cheaper human plan also when Fast Downward answers OPT "
            "(off: an FD call answers instead; on small tasks that is faster, bench/README.md)"
        },
    )
    counterexample_loop_updates: int = field(
        default=11,
        metadata={
            "doc": "the fewest updates a task needs for the sat engine to compute its frontier "
            "by the counterexample loop (one JOINT formula with the explanation free, "
            "encodings/counterexamples.md) instead of the hitting-set loop, unless "
            "--hitting-set ilp or --joint search asks for that loop's parts (0: never)",
            "zero": True,
        },
    )
    counterexample_plan_conflicts: int = field(
        default=2000,
        metadata={
            "doc": "conflicts of the one SAT call the counterexample loop makes for a plan "
            "cheaper than its candidate's (or than the coverage check's bound) before it asks "
            "OPT for the model's optimum (0: OPT at once)",
            "zero": True,
        },
    )
    plan_below_robot_max_updates: int = field(
        default=10,
        metadata={
            "doc": "the most updates a task may have for that search to run: with few, the "
            "SAT call's encoding is most of the work; with many, its plans (the model's "
            "optimum, where SAT returns any plan below the robot's) lead the loop longer "
            "ways (bench/README.md; 0: never)",
            "zero": True,
        },
    )
    dominance_trial_conflicts: int = field(
        default=300,
        metadata={"doc": "conflicts of the short SAT call that first tries a dominance-core trial"},
    )
    counting_trials: int = field(
        default=4,
        metadata={
            "doc": "operator-counting bounds tried on a task before they are switched off, "
            "unless one beat the cheaper bounds"
        },
    )
    search_first_hits: int = field(
        default=4,
        metadata={
            "doc": "OPT's lowered-cost searches that run before they must keep shortening "
            "the horizon to go on"
        },
    )
    search_first_steps: int = field(
        default=2,
        metadata={
            "doc": "horizon steps each lowered-cost search must save on average to keep "
            "running when OPT already has a plan"
        },
    )
    search_first_misses: int = field(
        default=2,
        metadata={
            "doc": "lowered-cost searches that may run out of nodes before they stop, "
            "once they miss more often than they hit"
        },
    )
    joint_core_min_nodes: int = field(
        default=500,
        metadata={"doc": "least node limit of the explicit JOINT search that confirms a core"},
    )
    unsolvable_core_states: int = field(
        default=1_000_000,
        metadata={
            "doc": "states the may-reachability proof that shrinks an unsolvable model's "
            "exclusion may hold; past that only the relaxed and pair proofs shrink it"
        },
    )
    unsolvable_core_work: int = field(
        default=300_000,
        metadata={
            "doc": "states that proof may add to the model's own reachable states for one "
            "unsolvable model, over all the updates it tries (a count, so the exclusion is "
            "the same on any machine)"
        },
    )
    unsolvable_core_trial_states: int = field(
        default=50_000,
        metadata={
            "doc": "states one update's trial in that proof may add, or "
            "unsolvable_core_trial_growth times as many as it holds already, whichever is "
            "more (an update whose freedom multiplies them stays in the exclusion)"
        },
    )
    unsolvable_core_trial_growth: int = field(
        default=3,
        metadata={
            "doc": "how many times the states it holds one trial of that proof may add "
            "(see unsolvable_core_trial_states)"
        },
    )
    unsolvable_core_ic3_queries: int = field(
        default=5000,
        metadata={
            "zero": True,
            "doc": "SAT calls of IC3 on the abstraction of an update's trial in that proof, "
            "where its states ran past their limits and the pair proof failed (0: off); "
            "each run starts from the lemmas of the core's last invariant. Smaller "
            "exclusions where the states outgrow the limits (bench/README.md)",
        },
    )
    unsolvable_core_ic3_misses: int = field(
        default=5,
        metadata={
            "zero": True,
            "doc": "runs of that IC3 in a row that reach their limit without a proof (runs "
            "that find a plan do not count) after which a run stops trying it (0: never "
            "stops)",
        },
    )
    joint_sat_conflicts: int = field(
        default=50_000,
        metadata={
            "zero": True,
            "doc": "SAT conflicts a JOINT call under --joint sat may take before the paired-state "
            "search answers it instead (0: no limit)",
        },
    )
    joint_sat_action_steps: int = field(
        default=12_000,
        metadata={
            "zero": True,
            "doc": "ground actions times the horizon of a JOINT call (--joint sat or "
            "portfolio) past which the paired-state search answers it without SAT, and of "
            "the SAT call for a plan below the robot optimum past which it is not made: the "
            "encoding has some 30 to 50 clauses per action and step, and on a million "
            "clauses each conflict is dear (a count, so the choice is the same on any "
            "machine; 0: no limit)",
        },
    )
    joint_fd: bool = field(
        default=True,
        metadata={
            "doc": "with Fast Downward installed, a JOINT call the paired-state search has not "
            "settled within joint_fd_after_work goes to FD, on the product of the robot task "
            "and the model with cost M * human cost + robot cost (exact when the human bound "
            "is the model's proven optimum, encodings/hitting-set.md); off: the search alone"
        },
    )
    joint_fd_after_work: int = field(
        default=20_000,
        metadata={
            "zero": True,
            "doc": "work of the paired-state search (expansions times ground actions) before "
            "FD takes the call: small searches end sooner than an FD run starts, and their "
            "cores take one search where FD's take a run per trial (0: FD at once)",
        },
    )
    joint_fd_lmcut: bool = field(
        default=False,
        metadata={
            "doc": "FD's search on that product task: A* with LM-cut; off: blind A*, which "
            "was faster on every task measured (bench/README.md)"
        },
    )
    joint_fd_core_trials: int = field(
        default=12,
        metadata={
            "zero": True,
            "doc": "FD runs that may shrink the core of a 'no joint plan' answered by FD, one "
            "deletion trial each on an abstraction (0: the core is every update)",
        },
    )
    portfolio_conflicts: int = field(
        default=5000,
        metadata={"doc": "first SAT conflict budget of a JOINT call under --joint portfolio"},
    )
    portfolio_min_conflicts: int = field(
        default=1000,
        metadata={"doc": "the portfolio's budget halves, down to this, while search wins"},
    )
    portfolio_max_conflicts: int = field(
        default=160_000,
        metadata={"doc": "the portfolio's budget doubles, up to this, while SAT wins"},
    )
    joint_core_factor: float = field(
        default=2.0,
        metadata={"doc": "node factor of the explicit JOINT search that confirms a core"},
    )
    quick_nodes: int = field(
        default=5000,
        metadata={"doc": "nodes of the blind search tried first in the sat engine's OPT"},
    )
    fd_alongside_quick_nodes: int = field(
        default=2048,
        metadata={
            "zero": True,
            "doc": "with Fast Downward as OPT's planner: expansions of that blind search after "
            "which FD starts on the same model alongside it, on the other core (ended if the "
            "search answers; the answer is the same either way; 0: FD only once the search "
            "has given up)",
        },
    )
    fd_first_candidate_ahead: bool = field(
        default=True,
        metadata={
            "doc": "with Fast Downward as OPT's planner: when FD starts on the robot's model, "
            "start it on the human's model as it is (the loop's first candidate) alongside, "
            "on the other core (ended once the loop has moved on without it; answers "
            "unchanged)"
        },
    )
    unsolvable_probe_states: int = field(
        default=50_000,
        metadata={
            "doc": "states of the breadth-first reachability that tries to prove a candidate "
            "model unsolvable before any plan search, once some candidate had no plan; halves "
            "after each model it does not prove unsolvable, doubles after each it does (0: off)",
            "zero": True,
        },
    )
    race_nodes_per_conflict: int = field(
        default=5,
        metadata={
            "doc": "the OPT portfolio's exchange rate: states the search may expand per "
            "conflict SAT spends (the referee counts work, not seconds, so runs repeat)"
        },
    )
    race_clauses_per_conflict: int = field(
        default=50,
        metadata={
            "doc": "clauses added to the OPT encoding that count as one conflict of work in "
            "that exchange (growing the encoding is most of SAT's time on some tasks)"
        },
    )
    race_lmcut_per_action: float = field(
        default=0.5,
        metadata={
            "doc": "the work of one LM-cut evaluation in the portfolio's explicit side, in "
            "uniform-cost expansions per action of the task (it takes turns with uniform-cost "
            "search by work)"
        },
    )
    race_side_vector_weight: float = field(
        default=0.1,
        metadata={
            "doc": "the work, in the race's explicit-search units, of one vectorised expansion "
            "(past the first 2048) of the lowered-cost search SAT OPT runs first, which counts "
            "on SAT's side of the exchange (a pure-Python expansion counts 1; a vectorised one "
            "takes about a tenth of its time)"
        },
    )
    race_search_vector_work: float = field(
        default=0.0,
        metadata={
            "zero": True,
            "doc": "the work, in the race's units, of one vectorised expansion (past the first "
            "2048) of the explicit side's uniform-cost search per action and 64-atom word of "
            "state it tests, at most 1 per expansion, in its turns with LM-cut and in the work "
            "it reports to the referee; 0: 1 per expansion, as a pure-Python one.  With "
            "about 0.0005 a unit of the search takes about as long as one of SAT's on the "
            "shipped domains (bench/README.md)",
        },
    )
    race_search_relevant_part: bool = field(
        default=False,
        metadata={
            "doc": "the explicit side searches the relevant part of each model (the same "
            "optimum, plans that run in the model, often far fewer states; other plans lead "
            "the loop other ways, bench/README.md)"
        },
    )
    race_states_per_lp_action: int = field(
        default=20,
        metadata={
            "doc": "the work of one operator-counting integer program on SAT's side of that "
            "exchange, in search states per action of the program"
        },
    )
    race_first_conflicts: int = field(
        default=1000,
        metadata={
            "doc": "conflicts of SAT's first turn when the portfolio takes turns in one "
            "process (doubling each round)"
        },
    )
    race_processes: bool = field(
        default=True,
        metadata={
            "doc": "the OPT portfolio runs its search in a forked process beside SAT "
            "(both cores; POSIX only); false: the two take turns in one process"
        },
    )
    fd_from_actions: int = field(
        default=400,
        metadata={
            "doc": "ground actions from which the sat engine's default OPT planner is Fast "
            "Downward instead of the portfolio, when FD is installed and costs are positive: "
            "SAT's encoding grows with actions times steps, and on such families the race "
            "can leave a model undecided that FD's astar(lmcut()) settles in seconds "
            "(bench/README.md; 0: never)",
            "zero": True,
        },
    )
    race_fd_after_work: int = field(
        default=300_000,
        metadata={
            "doc": "work of the forked OPT race's SAT side (in the referee's search states) "
            "after which, with neither side done, a plan of the model in hand (SAT's, or the "
            "greedy search's below) and Fast Downward installed, the race stops and FD's "
            "astar(lmcut()) proves the optimum; a point fixed by work, so runs repeat (0: "
            "never). The default lies past every race of the paper grid, so only a proof far "
            "longer than the rest is handed over: FD's other plans would take the loop other "
            "ways; smaller values hand over sooner (bench/README.md)",
            "zero": True,
        },
    )
    race_fd_greedy_evaluations: int = field(
        default=10_000,
        metadata={
            "doc": "at that point, when SAT holds no plan of the model: h_add evaluations of "
            "the greedy best-first search that looks for one; a plan it finds also hands the "
            "call to FD, which proves solvable models' optima fast but exhausts unsolvable "
            "ones (0: SAT's plan only)",
            "zero": True,
        },
    )
    joint_pair_proofs: bool = field(
        default=True,
        metadata={
            "doc": "the sat engine proves by h^2 on the product of the robot and the human "
            "models which updates every solution needs (unit clauses) and which JOINT cores "
            "hold at any cost bound (clauses without the plan's support)"
        },
    )
    monotone_cores: bool = field(
        default=True,
        metadata={
            "doc": "drop from every core the updates whose other value only removes plans, "
            "and from a plan's support those whose other value only adds plans "
            '(encodings/hitting-set.md, "Monotone updates")'
        },
    )
    joint_before_opt: bool = field(
        default=True,
        metadata={
            "doc": "the sat engine asks JOINT at the cost of a remembered plan that runs in "
            "the candidate model before proving its optimum; a core there needs no OPT"
        },
    )
    joint_before_opt_conflicts: int = field(
        default=2000,
        metadata={
            "doc": "conflicts per SAT call of that early JOINT; past them the candidate gets "
            "OPT and JOINT at the proven optimum as usual"
        },
    )
    blind_nodes: int = field(
        default=300_000,
        metadata={
            "doc": "nodes of the built-in planner's blind search before it switches to LM-cut"
        },
    )
    builtin_fd_after_blind: bool = field(
        default=True,
        metadata={
            "doc": "the built-in planner hands a call its blind search did not settle to Fast "
            "Downward's A* with LM-cut (when installed) instead of its own LM-cut, which is "
            "pure Python"
        },
    )
    superset_check_limit: int = field(
        default=64,
        metadata={
            "doc": "most strict supersets of an MME that verification re-plans, else skipped"
        },
    )

    def __post_init__(self) -> None:
        """The checks ``--option`` makes, for ``Options(...)`` in code too: a knob changes how
        fast an answer comes, never which, and a value such as ``nan`` (a time limit no call
        can reach or exceed) or a string would break that deep inside a run."""
        for f in fields(self):
            v = getattr(self, f.name)
            if f.type == "bool":
                if not isinstance(v, bool):
                    raise UsageError(f"option {f.name}={v!r}: expected True or False")
                continue
            # 0 stays open to code (tests switch a step off, or on at once, with it); the
            # CLI's --option refuses it where the knob's doc gives 0 no meaning
            kind = numbers.Integral if f.type == "int" else numbers.Real
            if not isinstance(v, kind) or isinstance(v, bool) or not math.isfinite(v) or v < 0:
                what = "an integer" if f.type == "int" else "a finite number"
                raise UsageError(f"option {f.name}={v!r}: expected {what} >= 0")

    @classmethod
    def docs(cls) -> list[tuple[str, str, str]]:
        """``(name, default, sentence)`` for every knob, in declaration order."""
        return [(f.name, repr(f.default), f.metadata["doc"]) for f in fields(cls)]

    def with_pairs(self, pairs: Iterable[str]) -> Options:
        """A copy with ``key=value`` settings applied (the CLI's repeatable ``--option``)."""
        types = {f.name: f.type for f in fields(self)}
        zero_ok = {f.name for f in fields(self) if f.metadata.get("zero")}
        changes: dict[str, object] = {}
        for pair in pairs:
            key, sep, text = pair.partition("=")
            key = key.strip().replace("-", "_")
            if not sep:
                raise UsageError(f"--option {pair!r}: expected key=value")
            if key not in types:
                known = ", ".join(sorted(types))
                raise UsageError(f"--option {pair!r}: unknown option {key!r} (known: {known})")
            changes[key] = _parse(key, types[key], text.strip(), key in zero_ok)
        return dataclasses.replace(self, **changes)


def _parse(key: str, kind: str, text: str, zero_ok: bool = False) -> object:
    """The value of ``--option key=text``: a bool, or a positive number (or 0 for the knobs
    marked ``zero``)."""
    if kind == "bool":
        low = text.lower()
        if low in ("1", "true", "yes", "on"):
            return True
        if low in ("0", "false", "no", "off"):
            return False
        raise UsageError(f"--option {key}={text}: expected true or false")
    try:
        value = int(text) if kind == "int" else float(text)
    except ValueError:
        raise UsageError(f"--option {key}={text}: expected a number ({kind})") from None
    if not (value > 0 or (zero_ok and value == 0)):
        raise UsageError(f"--option {key}={text}: must be {'0 or more' if zero_ok else 'positive'}")
    return value


def markdown_table() -> str:
    """The knobs as the Markdown table of docs/cli.md ("Tuning options"), which
    ``docs/sync.py`` keeps current."""
    rows = ["| option | default | what it does |", "|---|---|---|"]
    rows += [f"| `{name}` | `{default}` | {doc} |" for name, default, doc in Options.docs()]
    return "\n".join(rows) + "\n"


DEFAULT = Options()
