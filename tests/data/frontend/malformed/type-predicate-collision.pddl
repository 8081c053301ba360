(define (domain base)
  (:requirements :strips :typing)
  (:types p place)
  (:predicates (at ?x - p ?y - place)
               (p ?x))
  (:action a
    :parameters (?x - p)
    :precondition (p ?x)
    :effect (not (p ?x))))
