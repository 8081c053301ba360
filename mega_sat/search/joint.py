"""Explicit-state JOINT: one plan for two tasks at once, robot cost minimal, both costs bounded.

``joint_search(robot, human, K, c)`` answers the JOINT question of the hitting-set loop by A*
over *paired* states ``(robot state, human state)``: an action is applicable when it is
applicable in both tasks (matched by the family's action index), the pair's cost is
``(robot cost, human cost)``, and a path must reach both goals with robot cost ``<= K`` and
human cost ``<= c``.  The search is ordered by robot cost plus an admissible robot heuristic and
prunes a path as soon as either cost plus its side's admissible heuristic passes its bound.
Because a pair state can be reached by paths trading one cost against the other, each pair
keeps its Pareto set of ``(robot cost, human cost)`` labels; a label is dropped only when
another label of the same pair is no worse in both costs.  The first goal label popped then
has the minimum robot cost among all joint plans within the bounds (admissible heuristic,
non-negative costs), and an exhausted queue proves that no joint plan exists within them.

``human`` may be an abstraction (:mod:`mega_sat.analysis.abstraction`); "no joint plan" then holds for
every model it over-approximates, which is how JOINT cores are proven.
"""

from __future__ import annotations

import heapq
import time

from mega_sat.analysis.abstraction import abstract_task
from mega_sat.analysis.relaxation import RelaxedTask, bits
from mega_sat.deadline import NO_DEADLINE, Deadline
from mega_sat.ground.family import GroundTask, holds
from mega_sat.options import DEFAULT, Options
from mega_sat.search.answers import JointResult
from mega_sat.status import Status

_INF = float("inf")
_DEADLINE_EVERY = 64
"""Expansions between two looks at the clock (a clock read per expansion would dominate)."""


def _searched(
    status: Status, plan=None, robot_cost=None, human_cost=None, expanded: int = 0
) -> JointResult:
    """A :class:`JointResult` of :meth:`JointSearcher.search` (no core, no selection)."""
    return JointResult(
        status, plan, robot_cost, human_cost, None, None, status.decided,
        "proven by explicit search", 0, 1, 0.0, expanded,
    )  # fmt: skip


def _masks(task: GroundTask) -> dict[int, tuple[int, int, int, int, int]]:
    """Family action index -> (pre, negpre, ~delete, add, cost) bitmasks."""
    out = {}
    for a in task.actions:
        out[a.index] = (
            sum(1 << p for p in a.pre),
            sum(1 << p for p in a.negpre),
            ~sum(1 << p for p in a.delete),
            sum(1 << p for p in a.add),
            a.cost,
        )
    return out


class JointSearcher:
    """Reusable JOINT search against one fixed robot task (its heuristic cache is shared by
    every call, since the robot side never changes within a task)."""

    def __init__(self, robot: GroundTask):
        self.robot = robot
        self._r_masks = _masks(robot)
        self._r_goal = sum(1 << p for p in robot.goal)
        self._r_init = sum(1 << p for p in robot.init)
        self._r_relaxed = RelaxedTask(robot)
        self._r_h: dict[int, float] = {}

    def robot_h(self, s: int) -> float:
        h = self._r_h.get(s)
        if h is None:
            h = self._r_h[s] = self._r_relaxed.lmcut(bits(s))
        return h

    def search(
        self,
        human: GroundTask,
        robot_bound: int | None,
        human_bound: int,
        *,
        node_limit: int | None = None,
        deadline: Deadline = NO_DEADLINE,
        heuristic_task: GroundTask | None = None,
        track: CoreTracker | None = None,
    ) -> JointResult:
        """Cheapest-robot-cost joint plan with robot cost <= ``robot_bound`` (None: no bound)
        and human cost <= ``human_bound``; see the module docstring.  ``PLAN``, ``INFEASIBLE``
        (proven: no joint plan within the bounds; no core), ``LIMIT`` (``node_limit`` reached)
        or ``TIMEOUT`` (``deadline`` passed); ``expanded`` says how many nodes it took.

        ``heuristic_task``: compute the human heuristic on this task instead (an abstraction
        of ``human``, so the pruning stays valid for every model it covers).  ``track``
        records which updates the search's decisions depended on (:class:`CoreTracker`)."""
        r_masks = self._r_masks
        r_goal = self._r_goal
        h_goal = sum(1 << p for p in human.goal)
        h_fn = RelaxedTask(heuristic_task if heuristic_task is not None else human).h_max
        h_cache: dict[int, float] = {}

        def human_h(s: int) -> float:
            v = h_cache.get(s)
            if v is None:
                v = h_cache[s] = h_fn(bits(s))
            return v

        # human successors grouped as in the built-in planner, robot masks looked up per index
        h_acts = []
        step_of = {a.index: a.step for a in human.actions}
        for a in human.actions:
            rm = r_masks.get(a.index)
            if rm is None:
                continue  # the action does not exist for the robot
            h_acts.append(
                (
                    a.index,
                    sum(1 << p for p in a.pre),
                    sum(1 << p for p in a.negpre),
                    ~sum(1 << p for p in a.delete),
                    sum(1 << p for p in a.add),
                    a.cost,
                    *rm,
                )
            )
        k_bound = _INF if robot_bound is None else robot_bound
        start = (self._r_init, sum(1 << p for p in human.init))
        hr0, hh0 = self.robot_h(start[0]), human_h(start[1])
        expanded = 0
        if hr0 > k_bound or hh0 > human_bound:
            return _searched(Status.INFEASIBLE)
        labels: dict[tuple[int, int], list[tuple[int, int]]] = {start: [(0, 0)]}
        parent: dict[tuple[int, int, int, int], tuple[tuple[int, int, int, int], int] | None] = {
            (*start, 0, 0): None
        }
        counter = 0
        heap = [(hr0, hr0, counter, 0, 0, start)]
        while heap:
            _, _, _, gr, gh, key = heapq.heappop(heap)
            if (gr, gh) not in labels[key]:
                continue  # dominated after it was queued
            sr, sh = key
            if sr & r_goal == r_goal and sh & h_goal == h_goal:
                steps = []
                node = (sr, sh, gr, gh)
                while parent[node] is not None:
                    node, j = parent[node]  # type: ignore[misc]
                    steps.append(step_of[j])
                return _searched(Status.PLAN, tuple(reversed(steps)), gr, gh, expanded)
            if node_limit is not None and expanded >= node_limit:
                return _searched(Status.LIMIT, expanded=expanded)
            if expanded % _DEADLINE_EVERY == 0 and deadline.expired():
                return _searched(Status.TIMEOUT, expanded=expanded)
            expanded += 1
            if track is not None:
                track.expanded(sr)
            for j, pre, neg, keep, add, ch, rpre, rneg, rkeep, radd, cr in h_acts:
                if sr & rpre != rpre or sr & rneg:
                    continue
                if sh & pre != pre or sh & neg:
                    if track is not None:
                        track.failed(j, sh)
                    continue
                if track is not None:
                    track.applied(j)
                gh2 = gh + ch
                gr2 = gr + cr
                if gh2 > human_bound or gr2 > k_bound:
                    continue
                th = (sh & keep) | add
                tr = (sr & rkeep) | radd
                if gh2 + human_h(th) > human_bound:
                    continue
                hr = self.robot_h(tr)
                if gr2 + hr > k_bound:
                    continue
                key2 = (tr, th)
                old = labels.get(key2)
                if old is None:
                    labels[key2] = [(gr2, gh2)]
                else:
                    if any(a <= gr2 and b <= gh2 for a, b in old):
                        continue
                    old[:] = [(a, b) for a, b in old if not (gr2 <= a and gh2 <= b)]
                    old.append((gr2, gh2))
                parent[(tr, th, gr2, gh2)] = ((sr, sh, gr, gh), j)
                counter += 1
                heapq.heappush(heap, (gr2 + hr, hr, counter, gr2, gh2, key2))
        return _searched(Status.INFEASIBLE, expanded=expanded)


class CoreTracker:
    """The updates a paired-state search in ``human + E`` (two-fact form) depended on.

    After an exhausted search, ``used`` plus the updates the human heuristic's abstraction
    fixed is a core: every ``E'`` agreeing with ``E`` on it has, from every state the search
    expanded, only transitions that ``E`` has too, with the same successors and costs, the
    same initial state and no extra goal states, so an ``E'`` joint plan within the bounds
    would have been found (argument in ``encodings/hitting-set.md``).  Recorded:

    * guarded initial-state entries, and guarded goal entries present in ``E`` (removing a
      goal could create goal states); goal entries absent in ``E`` only restrict;
    * an action absent in ``E`` whose robot side is applicable in an expanded state: its
      existence guard (adding the action could add transitions);
    * an action applicable for the robot but not for the human: the guards of its present
      preconditions that failed (dropping one could enable it); absent ones only restrict;
    * an applied action: the guards of all its effects and cost cases.
    """

    def __init__(self, family, selection: frozenset[int], robot_masks) -> None:
        n = len(family.atoms)
        sel = frozenset(selection)
        self.used: set[int] = {g[0] for _, g in family.init if g}
        self.used.update(g[0] for _, g in family.goal if g and holds(g, sel))
        self._fail: dict[int, list[tuple[int, int]]] = {}
        self._effects: dict[int, set[int]] = {}
        self._absent: list[tuple[int, int, int]] = []
        for j, a in enumerate(family.actions):
            rm = robot_masks.get(j)
            if rm is None:
                continue
            if not holds(a.exists, sel):
                self._absent.append((rm[0], rm[1], a.exists[0]))
                continue
            fail = [(1 << p, g[0]) for p, g in a.pre if g and holds(g, sel)]
            fail += [(1 << (n + p), g[0]) for p, g in a.negpre if g and holds(g, sel)]
            self._fail[j] = fail
            eff = {g[0] for _, g in a.add + a.delete if g}
            eff.update(i for guards, _ in a.cost for i, _ in guards)
            self._effects[j] = eff

    def expanded(self, sr: int) -> None:
        if self._absent:
            rest = []
            for pre, neg, i in self._absent:
                if sr & pre == pre and not sr & neg:
                    self.used.add(i)
                else:
                    rest.append((pre, neg, i))
            self._absent = rest

    def failed(self, j: int, sh: int) -> None:
        for bit, i in self._fail[j]:
            if not sh & bit:
                self.used.add(i)

    def applied(self, j: int) -> None:
        eff = self._effects.pop(j, None)
        if eff:
            self.used.update(eff)


def infeasibility_core(
    searcher: JointSearcher,
    family,
    selection: frozenset[int],
    keep: frozenset[int],
    robot_bound: int | None,
    human_bound: int,
    *,
    node_limit: int,
    deadline: Deadline = NO_DEADLINE,
) -> frozenset[int]:
    """A set ``S ⊇ keep`` of updates such that no selection agreeing with ``selection`` on
    ``S`` has a joint plan within the bounds, given that ``human + selection`` has none.

    Deletion over the updates outside ``keep`` (first all at once, then one at a time): an
    update is dropped when the abstraction with it free (:mod:`mega_sat.analysis.abstraction`) still
    has no joint plan.  A search that hits ``node_limit`` proves nothing, so the update stays;
    the result is always sound, just possibly larger than necessary.
    """
    everything = frozenset(range(family.n_updates))

    def infeasible(fixed: frozenset[int]) -> bool:
        human = abstract_task(family, selection, fixed)
        r = searcher.search(
            human, robot_bound, human_bound, node_limit=node_limit, deadline=deadline
        )
        return r.status == Status.INFEASIBLE

    candidates = sorted(everything - keep)
    if not candidates:
        return everything
    if infeasible(keep):
        return keep
    fixed = everything
    for i in candidates:
        trial = fixed - {i}
        if infeasible(trial):
            fixed = trial
    return fixed


def search_joint(
    searcher: JointSearcher,
    family,
    selection: frozenset[int],
    robot_bound: int | None,
    human_bound: int,
    *,
    keep: frozenset[int] = frozenset(),
    deadline: Deadline = NO_DEADLINE,
    options: Options = DEFAULT,
    node_limit: int | None = None,
) -> JointResult | None:
    """JOINT(E, K, c) by explicit search, as the same :class:`JointResult` as the SAT oracle's.

    A plan is robot-cost minimal by A*.  "No plan" comes with a core: the updates the search
    depended on (:class:`CoreTracker`) plus ``keep`` (updates the caller fixes anyway, e.g.
    the tight support of ``pi*``), confirmed by a second search whose heuristic is computed on
    the abstraction fixing just those; if that one runs past ``joint_core_factor`` times the
    nodes of the first (at least ``joint_core_min_nodes``), by :func:`infeasibility_core`.
    Returns ``None`` when ``deadline`` passed before an answer, status ``LIMIT`` (nothing
    proven) when the first search reaches ``node_limit`` expansions.
    """
    t0 = time.perf_counter()
    sel = frozenset(selection)
    everything = frozenset(range(family.n_updates))
    human = abstract_task(family, sel, everything)
    track = CoreTracker(family, sel, searcher._r_masks)
    r = searcher.search(
        human, robot_bound, human_bound, node_limit=node_limit, deadline=deadline, track=track
    )
    if r.status == Status.LIMIT:
        return JointResult(
            Status.LIMIT, None, None, None, None, sel, False, f"node limit {node_limit}", 0, 1,
            time.perf_counter() - t0, r.expanded,
        )  # fmt: skip
    if not r.status.decided:
        return None
    if r.status == Status.PLAN:
        return JointResult(
            Status.PLAN, r.plan, r.robot_cost, r.human_cost, None, sel, True,
            "proven by explicit search", 0, 1, time.perf_counter() - t0, r.expanded,
        )  # fmt: skip
    node_limit = max(options.joint_core_min_nodes, int(options.joint_core_factor * r.expanded))
    # the search above pruned with the heuristic of human + E itself, valid for E alone; redo
    # it with the heuristic of the abstraction fixing only what it depended on, which stays
    # valid for every E' agreeing on the core
    fixed = frozenset(keep) | track.used
    if fixed != everything:
        track2 = CoreTracker(family, sel, searcher._r_masks)
        r2 = searcher.search(
            human,
            robot_bound,
            human_bound,
            node_limit=node_limit,
            deadline=deadline,
            heuristic_task=abstract_task(family, sel, fixed),
            track=track2,
        )
        if r2.status == Status.INFEASIBLE:
            fixed |= track2.used
        else:  # cut short: fall back to deletion, each search on an abstraction
            fixed = infeasibility_core(
                searcher,
                family,
                sel,
                frozenset(keep),
                robot_bound,
                human_bound,
                node_limit=node_limit,
                deadline=deadline,
            )
    return JointResult(
        Status.INFEASIBLE, None, None, None, frozenset((i, i in sel) for i in fixed), sel, True,
        "proven by explicit search", 0, 1, time.perf_counter() - t0, r.expanded,
    )  # fmt: skip
