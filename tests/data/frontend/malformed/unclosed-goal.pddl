; a problem whose goal is never closed
(define (problem base-1)
  (:domain base)
  (:objects o1 o2)
  (:init (p o1)
         (r o1 o2))
  (:goal (and (q o1))
