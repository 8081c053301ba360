; unsupported/or-goal
(define (problem base-1)
  (:domain base)
  (:objects o1 o2)
  (:init (p o1) (r o1 o2))
  (:goal (or (q o1) (q o2))))
