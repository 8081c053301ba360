;; logistics p3: two parcels from office1 (city1), one to office2 (a drop zone), one to
;; airport2.
(define (problem logistics-p3) (:domain logistics)
  (:objects city1 city2 - city airport1 airport2 - airport office1 office2 - location
            truck1 truck2 - truck plane1 - airplane parcel1 parcel2 - package)
  (:init (= (total-cost) 0)
    (in-city airport1 city1) (in-city office1 city1)
    (in-city airport2 city2) (in-city office2 city2)
    (drop-zone office2)
    (at truck1 office1) (at truck2 airport2) (at plane1 airport1)
    (at parcel1 office1) (at parcel2 office1))
  (:goal (and (at parcel1 office2) (at parcel2 airport2)))
  (:metric minimize (total-cost)))
