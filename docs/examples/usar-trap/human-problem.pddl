;; A hidden trap (the commander's map): no passage p1 -> p9, and p9 -> p5 still open.
(define (problem usar-trap) (:domain usar-fetch)
  (:objects p1 p5 p6 p7 p9 - waypoint)
  (:init
    (= (total-cost) 0)
    (robot_at p1)
    (clear_path p1 p6) (clear_path p6 p7) (clear_path p7 p5)
    (clear_path p9 p5)
  )
  (:goal (and (picture_taken p5)))
  (:metric minimize (total-cost)))
