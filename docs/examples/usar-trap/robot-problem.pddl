;; A hidden trap (robot's map): Fetch starts at p1 and must take a picture at p5.
;; Both maps have the route p1 -> p6 -> p7 -> p5 (the robot-optimal plan, cost 4).
;; A collapsed wall opened p1 -> p9, which the commander does not know; rubble blocks
;; p9 -> p5, which the commander believes open.  Told only about p1 -> p9, the commander
;; would expect the shorter p1 -> p9 -> p5: the MCE of the plan is empty, its MME is not.
(define (problem usar-trap) (:domain usar-fetch)
  (:objects p1 p5 p6 p7 p9 - waypoint)
  (:init
    (= (total-cost) 0)
    (robot_at p1)
    (clear_path p1 p6) (clear_path p6 p7) (clear_path p7 p5)
    (clear_path p1 p9)
  )
  (:goal (and (picture_taken p5)))
  (:metric minimize (total-cost)))
