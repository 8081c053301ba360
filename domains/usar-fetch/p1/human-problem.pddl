;; USAR p1 -- the paper's demonstration (the external commander's original map).
(define (problem usar-p1) (:domain usar-fetch)
  (:objects p1 p2 p3 p4 p5 p6 p7 p8 - waypoint)
  (:init
    (= (total-cost) 0)
    (robot_at p1)
    (clear_path p1 p2) (clear_path p2 p1)
    (clearable p2 p3)
    (clear_path p3 p4) (clear_path p4 p3)
    (clear_path p4 p5) (clear_path p5 p4)
    (clear_path p1 p6) (clear_path p6 p1)
    (clear_path p8 p5) (clear_path p5 p8)
    ;; the original map: corridor p1 -> p8 is open; walls p6|p7 and p7|p5 stand
    (clear_path p1 p8)
  )
  (:goal (and (picture_taken p5)))
  (:metric minimize (total-cost)))
