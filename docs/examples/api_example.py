"""The library API on the USAR example (docs/api.md); run from the repository root."""

import json

from mega_sat import api

# 1. Load the four PDDL files (the human problem defaults to the robot problem).
task = api.load_task(
    "domains/usar-fetch/robot-domain.pddl",
    "domains/usar-fetch/p1/robot-problem.pddl",
    "domains/usar-fetch/human-domain.pddl",
    "domains/usar-fetch/p1/human-problem.pddl",
)
print("Delta:", [u.name for u in task.delta])

# 2. One solver keeps the grounding and the SAT solvers alive across calls.
solver = api.MegaSolver(task)  # engine="sat", planner="portfolio", hitting_set="rc2"
fr = solver.frontier()
print(f"robot optimum {fr.robot_optimal_cost}, exact {fr.exact}, complete {fr.complete}")
for p in fr.points:
    print(
        f"  |E| = {p.size}, robot cost {p.robot_cost}, human cost {p.human_cost}:",
        list(p.explanation),
    )

# 3. Every alpha is answered from the same frontier (paper property 4).
for alpha in (0.1, 0.5, 1.0):
    sol = solver.solve(alpha)
    print(
        f"alpha {alpha}: |E| = {sol.chosen.size}, robot cost {sol.chosen.robot_cost}, "
        f"objective {sol.objective:g}"
    )

# 4. MCE of a robot-optimal plan, and an independent check of an answer.
mce = solver.explain()
print("MCE:", list(mce.explanation), "for", [" ".join(s) for s in mce.plan])
report = solver.verify(solver.solve(0.1).chosen)
print("verify ok:", report.ok)
for line in report.lines():
    print("  " + line)

# 5. Results serialise to JSON (the same objects the CLI prints with --json).
d = json.loads(solver.solve(0.1).to_json())
print("JSON keys:", sorted(d))

# 6. Models can also come from strings, e.g. generated in code.  Here the human wrongly
#    believes that the robot can only enter a lit room, so expects the longer lit route.
DOMAIN = """(define (domain rooms) (:requirements :strips :action-costs)
  (:predicates (at ?r) (door ?a ?b) (lit ?r))
  (:functions (total-cost))
  (:action go :parameters (?a ?b)
    :precondition (and (at ?a) (door ?a ?b){extra})
    :effect (and (not (at ?a)) (at ?b) (increase (total-cost) 1))))"""
PROBLEM = """(define (problem rooms-1) (:domain rooms) (:objects r1 r2 r3 r4 r5)
  (:init (at r1) (door r1 r2) (door r2 r4) (door r1 r3) (door r3 r5) (door r5 r4)
         (lit r3) (lit r4) (lit r5))
  (:goal (and (at r4))))"""
small = api.load_task_from_strings(
    DOMAIN.format(extra=""), PROBLEM, DOMAIN.format(extra=" (lit ?b)")
)
small_fr = api.frontier(small)
print("Delta:", [u.name for u in small.delta])
for p in small_fr.points:
    print(f"  |E| = {p.size}, robot cost {p.robot_cost}:", [" ".join(s) for s in p.plan])
for alpha in (0.5, 1.0):  # at alpha = 1 both points score 1: the lower robot cost wins
    sol = api.solve(small, alpha)
    print(f"alpha {alpha}: objective {sol.objective:g}, E = {list(sol.chosen.explanation)}")
