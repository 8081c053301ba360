(define (domain base)
  (:requirements :strips :action-costs)
  (:predicates (p ?x) (q ?x) (r ?x ?y))
  (:functions (total-cost) - number (w ?x) - number)
  (:action a
    :parameters (?x)
    :precondition (p ?x)
    :effect (and (q ?x)
                 (increase (total-cost) (+ (w ?x) 1)))))
