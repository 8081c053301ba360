; The robot: a drone is a vehicle, so it can deliver.
(define (domain delivery)
  (:requirements :strips :typing)
  (:types drone truck - vehicle
          vehicle parcel place)
  (:predicates (at ?x ?p) (holding ?v ?o) (delivered ?o))
  (:action deliver
    :parameters (?v - vehicle ?o - parcel ?p - place)
    :precondition (and (at ?v ?p) (holding ?v ?o))
    :effect (and (delivered ?o) (not (holding ?v ?o)))))
