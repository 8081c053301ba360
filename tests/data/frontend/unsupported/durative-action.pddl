(define (domain base)
  (:requirements :strips)
  (:predicates (p ?x) (q ?x) (r ?x ?y))
  (:durative-action a
    :parameters (?x)
    :duration (= ?duration 2)
    :condition (at start (p ?x))
    :effect (at end (q ?x))))
