;; tpp -- a Traveling Purchaser Problem in the IPC style: the robot's model.
;; A truck buys goods at markets and brings them to the depot.  Quantities are levels
;; l0 < l1 < l2 < ... linked by the static successor facts (next ?lo ?hi): buying or
;; unloading moves one unit and steps two levels by one.  Only open markets sell.
;; What the robot can do that its operator does not know:
;;  - deliver (8 parameters): at a market with a courier service to the depot, the driver
;;    orders one unit straight into depot storage (the truck does not carry it back);
;;  - drive-via (4 parameters): a through drive from ?from via ?via to ?to without stopping,
;;    cheaper than two drives.
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
    :precondition (and (at ?t ?from) (road ?from ?to))
    :effect (and (not (at ?t ?from)) (at ?t ?to) (increase (total-cost) 2)))

  (:action buy
    :parameters (?t - truck ?g - goods ?m - market
                 ?s1 - level ?s0 - level ?c0 - level ?c1 - level)
    :precondition (and (at ?t ?m) (open ?m)
                       (on-sale ?g ?m ?s1) (next ?s0 ?s1)
                       (loaded ?g ?t ?c0) (next ?c0 ?c1))
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

  (:action deliver
    :parameters (?t - truck ?g - goods ?m - market ?d - depot
                 ?s1 - level ?s0 - level ?k0 - level ?k1 - level)
    :precondition (and (at ?t ?m) (open ?m) (courier ?m ?d)
                       (on-sale ?g ?m ?s1) (next ?s0 ?s1)
                       (stored ?g ?k0) (next ?k0 ?k1))
    :effect (and (not (on-sale ?g ?m ?s1)) (on-sale ?g ?m ?s0)
                 (not (stored ?g ?k0)) (stored ?g ?k1)
                 (increase (total-cost) 2)))

  (:action drive-via
    :parameters (?t - truck ?from - place ?via - place ?to - place)
    :precondition (and (at ?t ?from) (road ?from ?via) (road ?via ?to))
    :effect (and (not (at ?t ?from)) (at ?t ?to) (increase (total-cost) 3)))
)
