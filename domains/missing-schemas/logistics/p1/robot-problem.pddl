;; logistics p1: one parcel from office1 (city1) to office2 (city2), a drop zone.
(define (problem logistics-p1) (:domain logistics)
  (:objects city1 city2 - city airport1 airport2 - airport office1 office2 - location
            truck1 truck2 - truck plane1 - airplane parcel1 - package)
  (:init (= (total-cost) 0)
    (in-city airport1 city1) (in-city office1 city1)
    (in-city airport2 city2) (in-city office2 city2)
    (drop-zone office2)
    (at truck1 office1) (at truck2 airport2) (at plane1 airport1)
    (at parcel1 office1))
  (:goal (and (at parcel1 office2)))
  (:metric minimize (total-cost)))
