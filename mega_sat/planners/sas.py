"""Ground tasks in Fast Downward's own input format (SAS+, version 3), products included.

Handing FD a ground task as PDDL makes its translator re-read thousands of zero-argument
actions, which can take far longer than the search (11 s against a few milliseconds on an
IPC snake task); the search component reads this text directly.  Every atom is a binary
variable (value 0: true, 1: false), as the translator makes it without mutex invariants, so
plans and costs are plain STRIPS.

The product of several tasks puts their atoms side by side: an operator is one family action
present in every task, applicable when it is applicable in each, with each task's effects on
that task's variables and, as its cost, the weighted sum of its costs.  A plan of the product
is then exactly a plan valid in every task (:mod:`mega_sat.planners.joint_fd`).
"""

from __future__ import annotations

from collections.abc import Sequence

from mega_sat.ground.family import GroundTask
from mega_sat.model.lifted import PlanStep


def product_sas(parts: Sequence[tuple[GroundTask, int]]) -> tuple[str, dict[str, PlanStep]]:
    """The product of the ``(task, weight)`` parts as SAS+ text, and a map from operator
    names back to plan steps.  Operators are matched by their ground step (the parts may come
    from different families: one per human model); an action adds an atom it also deletes
    (PDDL's rule).

    What FD's translator would drop is dropped here too, since every variable costs the
    search per state: operators not reachable in the delete relaxation (over both values of
    every variable), variables no reachable operator changes (their conditions hold or fail
    once and for all), and variables no condition or goal reads."""
    offsets, n = [], 0
    for task, _ in parts:
        offsets.append(n)
        n += len(task.atoms)
    init = [1] * n  # value 0: the atom holds
    goal: dict[int, int] = {}
    for (task, _), off in zip(parts, offsets, strict=True):
        for p in task.init:
            init[off + p] = 0
        goal.update((off + p, 0) for p in task.goal)
    by_step = [task.by_step for task, _ in parts]
    first = parts[0][0].actions
    shared = [j for j, a in enumerate(first) if all(a.step in b for b in by_step[1:])]
    ops: list[tuple[int, dict[int, int], dict[int, int], int]] = []  # (number, need, post, cost)
    for j in shared:
        step = first[j].step
        need: dict[int, int] = {}  # variable -> required value
        post: dict[int, int] = {}  # variable -> value after
        cost = 0
        for b, off, (_, weight) in zip(by_step, offsets, parts, strict=True):
            a = b[step]
            if a.pre & a.negpre:
                break  # requires an atom and its negation: never applicable
            need.update((off + p, 0) for p in a.pre)
            need.update((off + p, 1) for p in a.negpre)
            post.update((off + p, 1) for p in a.delete)
            post.update((off + p, 0) for p in a.add)  # add wins over delete
            cost += weight * a.cost
        else:
            # an effect that sets what the action requires changes nothing
            ops.append((j, need, {v: x for v, x in post.items() if need.get(v) != x}, cost))
    # delete-relaxed reachability of variable values
    reached = {(v, x) for v, x in enumerate(init)}
    live: list[tuple[int, dict[int, int], dict[int, int], int]] = []
    waiting = ops
    while True:
        now = [op for op in waiting if all(vx in reached for vx in op[1].items())]
        if not now:
            break
        live += now
        waiting = [op for op in waiting if not all(vx in reached for vx in op[1].items())]
        for op in now:
            reached.update(op[2].items())
    live.sort(key=lambda op: op[0])
    changed = {v for op in live for v in op[2]}
    # a condition or goal on a variable nothing changes holds or fails once and for all
    static_ok = all(init[v] == x for v, x in goal.items() if v not in changed)
    goal = {v: x for v, x in goal.items() if v in changed}
    keep = sorted(changed & ({v for op in live for v in op[1]} | set(goal)))
    new = {v: k for k, v in enumerate(keep)}
    names: dict[str, PlanStep] = {}
    body: list[str] = []
    for j, need, post, cost in live if static_ok else ():
        if any(init[v] != x for v, x in need.items() if v not in changed):
            continue
        post = {v: x for v, x in post.items() if v in new}
        if not post:
            continue  # changes nothing a condition or goal reads (costs are >= 0)
        prevail = sorted((new[v], x) for v, x in need.items() if v in new and v not in post)
        name = f"act{j}"
        names[name] = first[j].step
        body += ["begin_operator", name, str(len(prevail))]
        body += [f"{v} {x}" for v, x in prevail]
        body.append(str(len(post)))
        body += [f"0 {new[v]} {need.get(v, -1)} {x}" for v, x in sorted(post.items())]
        body += [str(cost), "end_operator"]
    values = [init[v] for v in keep]
    goals = sorted((new[v], x) for v, x in goal.items())
    if not static_ok:  # a goal nothing can reach: one variable whose goal value never holds
        values, goals = [1], [(0, 0)]
    out = ["begin_version", "3", "end_version", "begin_metric", "1", "end_metric"]
    out.append(str(len(values)))
    for k in range(len(values)):
        out += ["begin_variable", f"var{k}", "-1", "2", f"Atom a{k}()", f"NegatedAtom a{k}()"]
        out.append("end_variable")
    out += ["0", "begin_state", *map(str, values), "end_state"]  # no mutex groups
    out += ["begin_goal", str(len(goals)), *(f"{v} {x}" for v, x in goals), "end_goal"]
    out += [str(len(names)), *body, "0"]  # no axioms
    return "\n".join(out) + "\n", names
