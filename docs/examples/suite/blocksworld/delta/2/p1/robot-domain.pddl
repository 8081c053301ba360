;; Blocksworld with an adaptive gripper -- MEGA benchmark, robot model.
;; 4-operator blocksworld with action costs.  Putting a block down on the
;; (low, cluttered) table is slow: put-down costs 3, every other action 1.
;; Nothing may be stacked on a fragile block (both models agree on that).
;; Robot: its new adaptive gripper can stack a block it has just unstacked
;; from a tower -- stack has no (firm ?x) precondition.
(define (domain blocksworld-gripper)
  (:requirements :strips :typing :negative-preconditions :action-costs)
  (:types block)
  (:predicates
    (on ?x - block ?y - block)
    (ontable ?x - block)
    (clear ?x - block)
    (handempty)
    (holding ?x - block)
    (firm ?x - block)       ; held with a firm top grip (only pick-up from the table gives one)
    (fragile ?x - block))   ; nothing may be stacked on it
  (:functions (total-cost) - number)

  (:action pick-up
    :parameters (?x - block)
    :precondition (and (clear ?x) (ontable ?x) (handempty))
    :effect (and (not (ontable ?x)) (not (clear ?x)) (not (handempty)) (holding ?x) (firm ?x)
                 (increase (total-cost) 1)))

  (:action put-down
    :parameters (?x - block)
    :precondition (and (holding ?x))
    :effect (and (not (holding ?x)) (not (firm ?x)) (clear ?x) (handempty) (ontable ?x)
                 (increase (total-cost) 3)))

  (:action stack
    :parameters (?x - block ?y - block)
    :precondition (and (holding ?x) (clear ?y) (not (fragile ?y)))
    :effect (and (not (holding ?x)) (not (firm ?x)) (not (clear ?y)) (clear ?x) (handempty) (on ?x ?y)
                 (increase (total-cost) 1)))

  (:action unstack
    :parameters (?x - block ?y - block)
    :precondition (and (on ?x ?y) (clear ?x) (handempty))
    :effect (and (holding ?x) (clear ?y) (not (clear ?x)) (not (handempty)) (not (on ?x ?y))
                 (increase (total-cost) 1)))
)
