;; tpp -- a Traveling Purchaser Problem in the IPC style: the operator's model of the robot.
;; The operator knows drive, buy and unload, but
;;  - not deliver and drive-via (the robot's newer skills);
;;  - not the road map: a drive goes between any two places (no (road ?from ?to));
;;  - not how markets work: buy lacks the successor facts (next ...) and (open ?m), so one
;;    purchase may take any quantity, stock never runs out and every market is open.
(define (domain tpp)
  (:requirements :strips :typing :action-costs)
  (:types place truck goods level - object
          depot market - place)
  (:predicates
    (at ?t - truck ?p - place)
    (road ?from - place ?to - place)
    (courier ?m - market ?d - depot)
    (open ?m - market)
    (next ?lo - level ?hi - level)
    (on-sale ?g - goods ?m - market ?l - level)
    (loaded ?g - goods ?t - truck ?l - level)
    (stored ?g - goods ?l - level))
  (:functions (total-cost) - number)

  (:action drive
    :parameters (?t - truck ?from - place ?to - place)
    :precondition (and (at ?t ?from))
    :effect (and (not (at ?t ?from)) (at ?t ?to) (increase (total-cost) 2)))

  (:action buy
    :parameters (?t - truck ?g - goods ?m - market
                 ?s1 - level ?s0 - level ?c0 - level ?c1 - level)
    :precondition (and (at ?t ?m) (on-sale ?g ?m ?s1) (loaded ?g ?t ?c0))
    :effect (and (not (on-sale ?g ?m ?s1)) (on-sale ?g ?m ?s0)
                 (not (loaded ?g ?t ?c0)) (loaded ?g ?t ?c1)
                 (increase (total-cost) 1)))

  (:action unload
    :parameters (?t - truck ?g - goods ?d - depot
                 ?c1 - level ?c0 - level ?k0 - level ?k1 - level)
    :precondition (and (at ?t ?d)
                       (loaded ?g ?t ?c1) (next ?c0 ?c1)
                       (stored ?g ?k0) (next ?k0 ?k1))
    :effect (and (not (loaded ?g ?t ?c1)) (loaded ?g ?t ?c0)
                 (not (stored ?g ?k0)) (stored ?g ?k1)
                 (increase (total-cost) 1)))
)
