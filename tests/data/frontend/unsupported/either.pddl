; unsupported: either
(define (domain base)
  (:requirements :strips :adl)
  (:predicates (p ?x) (q ?x) (r ?x ?y))
  (:action a
    :parameters (?x - (either t1 t2) ?y)
    :precondition (and (p ?x) (not (q ?y)))
    :effect (and (q ?x) (not (p ?x)))))
