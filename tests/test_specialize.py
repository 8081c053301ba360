"""``GroundFamily.specialize`` keeps recent tasks and each action's versions: what it returns
is still exactly ``human + selection``, built from scratch by the definition."""

from __future__ import annotations

from pathlib import Path

from helpers.fuzzing import oracle_settings
from helpers.sat_families import families
from hypothesis import given
from hypothesis import strategies as st

from mega_sat.ground import family as family_mod
from mega_sat.ground.family import GroundFamily, GroundTask, StripsAction, holds
from mega_sat.ground.grounding import ground
from mega_sat.pddl.loading import load_task_dir

DOMAINS = Path(__file__).resolve().parent.parent / "domains"


def _by_definition(fam: GroundFamily, sel: frozenset[int]) -> GroundTask:
    def keep(entries):
        return frozenset(p for p, g in entries if holds(g, sel))

    acts = []
    for i, a in enumerate(fam.actions):
        if holds(a.exists, sel):
            parts = (keep(a.pre), keep(a.negpre), keep(a.add), keep(a.delete))
            acts.append(StripsAction(i, a.name, a.args, *parts, a.cost_in(sel)))
    return GroundTask(fam.atoms, tuple(acts), keep(fam.init), keep(fam.goal))


@st.composite
def asked(draw):
    """A family and a sequence of selections with repeats, as the loop asks them."""
    fam = draw(families(max_updates=5))
    sel = st.frozensets(st.integers(0, max(fam.n_updates - 1, 0)), max_size=fam.n_updates)
    pool = draw(st.lists(sel, min_size=1, max_size=6))
    return fam, draw(st.lists(st.sampled_from(pool), min_size=1, max_size=40))


@oracle_settings(100)
@given(asked(), st.sampled_from([(16, 4), (1, 1), (2, 0)]))
def test_specialize_is_the_definition_however_often_asked(case, caps):
    """Every answer equals the task built by the definition, with the caches at their sizes,
    keeping one task and one version per action on average, or no version at all."""
    fam, selections = case
    saved = family_mod._RECENT_TASKS, family_mod._VERSIONS_KEPT
    family_mod._RECENT_TASKS, family_mod._VERSIONS_KEPT = caps
    try:
        fam = GroundFamily(fam.atoms, fam.n_updates, fam.actions, fam.init, fam.goal)  # cold
        for sel in selections:
            assert fam.specialize(sel) == _by_definition(fam, sel)
        assert len(fam._recent_tasks) <= caps[0]
        kept, budget = sum(len(v) for v in fam._action_versions), caps[1] * len(fam.actions)
        assert kept <= budget and kept + fam._versions_room[0] == budget
    finally:
        family_mod._RECENT_TASKS, family_mod._VERSIONS_KEPT = saved


def test_a_repeated_selection_is_the_same_task():
    """The loop's repeated questions about one model share one task (and its caches)."""
    fam = ground(load_task_dir(DOMAINS / "rover-martian/delta/2/p1"))
    a = fam.specialize({0})
    assert fam.specialize([0]) is a
    assert fam.specialize({1}) == _by_definition(fam, frozenset({1}))
    assert fam.specialize(frozenset({0})) is a
