; unsupported/negated-equality-goal
(define (problem base-1)
  (:domain base)
  (:objects o1 o2)
  (:init (p o1) (r o1 o2))
  (:goal (and (q o1)
         (not (= o1 o2)))))
