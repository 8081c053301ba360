;; USAR with two commanders -- commander 1's map (drawn before the collapse).
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
    ;; the corridor p1 -> p8, now blocked by rubble, is still open on this map;
    ;; the passages p6 -> p7, p7 -> p5 and p1 -> p9 opened later: not on this map
    (clear_path p1 p8)
  )
  (:goal (and (picture_taken p5)))
  (:metric minimize (total-cost)))
