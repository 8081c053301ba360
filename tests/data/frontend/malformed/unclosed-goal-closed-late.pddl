; a problem whose goal is never closed: the last line closes it, not the define
(define (problem base-1)
  (:domain base)
  (:objects o1 o2)
  (:init (p o1)
         (r o1 o2))
  (:goal (and (q o1))
)
