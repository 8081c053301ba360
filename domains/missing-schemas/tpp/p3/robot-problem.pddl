;; tpp p3: one unit of bread and one of milk.  market3, next to the depot, sells both but is
;; closed today; bread is at market1 and milk at market2 (depot1 - market1 - market2), both
;; with a courier service to the depot.
(define (problem tpp-p3) (:domain tpp)
  (:objects depot1 - depot market1 market2 market3 - market truck1 - truck
            bread milk - goods l0 l1 - level)
  (:init (= (total-cost) 0)
    (next l0 l1)
    (road depot1 market1) (road market1 depot1)
    (road market1 market2) (road market2 market1)
    (road depot1 market3) (road market3 depot1)
    (open market1) (open market2)
    (courier market1 depot1) (courier market2 depot1)
    (at truck1 depot1)
    (on-sale bread market1 l1) (on-sale milk market2 l1)
    (on-sale bread market3 l1) (on-sale milk market3 l1)
    (loaded bread truck1 l0) (loaded milk truck1 l0)
    (stored bread l0) (stored milk l0))
  (:goal (and (stored bread l1) (stored milk l1)))
  (:metric minimize (total-cost)))
