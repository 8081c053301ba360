(define (problem typed-1)
  (:domain typed-logistics)
  (:objects a b - place
            pkg - package
            car1 - car
            thing)
  (:init (at van1 a) (at pkg a) (at car1 b)
         (road a b) (road b depot) (road a depot))
  (:goal (and (at pkg depot))))
