; the domain the problem-side fixtures are checked against
(define (domain base)
  (:requirements :strips :negative-preconditions)
  (:predicates (p ?x) (q ?x) (r ?x ?y))
  (:action a
    :parameters (?x ?y)
    :precondition (and (p ?x) (not (q ?y)))
    :effect (and (q ?x) (not (p ?x)))))
