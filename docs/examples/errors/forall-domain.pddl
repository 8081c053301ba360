;; uses a universal quantifier, which mega-sat refuses (STRIPS with negative preconditions only)
(define (domain lights)
  (:requirements :strips :adl)
  (:predicates (on ?l) (light ?l))
  (:action all-off
    :parameters ()
    :precondition (and)
    :effect (forall (?l) (when (light ?l) (not (on ?l))))))
