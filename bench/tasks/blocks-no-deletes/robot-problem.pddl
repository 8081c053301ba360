(define (problem bw8) (:domain blocks)
  (:objects a b c d e f g h - block)
  (:init (clear d) (on d c) (on c b) (on b a) (ontable a) (clear h) (on h g) (on g f) (on f e) (ontable e) (handempty))
  (:goal (and (on a b) (on b c) (on c d) (on e f) (on f g) (on g h))))
