;; depots p2: one crate from depot0 to distributor1, two roads away
;; (depot0 - distributor0 - distributor1).
(define (problem depots-p2) (:domain depots)
  (:objects depot0 - depot distributor0 distributor1 - distributor truck0 - truck
            hoist0 hoist1 hoist2 - hoist pallet0 pallet1 pallet2 - pallet crate0 - crate)
  (:init (= (total-cost) 0)
    (road depot0 distributor0) (road distributor0 depot0)
    (road distributor0 distributor1) (road distributor1 distributor0)
    (at truck0 depot0)
    (at hoist0 depot0) (available hoist0)
    (at hoist1 distributor0) (available hoist1)
    (at hoist2 distributor1) (available hoist2)
    (at pallet0 depot0) (at pallet1 distributor0) (at pallet2 distributor1)
    (clear pallet1) (clear pallet2)
    (at crate0 depot0) (on crate0 pallet0) (clear crate0))
  (:goal (and (on crate0 pallet2)))
  (:metric minimize (total-cost)))
