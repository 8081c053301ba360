(define (domain base)
  (:requirements :strips)
  (:predicates (p ?x) (q ?x) (r ?x ?y))
  (:action a
    :parameters (?x)
    ; the '(' before (p ?x) is one too many
    :precondition ((p ?x)
    :effect (q ?x))

  (:action b
    :parameters (?x ?y)
    :precondition (q ?x)
    :effect (r ?x ?y)))
