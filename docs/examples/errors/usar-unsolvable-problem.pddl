;; usar-fetch with every corridor out of p1 blocked: no plan reaches p5
(define (problem usar-blocked) (:domain usar-fetch)
  (:objects p1 p2 p5 - waypoint)
  (:init (= (total-cost) 0) (robot_at p1) (clear_path p2 p5))
  (:goal (and (picture_taken p5)))
  (:metric minimize (total-cost)))
