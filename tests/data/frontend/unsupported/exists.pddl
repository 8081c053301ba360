; unsupported: exists
(define (domain base)
  (:requirements :strips :adl)
  (:predicates (p ?x) (q ?x) (r ?x ?y))
  (:action a
    :parameters (?x ?y)
    :precondition (exists (?z) (r ?x ?z))
    :effect (and (q ?x) (not (p ?x)))))
