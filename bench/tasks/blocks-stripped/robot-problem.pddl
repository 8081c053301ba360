(define (problem bw9) (:domain blocks)
  (:objects a b c d e f g h i - block)
  (:init (clear c) (on c b) (on b a) (ontable a) (clear f) (on f e) (on e d) (ontable d) (clear i) (on i h) (on h g) (ontable g) (handempty))
  (:goal (and (on a b) (on b c) (on d e) (on e f) (on g h) (on h i))))
