;; Rover (meets a Martian) -- MEGA benchmark, robot model.
;; IPC-2002 Rovers (STRIPS), simplified to a single rover (the rover is implicit,
;; as in the paper's printed plans, e.g. (sample_soil store waypoint3)).
;; The rover has been upgraded: it can carry all samples at once, so
;; sample_soil / sample_rock no longer need (empty ?s).
(define (domain rover-martian)
  (:requirements :strips :typing :action-costs)
  (:types waypoint store camera mode lander objective)
  (:predicates
    (at ?w - waypoint)
    (at_lander ?l - lander ?w - waypoint)
    (can_traverse ?x - waypoint ?y - waypoint)
    (visible ?x - waypoint ?y - waypoint)
    (empty ?s - store)
    (full ?s - store)
    (at_soil_sample ?w - waypoint)
    (at_rock_sample ?w - waypoint)
    (have_soil_analysis ?w - waypoint)
    (have_rock_analysis ?w - waypoint)
    (calibrated ?c - camera)
    (supports ?c - camera ?m - mode)
    (calibration_target ?c - camera ?o - objective)
    (visible_from ?o - objective ?w - waypoint)
    (have_image ?o - objective ?m - mode)
    (communicated_soil_data ?w - waypoint)
    (communicated_rock_data ?w - waypoint)
    (communicated_image_data ?o - objective ?m - mode))
  (:functions (total-cost) - number)

  (:action navigate
    :parameters (?y - waypoint ?z - waypoint)
    :precondition (and (at ?y) (can_traverse ?y ?z))
    :effect (and (not (at ?y)) (at ?z) (increase (total-cost) 2)))

  (:action sample_soil
    :parameters (?s - store ?p - waypoint)
    :precondition (and (at ?p) (at_soil_sample ?p))
    :effect (and (not (empty ?s)) (full ?s) (have_soil_analysis ?p) (not (at_soil_sample ?p))
                 (increase (total-cost) 2)))

  (:action sample_rock
    :parameters (?s - store ?p - waypoint)
    :precondition (and (at ?p) (at_rock_sample ?p))
    :effect (and (not (empty ?s)) (full ?s) (have_rock_analysis ?p) (not (at_rock_sample ?p))
                 (increase (total-cost) 2)))

  (:action drop
    :parameters (?s - store)
    :precondition (and (full ?s))
    :effect (and (not (full ?s)) (empty ?s) (increase (total-cost) 1)))

  (:action calibrate
    :parameters (?c - camera ?t - objective ?w - waypoint)
    :precondition (and (calibration_target ?c ?t) (at ?w) (visible_from ?t ?w))
    :effect (and (calibrated ?c) (increase (total-cost) 1)))

  (:action take_image
    :parameters (?p - waypoint ?o - objective ?c - camera ?m - mode)
    :precondition (and (calibrated ?c) (supports ?c ?m) (visible_from ?o ?p) (at ?p))
    :effect (and (have_image ?o ?m) (not (calibrated ?c)) (increase (total-cost) 1)))

  (:action communicate_soil_data
    :parameters (?l - lander ?p - waypoint ?x - waypoint ?y - waypoint)
    :precondition (and (at ?x) (at_lander ?l ?y) (have_soil_analysis ?p) (visible ?x ?y))
    :effect (and (communicated_soil_data ?p) (increase (total-cost) 1)))

  (:action communicate_rock_data
    :parameters (?l - lander ?p - waypoint ?x - waypoint ?y - waypoint)
    :precondition (and (at ?x) (at_lander ?l ?y) (have_rock_analysis ?p) (visible ?x ?y))
    :effect (and (communicated_rock_data ?p) (increase (total-cost) 1)))

  (:action communicate_image_data
    :parameters (?l - lander ?o - objective ?m - mode ?x - waypoint ?y - waypoint)
    :precondition (and (at ?x) (at_lander ?l ?y) (have_image ?o ?m) (visible ?x ?y))
    :effect (and (communicated_image_data ?o ?m) (increase (total-cost) 1)))
)
