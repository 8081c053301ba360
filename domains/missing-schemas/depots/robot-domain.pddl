;; depots -- crates between depots and distributors in the IPC style: the robot's model.
;; Hoists stand at one place each; trucks drive along roads; crates stand in stacks on
;; pallets.  A hoist lifts a crate off its stack, drops it onto a clear surface, loads it into
;; a truck or unloads it from one.
;; What the robot can do that its operator does not know: its hoists swing a crate straight
;; between a stack and a truck,
;;  - lift-load (5 parameters): off a stack into a truck in one motion;
;;  - unload-drop (5 parameters): out of a truck onto a stack in one motion;
;; each as cheap as one ordinary hoist action.
(define (domain depots)
  (:requirements :strips :typing :action-costs)
  (:types place locatable - object
          depot distributor - place
          truck hoist surface - locatable
          pallet crate - surface)
  (:predicates
    (at ?x - locatable ?p - place)
    (on ?c - crate ?s - surface)
    (in ?c - crate ?t - truck)
    (lifting ?h - hoist ?c - crate)
    (available ?h - hoist)
    (clear ?s - surface)
    (road ?from - place ?to - place))
  (:functions (total-cost) - number)

  (:action drive
    :parameters (?t - truck ?from - place ?to - place)
    :precondition (and (at ?t ?from) (road ?from ?to))
    :effect (and (not (at ?t ?from)) (at ?t ?to) (increase (total-cost) 3)))

  (:action lift
    :parameters (?h - hoist ?c - crate ?s - surface ?p - place)
    :precondition (and (at ?h ?p) (available ?h) (at ?c ?p) (on ?c ?s) (clear ?c))
    :effect (and (not (at ?c ?p)) (lifting ?h ?c) (not (clear ?c)) (not (available ?h))
                 (clear ?s) (not (on ?c ?s)) (increase (total-cost) 1)))

  (:action drop
    :parameters (?h - hoist ?c - crate ?s - surface ?p - place)
    :precondition (and (at ?h ?p) (at ?s ?p) (clear ?s) (lifting ?h ?c))
    :effect (and (available ?h) (not (lifting ?h ?c)) (at ?c ?p) (not (clear ?s)) (clear ?c)
                 (on ?c ?s) (increase (total-cost) 1)))

  (:action load
    :parameters (?h - hoist ?c - crate ?t - truck ?p - place)
    :precondition (and (at ?h ?p) (at ?t ?p) (lifting ?h ?c))
    :effect (and (not (lifting ?h ?c)) (in ?c ?t) (available ?h) (increase (total-cost) 1)))

  (:action unload
    :parameters (?h - hoist ?c - crate ?t - truck ?p - place)
    :precondition (and (at ?h ?p) (at ?t ?p) (available ?h) (in ?c ?t))
    :effect (and (not (in ?c ?t)) (not (available ?h)) (lifting ?h ?c)
                 (increase (total-cost) 1)))

  (:action lift-load
    :parameters (?h - hoist ?c - crate ?s - surface ?t - truck ?p - place)
    :precondition (and (at ?h ?p) (available ?h) (at ?c ?p) (on ?c ?s) (clear ?c) (at ?t ?p))
    :effect (and (not (at ?c ?p)) (not (clear ?c)) (clear ?s) (not (on ?c ?s)) (in ?c ?t)
                 (increase (total-cost) 1)))

  (:action unload-drop
    :parameters (?h - hoist ?c - crate ?t - truck ?s - surface ?p - place)
    :precondition (and (at ?h ?p) (available ?h) (at ?t ?p) (in ?c ?t) (at ?s ?p) (clear ?s))
    :effect (and (not (in ?c ?t)) (at ?c ?p) (not (clear ?s)) (clear ?c) (on ?c ?s)
                 (increase (total-cost) 1)))
)
