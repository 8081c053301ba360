;; USAR with two commanders -- the robot's map (the building as it is now).
;; Fetch starts at p1 and must take a picture at p5.
;;  blue  : p1 -> p2 =clear_passage=> p3 -> p4 -> p5          robot cost 8
;;  north : p1 -> p9 -> p10 -> p4 -> p5                        robot cost 5
;;  green : p1 -> p6 -> p7 -> p5                               robot cost 4 (optimal)
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
    ;; passages opened by collapsed walls
    (clear_path p6 p7)
    (clear_path p7 p5)
    (clear_path p1 p9)
    ;; rubble: no (clear_path p1 p8), no (clear_path p2 p5)
  )
  (:goal (and (picture_taken p5)))
  (:metric minimize (total-cost)))
