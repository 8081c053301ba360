;; USAR p1 -- the paper's demonstration (robot's map).
;; Fetch starts at p1 and must take a picture at p5.
;;  red   (human expects): p1 -> p8 -> p5                        -- blocked by rubble in the robot's map
;;  blue  (explicable)   : p1 -> p2 =clear_passage=> p3 -> p4 -> p5
;;  green (robot optimal): p1 -> p6 -> p7 -> p5                  -- walls collapsed, new passages
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
    ;; collapsed walls: new one-way passages only the robot knows about
    (clear_path p6 p7)
    (clear_path p7 p5)
    ;; rubble: the robot's map has no (clear_path p1 p8)
  )
  (:goal (and (picture_taken p5)))
  (:metric minimize (total-cost)))
