; unsupported: equality in an effect (in a precondition it is read)
(define (domain base)
  (:requirements :strips :adl)
  (:predicates (p ?x) (q ?x) (r ?x ?y))
  (:action a
    :parameters (?x ?y)
    :precondition (and (p ?x) (= ?x ?y))
    :effect (and (q ?x) (= ?x ?y) (not (p ?x)))))
