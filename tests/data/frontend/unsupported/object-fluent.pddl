(define (domain base)
  (:requirements :strips :typing)
  (:types place)
  (:predicates (p ?x) (q ?x) (r ?x ?y))
  (:functions (location ?x) - place)
  (:action a
    :parameters (?x)
    :precondition (p ?x)
    :effect (q ?x)))
