;; USAR p2 (the external commander's original map).
(define (problem usar-p2) (:domain usar-fetch)
  (:objects p1 p2 p3 p4 p5 p6 p7 p8 p9 p10 - waypoint)
  (:init
    (= (total-cost) 0)
    (robot_at p1)
    (clear_path p1 p2) (clear_path p2 p1)
    (clearable p2 p3)
    (clear_path p3 p4) (clear_path p4 p3)
    (clear_path p4 p10) (clear_path p10 p4)
    (clear_path p1 p5) (clear_path p5 p1)
    (clear_path p5 p6) (clear_path p6 p5)
    (clear_path p9 p8)
    (clear_path p8 p10) (clear_path p10 p8)
    ;; the original map: corridor p6 -> p10 is open; walls p6|p9, p2|p7, p7|p8 stand
    (clear_path p6 p10)
  )
  (:goal (and (picture_taken p10)))
  (:metric minimize (total-cost)))
