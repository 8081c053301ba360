(define (domain roads)
  (:requirements :strips :typing :action-costs)
  (:types city)
  (:predicates (at ?c - city) (connected ?a ?b - city) (visited ?c - city))
  (:functions (total-cost) - number
              (road-length ?a ?b - city) - number)
  (:action drive
    :parameters (?from ?to - city)
    :precondition (and (at ?from) (connected ?from ?to))
    :effect (and (at ?to) (not (at ?from)) (visited ?to)
                 (increase (total-cost) (road-length ?from ?to))))
  (:action teleport
    :parameters (?from ?to - city)
    :precondition (at ?from)
    :effect (and (at ?to) (not (at ?from)) (increase (total-cost) 10)))
  (:action look
    :parameters (?c - city)
    :precondition (at ?c)
    :effect (visited ?c)))
