(define (domain base)
  (:requirements :strips)
  (:predicates (p ?x) (q ?x) (r ?x ?y))
  (:action a
    :parameters (?x)
    :precondition (p ?x)
    :effect (and (q ?x)
                 (r ?x))))
