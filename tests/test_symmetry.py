"""Object swaps: the signature filter finds exactly the swaps a check of every pair finds."""

from __future__ import annotations

from pathlib import Path

import pytest
from helpers.fuzzing import oracle_settings
from helpers.sat_families import families, symmetric_families
from hypothesis import given
from hypothesis import strategies as st

from mega_sat.ground.family import GroundFamily
from mega_sat.ground.grounding import ground
from mega_sat.pddl.loading import load_task_dir
from mega_sat.sat import symmetry
from mega_sat.sat.symmetry import object_swaps

DOMAINS = Path(__file__).resolve().parent.parent / "domains"


def every_pair(family: GroundFamily) -> list[symmetry.Swap]:
    """The swaps of every object pair, each checked in full (no filter)."""
    objects = sorted(
        {x for atom in family.atoms for x in atom[1:]} | {x for a in family.actions for x in a.args}
    )
    out = []
    for i, a in enumerate(objects):
        for b in objects[i + 1 :]:
            swap = symmetry._check(family, a, b, family.atom_index, family.action_index)
            if swap is not None:
                out.append(swap)
    return out


@oracle_settings(200)
@given(fam=st.one_of(families(), symmetric_families(max_atoms=3, max_actions=3, max_updates=3)))
def test_filter_keeps_every_swap_of_random_families(fam: GroundFamily):
    assert object_swaps(fam) == every_pair(fam)


@pytest.mark.parametrize(
    "task_dir",
    ["barman-bar/delta/7/p3", "blocksworld/delta/2/p3", "rover-martian/delta/10/p3",
     "usar-fetch/delta/2/p2", "missing-schemas/tpp/p2"],
)  # fmt: skip
def test_filter_keeps_every_swap_of_shipped_tasks(task_dir: str):
    """Barman's two hands and two of blocksworld's blocks are interchangeable: the filter
    keeps them and finds no other."""
    family = ground(load_task_dir(DOMAINS / task_dir))
    expected = every_pair(family)
    assert object_swaps(family) == expected
    pairs = [(s.a, s.b) for s in expected]
    if task_dir.startswith("barman"):
        assert pairs == [("left", "right")]
    if task_dir.startswith("blocksworld"):
        assert pairs == [("e", "f")]
