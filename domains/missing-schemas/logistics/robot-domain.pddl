;; logistics -- parcels between cities in the IPC style: the robot's model.
;; Trucks drive between the locations of one city, airplanes fly between airports, parcels
;; are loaded into and unloaded from vehicles.
;; What the robot can do that its operator does not know:
;;  - airdrop (5 parameters): an airplane at an airport drops a parcel it carries by parachute
;;    onto a drop zone of the same city, without landing there;
;;  - truck-to-plane and plane-to-truck (4 parameters each): at an airport a parcel goes
;;    straight between a truck and an airplane, as cheap as one loading.
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
    :precondition (and (at ?t ?from) (in-city ?from ?c) (in-city ?to ?c))
    :effect (and (not (at ?t ?from)) (at ?t ?to) (increase (total-cost) 2)))

  (:action fly-airplane
    :parameters (?a - airplane ?from - airport ?to - airport)
    :precondition (and (at ?a ?from))
    :effect (and (not (at ?a ?from)) (at ?a ?to) (increase (total-cost) 3)))

  (:action airdrop
    :parameters (?a - airplane ?p - package ?from - airport ?to - location ?c - city)
    :precondition (and (at ?a ?from) (in ?p ?a) (in-city ?from ?c) (in-city ?to ?c)
                       (drop-zone ?to))
    :effect (and (not (in ?p ?a)) (at ?p ?to) (increase (total-cost) 2)))

  (:action truck-to-plane
    :parameters (?p - package ?t - truck ?a - airplane ?l - airport)
    :precondition (and (in ?p ?t) (at ?t ?l) (at ?a ?l))
    :effect (and (not (in ?p ?t)) (in ?p ?a) (increase (total-cost) 1)))

  (:action plane-to-truck
    :parameters (?p - package ?a - airplane ?t - truck ?l - airport)
    :precondition (and (in ?p ?a) (at ?a ?l) (at ?t ?l))
    :effect (and (not (in ?p ?a)) (in ?p ?t) (increase (total-cost) 1)))
)
