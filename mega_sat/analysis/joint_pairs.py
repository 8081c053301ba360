"""Horizon-free proofs that no plan runs in both the robot model and a human model.

Every MEGA solution is a *joint* plan: it reaches the robot's goal in the robot model and the
human's goal in ``human + E``.  Where no joint plan exists at any length, ``E`` is no solution
for any cost bound, and neither is any ``E'`` the proof covers.  The SAT JOINT oracle proves
"no joint plan" only up to a horizon (a human cost bound), so its learned clauses must also fix
the updates that keep the bound's plan running; a proof without a horizon needs neither.

The proof is h^2 (:mod:`mega_sat.analysis.pair_reachability`) on the *product* of the robot
model and the abstraction of every ``human + E'`` agreeing with ``E`` on ``fixed``
(:mod:`mega_sat.analysis.abstraction`): one fact set per copy, and an action exactly where both
copies have it, with the union of both copies' conditions and effects.  A joint execution of
any agreeing model is an execution of the product (componentwise, as in the abstraction's
argument), so a goal pair the product never reaches proves that none of those models has a
joint plan.  Pairs across the copies are what the product adds: the robot's ``(on b a)`` with
the human's ``(clear a)`` when only actions both models agree on could make both true.
"""

from __future__ import annotations

from functools import cached_property

from mega_sat.analysis.abstraction import abstract_task
from mega_sat.analysis.pair_reachability import goal_pairs_reached, pair_masks
from mega_sat.deadline import NO_DEADLINE, Deadline
from mega_sat.ground.family import GroundFamily, GroundTask, StripsAction


def joint_product(robot: GroundTask, human: GroundTask) -> GroundTask:
    """Both copies side by side: the human copy's facts are shifted past the robot's, and an
    action of the family is kept where both copies have it (``StripsAction.index``)."""
    off = len(robot.atoms)

    def shift(facts: frozenset[int]) -> frozenset[int]:
        return frozenset(p + off for p in facts)

    by_index = {a.index: a for a in human.actions}
    actions = []
    for r in robot.actions:
        h = by_index.get(r.index)
        if h is None:
            continue
        actions.append(
            StripsAction(
                r.index, r.name, r.args, r.pre | shift(h.pre), r.negpre | shift(h.negpre),
                r.add | shift(h.add), r.delete | shift(h.delete), r.cost,
            )
        )  # fmt: skip
    atoms = robot.atoms + tuple(("human", *a) for a in human.atoms)
    return GroundTask(
        atoms, tuple(actions), robot.init | shift(human.init), robot.goal | shift(human.goal)
    )


class JointPairs:
    """h^2 proofs of "no joint plan" for one family; the robot copy is built once, when first
    needed."""

    def __init__(self, family: GroundFamily):
        self.family = family

    @cached_property
    def _robot(self) -> GroundTask:
        every = self.family.robot_selection
        return abstract_task(self.family, every, every)

    def product(self, selection: frozenset[int], fixed: frozenset[int]) -> GroundTask:
        return joint_product(self._robot, abstract_task(self.family, selection, fixed))

    def no_joint_plan(self, selection: frozenset[int], fixed: frozenset[int]) -> bool:
        """True when no ``human + E'`` with ``E'`` agreeing with ``selection`` on ``fixed``
        has a plan that also runs in the robot model (False proves nothing)."""
        task = self.product(selection, fixed)
        return not goal_pairs_reached(pair_masks(task), task)

    def landmarks(self, deadline: Deadline = NO_DEADLINE) -> frozenset[int]:
        """Updates every solution's explanation contains: ``i`` where no model without ``i``
        (every other update free) has a joint plan.  (No model *with* ``i`` can be ruled out
        this way: with every other update free, the robot model itself agrees.)  Each trial
        relaxes the human model's own product, whose pairs seed its fixpoint."""
        n = self.family.n_updates
        everything = frozenset(range(n))
        base = self.product(frozenset(), everything)
        seed = pair_masks(base)
        if goal_pairs_reached(seed, base):
            return frozenset()  # every trial relaxes the human model's product: none proves
        found = []
        for i in range(n):
            if deadline.expired():
                break
            task = self.product(frozenset(), frozenset({i}))
            if not goal_pairs_reached(pair_masks(task, seed), task):
                found.append(i)
        return frozenset(found)
