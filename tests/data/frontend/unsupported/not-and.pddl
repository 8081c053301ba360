; unsupported: not-and
(define (domain base)
  (:requirements :strips :adl)
  (:predicates (p ?x) (q ?x) (r ?x ?y))
  (:action a
    :parameters (?x ?y)
    :precondition (not (and (p ?x) (q ?x)))
    :effect (and (q ?x) (not (p ?x)))))
