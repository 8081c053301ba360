;; logistics -- parcels between cities in the IPC style: the operator's model.
;; The operator knows the six IPC actions but
;;  - not airdrop, truck-to-plane and plane-to-truck (the robot's newer skills);
;;  - not that a truck stays in its city: drive-truck lacks (in-city ?from ?c) and
;;    (in-city ?to ?c), so a truck may drive from any location to any other.
(define (domain logistics)
  (:requirements :strips :typing :action-costs)
  (:types location city locatable - object
          airport - location
          package vehicle - locatable
          truck airplane - vehicle)
  (:predicates
    (at ?x - locatable ?l - location)
    (in ?p - package ?v - vehicle)
    (in-city ?l - location ?c - city)
    (drop-zone ?l - location))
  (:functions (total-cost) - number)

  (:action load-truck
    :parameters (?p - package ?t - truck ?l - location)
    :precondition (and (at ?t ?l) (at ?p ?l))
    :effect (and (not (at ?p ?l)) (in ?p ?t) (increase (total-cost) 1)))

  (:action unload-truck
    :parameters (?p - package ?t - truck ?l - location)
    :precondition (and (at ?t ?l) (in ?p ?t))
    :effect (and (not (in ?p ?t)) (at ?p ?l) (increase (total-cost) 1)))

  (:action load-airplane
    :parameters (?p - package ?a - airplane ?l - airport)
    :precondition (and (at ?a ?l) (at ?p ?l))
    :effect (and (not (at ?p ?l)) (in ?p ?a) (increase (total-cost) 1)))

  (:action unload-airplane
    :parameters (?p - package ?a - airplane ?l - airport)
    :precondition (and (at ?a ?l) (in ?p ?a))
    :effect (and (not (in ?p ?a)) (at ?p ?l) (increase (total-cost) 1)))

  (:action drive-truck
    :parameters (?t - truck ?from - location ?to - location ?c - city)
    :precondition (and (at ?t ?from))
    :effect (and (not (at ?t ?from)) (at ?t ?to) (increase (total-cost) 2)))

  (:action fly-airplane
    :parameters (?a - airplane ?from - airport ?to - airport)
    :precondition (and (at ?a ?from))
    :effect (and (not (at ?a ?from)) (at ?a ?to) (increase (total-cost) 3)))
)
