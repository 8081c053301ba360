;; depots p3: the truck waits at depot0 and must fetch a crate from distributor0 and bring it
;; to distributor1; the roads form a star around depot0.
(define (problem depots-p3) (:domain depots)
  (:objects depot0 - depot distributor0 distributor1 - distributor truck0 - truck
            hoist0 hoist1 hoist2 - hoist pallet0 pallet1 pallet2 - pallet crate0 - crate)
  (:init (= (total-cost) 0)
    (road depot0 distributor0) (road distributor0 depot0)
    (road depot0 distributor1) (road distributor1 depot0)
    (at truck0 depot0)
    (at hoist0 depot0) (available hoist0)
    (at hoist1 distributor0) (available hoist1)
    (at hoist2 distributor1) (available hoist2)
    (at pallet0 depot0) (at pallet1 distributor0) (at pallet2 distributor1)
    (clear pallet0) (clear pallet2)
    (at crate0 distributor0) (on crate0 pallet1) (clear crate0))
  (:goal (and (on crate0 pallet2)))
  (:metric minimize (total-cost)))
