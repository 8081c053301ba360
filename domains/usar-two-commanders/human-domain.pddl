;; USAR with a Fetch robot and two commanders (several human models).
;; The robot and both commanders share this domain; the models differ only in the map
;; (initial-state clear_path facts), see README.md.
(define (domain usar-fetch)
  (:requirements :strips :typing :action-costs)
  (:types waypoint)
  (:predicates
    (robot_at ?l - waypoint)
    (clear_path ?from - waypoint ?to - waypoint)   ; corridor ?from -> ?to is traversable
    (clearable ?from - waypoint ?to - waypoint)    ; corridor blocked by light debris the robot can push aside
    (picture_taken ?l - waypoint))
  (:functions (total-cost) - number)

  (:action move
    :parameters (?from - waypoint ?to - waypoint)
    :precondition (and (robot_at ?from) (clear_path ?from ?to))
    :effect (and (not (robot_at ?from)) (robot_at ?to) (increase (total-cost) 1)))

  ;; costly: the robot pushes the debris aside, the corridor becomes traversable
  (:action clear_passage
    :parameters (?from - waypoint ?to - waypoint)
    :precondition (and (robot_at ?from) (clearable ?from ?to))
    :effect (and (not (clearable ?from ?to)) (clear_path ?from ?to) (increase (total-cost) 3)))

  (:action take_picture
    :parameters (?loc - waypoint)
    :precondition (and (robot_at ?loc))
    :effect (and (picture_taken ?loc) (increase (total-cost) 1)))
)
