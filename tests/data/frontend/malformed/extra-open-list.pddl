(define (domain base)
  (:requirements :strips)
  (:predicates (p ?x) (q ?x) (r ?x ?y))
  (:action a
    :parameters (?x)
    :precondition (p ?x)
    :effect (q ?x))

; the '(' that opens the next line is one too many
(  (:action b
    :parameters (?x ?y)
    :precondition (q ?x)
    :effect (r ?x ?y)))
