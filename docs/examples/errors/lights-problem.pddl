(define (problem lights-1) (:domain lights)
  (:objects l1 l2)
  (:init (light l1) (light l2) (on l1))
  (:goal (and (light l1))))
