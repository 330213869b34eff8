"""How new an unseen caregiver is: distance to the nearest known one over the known's spacing."""

from __future__ import annotations

import numpy as np
from hypothesis import given, settings
from hypothesis import strategies as st

from jointattention.config import WorldConfig, load_config
from jointattention.rng import stream
from jointattention.world.identity import sample_caregiver
from jointattention.world.novelty import COORDINATES, coordinates, novelty

PEOPLE = load_config("people").world
MANY = load_config("many-caregivers").world


def _people(world: WorldConfig, n: int, seed: int):
    rng = stream(seed, "test-novelty")
    return [sample_caregiver(world, rng) for _ in range(n)]


def test_a_known_caregiver_is_not_new_and_others_are():
    """A known identity's novelty is 0; a new one of the same world lies about one spacing off."""
    known = _people(PEOPLE, 64, 0)
    assert np.all(novelty(known[:5], PEOPLE, known, PEOPLE) == 0)
    new = novelty(_people(PEOPLE, 64, 1), PEOPLE, known, PEOPLE)
    assert np.all(new > 0) and 0.7 < np.median(new) < 2.0


def test_people_of_a_wider_world_are_newer():
    """Caregivers of the people world are newer to the many-caregivers ones than their own are."""
    known = _people(MANY, 64, 0)
    same = novelty(_people(MANY, 32, 1), MANY, known, MANY)
    wider = novelty(_people(PEOPLE, 32, 1), PEOPLE, known, MANY)
    assert np.median(wider) > 1.2 * np.median(same)


def test_coordinates_take_the_world_s_means():
    """A caregiver's distance, stature, head share and pose noise are her world's plus hers."""
    c = _people(PEOPLE, 1, 2)[0]
    x = dict(zip(COORDINATES, coordinates([c], PEOPLE)[0], strict=True))
    cg = PEOPLE.caregiver
    assert x["distance_m"] == cg.distance_m + c.distance_offset_m
    assert x["head_turn_fraction"] == cg.head_turn_fraction + c.head_turn_offset
    assert x["pose_noise_deg"] == cg.pose_noise_deg + c.pose_noise_offset_deg


def test_too_few_known_caregivers_give_no_novelty():
    """With one known identity there is no spacing: NaN for each unseen one."""
    assert np.all(np.isnan(novelty(_people(PEOPLE, 3, 1), PEOPLE, _people(PEOPLE, 1, 0), PEOPLE)))


@settings(max_examples=20, deadline=None)
@given(st.integers(0, 2**32 - 1))
def test_novelty_does_not_depend_on_the_known_caregivers_order(seed):
    """Shuffling the known identities leaves every novelty as it was."""
    known, unseen = _people(PEOPLE, 12, 0), _people(PEOPLE, 4, 1)
    order = np.random.default_rng(seed).permutation(len(known))
    np.testing.assert_allclose(novelty(unseen, PEOPLE, [known[i] for i in order], PEOPLE),
                               novelty(unseen, PEOPLE, known, PEOPLE), rtol=1e-12)
