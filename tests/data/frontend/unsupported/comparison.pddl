; unsupported: comparison
(define (domain base)
  (:requirements :strips :adl)
  (:predicates (p ?x) (q ?x) (r ?x ?y))
  (:action a
    :parameters (?x ?y)
    :precondition (and (p ?x) (> (fuel) 1))
    :effect (and (q ?x) (not (p ?x)))))
