; unsupported: forall
(define (domain base)
  (:requirements :strips :adl)
  (:predicates (p ?x) (q ?x) (r ?x ?y))
  (:action a
    :parameters (?x ?y)
    :precondition (forall (?z) (p ?z))
    :effect (and (q ?x) (not (p ?x)))))
