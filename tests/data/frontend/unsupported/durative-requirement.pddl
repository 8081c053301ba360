(define (domain base)
  (:requirements :strips
                 :durative-actions)
  (:predicates (p ?x) (q ?x) (r ?x ?y)))
