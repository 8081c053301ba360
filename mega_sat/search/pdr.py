"""Property-directed reachability (IC3/PDR): proves a STRIPS task unsolvable by finding an
inductive invariant that holds initially and excludes every goal state.

The other proofs of "no plan" each see one kind of reason: relaxed and pair reachability a
reason visible in an abstraction, exhaustive reachability a small relevant state space, a
SAT horizon a bounded one.  A model whose goal is unreachable only because of an ordering
argument over a huge state space (blocksworld Δ15 p1 with updates {5, 12}: no plan within 200
steps, more than 37 million relevant reachable states) needs an invariant, which IC3 builds
clause by clause from the states it proves unreachable (Bradley 2011; for planning, Suda
2014).

Frames ``F_0 = init``, ``F_1``, ... over-approximate the states reachable within ``i``
steps; each is the set of clauses learned at its level or above (one solver, one activation
literal per level).  Once ``F_k`` holds a goal state, the goal's cube is blocked
recursively.  A cube with no predecessor in ``F_{i-1}`` becomes a clause of ``F_1..F_i``,
generalized by the solver's core and by dropping literals while that stays true (the query
is not made relative to the cube's own negation: on the shipped models the plain query was
2-3 times faster).  A cube with a predecessor is regressed through that step's action (Suda
2014): the obligation one level down is every state from which the action leads into the
cube, not the one state the solver found, so one clause blocks what would otherwise take a
query per state.  Once a level's clauses all hold one level up, that level is an inductive
invariant: no plan.  A chain of obligations back to the initial state means a plan exists
(its cost is not computed: the caller only asks whether there is none).  :meth:`Pdr.seed`
starts ``F_1`` from the clauses of earlier invariants that hold there (models a few updates
apart share most).
"""

from __future__ import annotations

import heapq
import itertools
from collections.abc import Iterable

from pysat.card import CardEnc, EncType
from pysat.solvers import Solver

from mega_sat.deadline import NO_DEADLINE, Deadline
from mega_sat.ground.family import GroundTask
from mega_sat.ground.relevance import relevant_atoms, relevant_part
from mega_sat.status import Status

Cube = frozenset[tuple[int, bool]]  # a set of states: (atom, value) literals


class Pdr:
    """IC3 on the relevant part of ``task`` (the same verdict, fewer atoms); ``queries`` counts
    the SAT calls so far, the work the caller's limit is on."""

    def __init__(self, task: GroundTask, solver: str = "cadical195"):
        task = relevant_part(task)
        self.task = task
        n = len(task.atoms)
        self.n = n
        self.init = frozenset(task.init)
        self._x = list(range(1, n + 1))  # atom p now
        self._y = list(range(n + 1, 2 * n + 1))  # atom p after the step
        acts = list(range(2 * n + 1, 2 * n + len(task.actions) + 1))
        self._top = 2 * n + len(task.actions)
        self._solver = Solver(name=solver)
        self._transition(acts)
        self._levels: list[int] = []  # activation literal of the clauses stored at level i + 1
        self._frames: list[list[Cube]] = [[]]  # cubes blocked at exactly level i (delta)
        self.queries = 0
        self._fixpoint: int | None = None  # F_i = F_{i+1} for this i, once proven
        self._goal: Cube = frozenset((p, True) for p in task.goal)  # the first obligation

    def close(self) -> None:
        self._solver.delete()

    def __enter__(self) -> Pdr:
        return self

    def __exit__(self, *exc) -> None:
        self.close()

    # ------------------------------------------------------------------ encoding
    def _transition(self, acts: list[int]) -> None:
        """One sequential step: exactly one action (at least one under the assumption
        ``_step``, else none and the state stays), its conditions now, its effects after
        (an atom both added and deleted ends true), every other atom unchanged."""
        task, x, y, add = self.task, self._x, self._y, self._solver.add_clause
        adders: list[list[int]] = [[] for _ in range(self.n)]
        deleters: list[list[int]] = [[] for _ in range(self.n)]
        for a, act in zip(acts, task.actions, strict=True):
            for p in act.pre:
                add([-a, x[p]])
            for p in act.negpre:
                add([-a, -x[p]])
            for p in act.add:
                add([-a, y[p]])
                adders[p].append(a)
            for p in act.delete - act.add:
                add([-a, -y[p]])
                deleters[p].append(a)
        for p in range(self.n):
            add([-y[p], x[p], *adders[p]])
            add([y[p], -x[p], *deleters[p]])
        # "some action is taken" only where a query assumes a step: a goal query must not
        # exclude the states where no action applies
        self._step = self._fresh()
        add([-self._step, *acts])
        if len(acts) > 1:
            amo = CardEnc.atmost(acts, 1, top_id=self._top, encoding=EncType.seqcounter)
            self._top = max(self._top, amo.nv)
            for clause in amo.clauses:
                add(clause)

    def _fresh(self) -> int:
        self._top += 1
        return self._top

    def _now(self, cube: Cube) -> list[int]:
        return [self._x[p] if v else -self._x[p] for p, v in sorted(cube)]

    def _next(self, cube: Cube) -> list[int]:
        return [self._y[p] if v else -self._y[p] for p, v in sorted(cube)]

    def _frame(self, i: int) -> list[int]:
        """Assumptions for ``F_i`` (``i >= 1``): the clauses stored at levels ``>= i``."""
        return self._levels[i - 1 :]

    def _solve(self, assumptions: list[int]) -> bool:
        self.queries += 1
        return bool(self._solver.solve(assumptions=assumptions))

    def _in_init(self, cube: Cube) -> bool:
        return all((p in self.init) == v for p, v in cube)

    def _block_at(self, cube: Cube, level: int) -> None:
        self._frames[level].append(cube)
        self._solver.add_clause([-self._levels[level - 1]] + [-lit for lit in self._now(cube)])

    def _new_level(self) -> None:
        self._levels.append(self._fresh())
        self._frames.append([])

    # -------------------------------------------------------------------- search
    def _predecessor(self, cube: Cube, i: int) -> tuple[bool, Cube | set[int]]:
        """Whether some state of ``F_{i-1}`` has a successor in ``cube`` (``F_0`` is the
        initial state, which no blocked cube contains): ``(True, the regression of cube
        through that step's action)``, or ``(False, the solver's core)``."""
        if i == 1:
            base = [self._x[p] if p in self.init else -self._x[p] for p in range(self.n)]
        else:
            base = self._frame(i - 1)
        found = self._solve([self._step, *base, *self._next(cube)])
        return found, self._regress(cube) if found else set(self._solver.get_core() or [])

    def _regress(self, cube: Cube) -> Cube:
        """The states from which the model's action leads into ``cube``: its conditions
        and the literals of ``cube`` it leaves alone.  Every one of them reaches ``cube`` in
        one step, so an obligation on all of them is as sound as one on the model's state,
        and blocking them all at once spares IC3 a query per state (Suda 2014)."""
        model, first = self._solver.get_model(), 2 * self.n
        a = next(j for j in range(len(self.task.actions)) if model[first + j] > 0)
        act = self.task.actions[a]
        out = {(p, v) for p, v in cube if p not in act.add and p not in act.delete}
        out.update((p, True) for p in act.pre)
        out.update((p, False) for p in act.negpre)
        return frozenset(out)

    def _generalize(self, cube: Cube, i: int, core: set[int]) -> Cube:
        """A subset of ``cube`` (just proven to have no predecessor in ``F_{i-1}``, ``core``
        the proof's assumptions) that still has none and excludes the initial state: the
        core, then literal dropping."""
        nxt = dict(zip(sorted(cube), self._next(cube), strict=True))
        gen = frozenset(lit for lit in cube if nxt[lit] in core)
        if self._in_init(gen):  # put back one literal the initial state violates
            gen |= {next((p, v) for p, v in sorted(cube) if (p in self.init) != v)}
        for lit in sorted(gen):
            trial = gen - {lit}
            if trial and not self._in_init(trial) and not self._predecessor(trial, i)[0]:
                gen = trial
        return gen

    def _block(self, bad: Cube, k: int, limit: int | None, deadline: Deadline) -> Status | None:
        """Block the goal state ``bad`` of ``F_k``: ``PLAN`` if it is reachable, ``None`` once
        blocked, ``LIMIT``/``TIMEOUT`` when out of work or time."""
        order = itertools.count()
        queue = [(k, next(order), bad)]
        while queue:
            if limit is not None and self.queries > limit:
                return Status.LIMIT
            if deadline.expired():
                return Status.TIMEOUT
            i, _, cube = heapq.heappop(queue)
            found, got = self._predecessor(cube, i)
            if found:
                # at level 1 the predecessor is the initial state, so no obligation reaches
                # level 0: a chain of obligations ends here
                if self._in_init(got):
                    return Status.PLAN  # the initial state reaches bad
                heapq.heappush(queue, (i - 1, next(order), got))
                heapq.heappush(queue, (i, next(order), cube))
            else:
                self._block_at(self._generalize(cube, i, got), i)
        return None

    def run(self, query_limit: int | None = None, deadline: Deadline | None = None) -> Status:
        """``UNSOLVABLE`` (an inductive invariant excludes the goal), ``PLAN`` (the goal is
        reachable), ``LIMIT`` after more than ``query_limit`` SAT calls in all, or
        ``TIMEOUT`` once ``deadline`` passes."""
        deadline = deadline if deadline is not None else NO_DEADLINE
        if self.task.goal <= self.init:
            return Status.PLAN
        goal = self._now(self._goal)
        if not self._levels:
            self._new_level()
        while True:
            k = len(self._levels)
            if query_limit is not None and self.queries > query_limit:
                return Status.LIMIT
            if deadline.expired():
                return Status.TIMEOUT
            if self._solve(self._frame(k) + goal):
                got = self._block(self._goal, k, query_limit, deadline)
                if got is not None:
                    return got
                continue
            self._new_level()  # F_k excludes the goal: push clauses forward
            for i in range(1, k + 1):
                for cube in list(self._frames[i]):
                    if not self._solve([self._step, *self._frame(i), *self._next(cube)]):
                        self._frames[i].remove(cube)
                        self._block_at(cube, i + 1)
                if not self._frames[i]:
                    self._fixpoint = i
                    return Status.UNSOLVABLE  # F_i = F_{i+1}: an inductive invariant

    def seed(self, cubes: Iterable[Cube]) -> int:
        """Put the cubes (lemmas of earlier invariants, over the same atom ids) that no
        state reachable within one step is in into ``F_1``, before the first run; how many.

        That is all ``F_1`` must satisfy (hold initially, and after one step from the initial
        state), so the frames stay over-approximations and every verdict stays exact; the
        propagation phase pushes a lemma further while it holds one level up.  A model close
        to one proven unsolvable before (a few updates apart) keeps most of its lemmas, and
        IC3 then needs far fewer queries.  A literal ``(p, False)`` on an atom outside the
        relevant part always holds (the atom is false throughout) and is dropped; a cube with
        ``(p, True)`` on one is empty and is skipped."""
        if self._levels:
            raise ValueError("lemmas are seeded before the first run")
        self._new_level()
        keep = relevant_atoms(self.task)
        added = 0
        for cube in cubes:
            if any(v and p not in keep for p, v in cube):
                continue
            cube = frozenset((p, v) for p, v in cube if p in keep)
            if cube and not self._in_init(cube) and not self._predecessor(cube, 1)[0]:
                self._block_at(cube, 1)
                added += 1
        return added

    def invariant(self) -> tuple[Cube, ...]:
        """After ``UNSOLVABLE``: cubes whose negations together are an inductive invariant of
        the relevant part that holds initially and excludes the goal (the clauses of the
        fixpoint frame).  Literals on atoms outside the relevant part are dropped (those atoms
        are false in every state of the relevant part, so a cube they are in stays the same
        set of its states; a cube that needs one true is empty there and is left out), so the
        invariant speaks only of atoms the goal depends on."""
        if self._fixpoint is None:
            raise ValueError("no invariant: the last run did not prove the task unsolvable")
        keep = relevant_atoms(self.task)
        out = []
        for level in self._frames[self._fixpoint + 1 :]:
            for cube in level:
                if all(p in keep or not v for p, v in cube):
                    out.append(frozenset((p, v) for p, v in cube if p in keep))
        return tuple(out)
