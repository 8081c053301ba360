;; USAR with two commanders -- commander 2's map (a drone survey after the first collapse).
(define (problem usar-two-commanders) (:domain usar-fetch)
  (:objects p1 p2 p3 p4 p5 p6 p7 p8 p9 p10 - waypoint)
  (:init
    (= (total-cost) 0)
    (robot_at p1)
    (clear_path p1 p2) (clear_path p2 p1)
    (clearable p2 p3)
    (clear_path p3 p4) (clear_path p4 p3)
    (clear_path p4 p5) (clear_path p5 p4)
    (clear_path p1 p6) (clear_path p6 p1)
    (clear_path p8 p5) (clear_path p5 p8)
    (clear_path p9 p10) (clear_path p10 p4)
    ;; the survey saw the rubble on p1 -> p8 and the new passage p6 -> p7,
    ;; but not the aftershock that blocked p2 -> p5, nor the passages p7 -> p5 and p1 -> p9
    (clear_path p6 p7)
    (clear_path p2 p5)
  )
  (:goal (and (picture_taken p5)))
  (:metric minimize (total-cost)))
