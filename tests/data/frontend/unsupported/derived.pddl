(define (domain base)
  (:requirements :strips :derived-predicates)
  (:predicates (p ?x) (q ?x) (r ?x ?y))
  (:derived (q ?x)
     (p ?x))
  (:action a
    :parameters (?x)
    :precondition (q ?x)
    :effect (not (p ?x))))
