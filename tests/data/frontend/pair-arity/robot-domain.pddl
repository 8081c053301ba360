(define (domain rover)
  (:requirements :strips)
  (:predicates (at ?r ?w) (sampled ?w) (empty ?r))
  (:action move
    :parameters (?r ?from ?to)
    :precondition (at ?r ?from)
    :effect (and (at ?r ?to) (not (at ?r ?from))))
  (:action sample
    :parameters (?r ?w)
    :precondition (and (at ?r ?w) (empty ?r))
    :effect (sampled ?w)))
