;; A human domain for usar-fetch whose take_picture has two parameters (the robot's has one):
;; the two models cannot be compared feature by feature.
(define (domain usar-fetch)
  (:requirements :strips :typing :action-costs)
  (:types waypoint)
  (:predicates
    (robot_at ?l - waypoint)
    (clear_path ?from - waypoint ?to - waypoint)
    (clearable ?from - waypoint ?to - waypoint)
    (picture_taken ?l - waypoint))
  (:functions (total-cost) - number)
  (:action move
    :parameters (?from - waypoint ?to - waypoint)
    :precondition (and (robot_at ?from) (clear_path ?from ?to))
    :effect (and (not (robot_at ?from)) (robot_at ?to) (increase (total-cost) 1)))
  (:action clear_passage
    :parameters (?from - waypoint ?to - waypoint)
    :precondition (and (robot_at ?from) (clearable ?from ?to))
    :effect (and (not (clearable ?from ?to)) (clear_path ?from ?to) (increase (total-cost) 3)))
  (:action take_picture
    :parameters (?from - waypoint ?loc - waypoint)
    :precondition (and (robot_at ?from) (clear_path ?from ?loc))
    :effect (and (picture_taken ?loc) (increase (total-cost) 1))))
