;; barman-bar p2: cocktail1 in shot1, a plain shot of ingredient2 in shot2, and the shaker cleaned afterwards.
(define (problem barman-p2) (:domain barman-bar)
  (:objects left right - hand l0 l1 l2 - level dispenser1 dispenser2 - dispenser
            ingredient1 ingredient2 - ingredient cocktail1 - cocktail
            shaker1 - shaker shot1 shot2 - shot)
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
    (ontable shot2)
    (empty shot2)
    (clean shot2)
    (dispenses dispenser1 ingredient1)
    (dispenses dispenser2 ingredient2)
    (cocktail-part1 cocktail1 ingredient1)
    (cocktail-part2 cocktail1 ingredient2))
  (:goal (and (contains shot1 cocktail1) (contains shot2 ingredient2) (clean shaker1)))
  (:metric minimize (total-cost)))

