(define (domain base)
  (:requirements :strips :typing)
  (:types place)
  (:predicates (p ?x) (q ?x) (r ?x ?y))
  (:action a
    :parameters (?x - city)
    :precondition (p ?x)
    :effect (q ?x)))
