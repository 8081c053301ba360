;; courier (docs/models.md): the human's model.  No throw action; parameter names differ from
;; the robot's (they are matched by position); picking a package up is believed to cost 2.
(define (domain courier)
  (:requirements :strips :typing :action-costs)
  (:types location package)
  (:predicates (robot-at ?l - location) (road ?a ?b - location)
               (pkg-at ?p - package ?l - location) (holding ?p - package)
               (handempty) (fragile ?p - package))
  (:functions (total-cost) (road-length ?a ?b - location))
  (:action drive
    :parameters (?x ?y - location)
    :precondition (and (robot-at ?x) (road ?x ?y))
    :effect (and (not (robot-at ?x)) (robot-at ?y)
                 (increase (total-cost) (road-length ?x ?y))))
  (:action pick
    :parameters (?pkg - package ?loc - location)
    :precondition (and (robot-at ?loc) (pkg-at ?pkg ?loc) (handempty))
    :effect (and (holding ?pkg) (not (pkg-at ?pkg ?loc)) (not (handempty))
                 (increase (total-cost) 2)))
  (:action drop
    :parameters (?pkg - package ?loc - location)
    :precondition (and (robot-at ?loc) (holding ?pkg))
    :effect (and (pkg-at ?pkg ?loc) (handempty) (not (holding ?pkg))
                 (increase (total-cost) 1))))
