; unsupported: increase-fluent
(define (domain base)
  (:requirements :strips :adl)
  (:predicates (p ?x) (q ?x) (r ?x ?y))
  (:action a
    :parameters (?x ?y)
    :precondition (and (p ?x) (not (q ?y)))
    :effect (and (q ?x) (increase (fuel) 1))))
