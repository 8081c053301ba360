; The human: a drone is not a vehicle (different type hierarchy), and parameter names differ.
(define (domain delivery)
  (:requirements :strips :typing)
  (:types truck - vehicle
          drone vehicle parcel place)
  (:predicates (at ?x ?p) (holding ?v ?o) (delivered ?o))
  (:action deliver
    :parameters (?veh - vehicle ?obj - parcel ?loc - place)
    :precondition (and (at ?veh ?loc) (holding ?veh ?obj))
    :effect (and (delivered ?obj) (not (holding ?veh ?obj)))))
