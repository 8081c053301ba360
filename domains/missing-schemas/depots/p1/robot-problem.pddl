;; depots p1: one crate from depot0 to distributor0, one truck.
(define (problem depots-p1) (:domain depots)
  (:objects depot0 - depot distributor0 - distributor truck0 - truck
            hoist0 hoist1 - hoist pallet0 pallet1 - pallet crate0 - crate)
  (:init (= (total-cost) 0)
    (road depot0 distributor0) (road distributor0 depot0)
    (at truck0 depot0)
    (at hoist0 depot0) (available hoist0)
    (at hoist1 distributor0) (available hoist1)
    (at pallet0 depot0) (at pallet1 distributor0) (clear pallet1)
    (at crate0 depot0) (on crate0 pallet0) (clear crate0))
  (:goal (and (on crate0 pallet1)))
  (:metric minimize (total-cost)))
