; unsupported/timed-literal
(define (problem base-1)
  (:domain base)
  (:objects o1 o2)
  (:init (p o1)
         (at 10 (p o2)))
  (:goal (and (q o1))))
