;; courier with a zero-cost pick (docs/exactness.md): the robot's model.
(define (domain courier)
  (:requirements :strips :typing :negative-preconditions :action-costs)
  (:types location package)
  (:predicates (robot-at ?l - location) (road ?a ?b - location)
               (pkg-at ?p - package ?l - location) (holding ?p - package)
               (handempty) (fragile ?p - package))
  (:functions (total-cost) (road-length ?a ?b - location))
  (:action drive
    :parameters (?from ?to - location)
    :precondition (and (robot-at ?from) (road ?from ?to))
    :effect (and (not (robot-at ?from)) (robot-at ?to)
                 (increase (total-cost) (road-length ?from ?to))))
  (:action pick
    :parameters (?p - package ?l - location)
    :precondition (and (robot-at ?l) (pkg-at ?p ?l) (handempty))
    :effect (and (holding ?p) (not (pkg-at ?p ?l)) (not (handempty))
                 (increase (total-cost) 0)))
  (:action drop
    :parameters (?p - package ?l - location)
    :precondition (and (robot-at ?l) (holding ?p))
    :effect (and (pkg-at ?p ?l) (handempty) (not (holding ?p))
                 (increase (total-cost) 1)))
  (:action throw
    :parameters (?p - package ?from ?to - location)
    :precondition (and (robot-at ?from) (holding ?p) (road ?from ?to) (not (fragile ?p)))
    :effect (and (pkg-at ?p ?to) (handempty) (not (holding ?p))
                 (increase (total-cost) 2))))
