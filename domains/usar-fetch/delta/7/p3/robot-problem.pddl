;; USAR p3 (robot's map). Fetch starts at p1 and must take a picture at p10.
;;  blue   (human expects, explicable): p1 -> p2 =clear_passage=> p3 -> p4 -> p10
;;  orange (balanced)     : p1 -> p5 -> p6 -> p7 -> p8 -> p10       -- new passage p6 -> p7
;;  green  (robot optimal): p1 -> p11 -> p12 -> p9 -> p10           -- new passages p11 -> p12, p12 -> p9
;;  red    (tempting)     : p1 -> p11 -> p12 -> p10                 -- p12 -> p10 blocked by rubble; the
;;                          human would prefer it as soon as it learns about p11 -> p12
;;  distractor            : new passage p7 -> p3 (useless: never on a cheapest route)
(define (problem usar-p3) (:domain usar-fetch)
  (:objects p1 p2 p3 p4 p5 p6 p7 p8 p9 p10 p11 p12 - waypoint)
  (:init
    (= (total-cost) 0)
    (robot_at p1)
    (clear_path p1 p2) (clear_path p2 p1)
    (clearable p2 p3)
    (clear_path p3 p4) (clear_path p4 p3)
    (clear_path p4 p10) (clear_path p10 p4)
    (clear_path p1 p5) (clear_path p5 p1)
    (clear_path p5 p6) (clear_path p6 p5)
    (clear_path p7 p8) (clear_path p8 p7)
    (clear_path p8 p10) (clear_path p10 p8)
    (clear_path p1 p11) (clear_path p11 p1)
    (clear_path p9 p10) (clear_path p10 p9)
    ;; collapsed walls: new one-way passages only the robot knows about
    (clear_path p6 p7)
    (clear_path p11 p12)
    (clear_path p12 p9)
    (clear_path p7 p3)
    ;; rubble: the robot's map has no (clear_path p12 p10)
  )
  (:goal (and (picture_taken p10)))
  (:metric minimize (total-cost)))
