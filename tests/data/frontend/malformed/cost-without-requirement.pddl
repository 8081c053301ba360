(define (domain base)
  (:requirements :strips)
  (:predicates (p ?x) (q ?x) (r ?x ?y))
  (:functions (total-cost) - number)
  (:action a
    :parameters (?x)
    :precondition (p ?x)
    :effect (and (q ?x) (increase (total-cost) 2))))
