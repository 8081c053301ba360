; A typed logistics-like domain with a type hierarchy and constants.
(define (domain typed-logistics)
  (:requirements :strips :typing :negative-preconditions)
  (:types truck car - vehicle
          vehicle package - locatable
          place)
  (:constants depot - place
              van1 - truck)
  (:predicates (at ?x - locatable ?p - place)
               (road ?a ?b - place)
               (in ?p - package ?v - vehicle)
               (broken ?v - vehicle))
  (:action drive
    :parameters (?v - vehicle ?from ?to - place)
    :precondition (and (at ?v ?from) (road ?from ?to) (not (broken ?v)))
    :effect (and (at ?v ?to) (not (at ?v ?from))))
  (:action load
    :parameters (?p - package ?v - truck ?l - place)
    :precondition (and (at ?p ?l) (at ?v ?l))
    :effect (and (in ?p ?v) (not (at ?p ?l))))
  (:action unload-at-depot
    :parameters (?p - package ?v - truck)
    :precondition (and (in ?p ?v) (at ?v depot))
    :effect (and (at ?p depot) (not (in ?p ?v))))
  (:action wait
    :parameters (?x)
    :precondition ()
    :effect ()))
