(define (problem base-1)
  (:domain base)
  (:objects o1
            2o)
  (:init (p o1) (p 2o))
  (:goal (and (q o1))))
