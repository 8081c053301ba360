(define (domain base)
  (:requirements :strips)
  (:predicates (p ?x) (q ?x) (r ?x ?y))
  (:action a
    :parameters (?x)
    :precondition (and (p ?x)
    :effect (q ?x)))
