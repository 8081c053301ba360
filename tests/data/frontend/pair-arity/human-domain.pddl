(define (domain rover)
  (:requirements :strips)
  (:predicates (at ?w) (sampled ?w) (empty ?r))
  (:action move
    :parameters (?r ?from ?to)
    :precondition (at ?from)
    :effect (and (at ?to) (not (at ?from))))
  (:action sample
    :parameters (?r ?w)
    :precondition (and (at ?w) (empty ?r))
    :effect (sampled ?w)))
