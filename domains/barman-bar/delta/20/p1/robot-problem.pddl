;; barman-bar p1: one cocktail (ingredient1 + ingredient2) served in shot1; one shot, one shaker.
(define (problem barman-p1) (:domain barman-bar)
  (:objects left right - hand l0 l1 l2 - level dispenser1 dispenser2 - dispenser
            ingredient1 ingredient2 - ingredient cocktail1 - cocktail
            shaker1 - shaker shot1 - shot)
  (:init
    (= (total-cost) 0)
    (handempty left)
    (handempty right)
    (ontable shaker1)
    (empty shaker1)
    (clean shaker1)
    (shaker-empty-level shaker1 l0)
    (shaker-level shaker1 l0)
    (next l0 l1)
    (next l1 l2)
    (ontable shot1)
    (empty shot1)
    (clean shot1)
    (dispenses dispenser1 ingredient1)
    (dispenses dispenser2 ingredient2)
    (cocktail-part1 cocktail1 ingredient1)
    (cocktail-part2 cocktail1 ingredient2))
  (:goal (and (contains shot1 cocktail1)))
  (:metric minimize (total-cost)))

