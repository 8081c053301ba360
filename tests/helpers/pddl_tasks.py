"""PDDL text of tasks the planner tests share."""

from __future__ import annotations


def pigeonhole(n: int) -> tuple[str, str]:
    """n + 1 pigeons, n holes: relaxed-solvable, really unsolvable, hard for any search."""
    domain = """(define (domain ph) (:requirements :strips)
 (:predicates (free ?h) (placed ?p) (pigeon ?p) (hole ?h))
 (:action put :parameters (?p ?h)
  :precondition (and (pigeon ?p) (hole ?h) (free ?h))
  :effect (and (placed ?p) (not (free ?h)))))
"""
    pigeons = [f"p{i}" for i in range(n + 1)]
    holes = [f"h{i}" for i in range(n)]
    init = [f"(pigeon {p})" for p in pigeons] + [f"(hole {h}) (free {h})" for h in holes]
    problem = (
        f"(define (problem ph{n}) (:domain ph) (:objects {' '.join(pigeons + holes)})"
        f" (:init {' '.join(init)}) (:goal (and {' '.join(f'(placed {p})' for p in pigeons)})))"
    )
    return domain, problem
