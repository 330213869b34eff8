"""The memory keeps, per kept place, how many of its face code's places agree with it."""

from __future__ import annotations

import numpy as np
from hypothesis import example, given, settings
from hypothesis import strategies as st

from jointattention.models.memory._agreement import votes_of
from jointattention.models.memory._recall import AGREE, CODE_OF, HEAD, NEXT, votes_into
from jointattention.models.memory.episodic import EpisodicMemory
from jointattention.models.memory.options import MemoryOptions

LIMITS = ((-1.0, 1.0), (-0.7, 0.6))


def _filled(faces, spread, capacity, seed) -> EpisodicMemory:
    """A memory that kept one place per face index in ``faces``, clustered within ``spread``."""
    rng = np.random.default_rng(seed)
    windows = rng.uniform(0, 255, (4, 12))
    memory = EpisodicMemory(12, MemoryOptions(capacity=capacity), LIMITS, rng)
    centre = rng.uniform(-0.5, 0.5, (4, 2))
    places = centre[faces] + rng.uniform(-spread, spread, (len(faces), 2))
    memory.partial_fit(windows[faces], places)
    return memory


def _slots_of(links, u) -> list[int]:
    slots, slot = [], links[HEAD, u]
    while slot >= 0:
        slots.append(slot)
        slot = links[NEXT, slot]
    return slots


FACES = st.lists(st.integers(0, 3), min_size=1, max_size=120)


@settings(deadline=None)  # the first example compiles the kernels
@given(FACES, st.floats(0.001, 0.05), st.integers(1, 60), st.integers(0, 2**16))
@example([0] * 50, 0.001, 10, 0)  # one cluster, kept five times over in a ring of 10
def test_each_kept_place_counts_its_code_s_places_within_the_radius_as_it_forgets(
        faces, spread, capacity, seed):
    """links[AGREE] is a scan's count of the same code's places within the radius (ring too)."""
    memory = _filled(np.array(faces), spread, capacity, seed)
    links, aims, r2 = memory.links_, memory.aims_, memory.radius_rad ** 2
    for u in range(memory.n_codes_):
        slots = _slots_of(links, u)
        for a in slots:
            near = sum((aims[b, 0] - aims[a, 0]) ** 2 + (aims[b, 1] - aims[a, 1]) ** 2 < r2
                       for b in slots)
            assert links[AGREE, a] == near


@settings(deadline=None)
@given(st.integers(1, 300), st.floats(0.001, 0.3), st.floats(0.1, 1.0), st.integers(0, 2**16))
def test_one_code_s_votes_read_from_its_counts_are_the_counted_votes_bit_for_bit(
        n, spread, weight, seed):
    """votes_of one code's places gives votes_into's votes exactly, clustered or spread."""
    memory = _filled(np.zeros(n, int), spread, 400, seed)
    near = np.array(_slots_of(memory.links_, 0), np.int64)
    weights = np.full(len(near), weight)
    read, counted = np.empty(len(near)), np.empty(len(near))
    votes_of(near, weights, memory.links_, memory.aims_, memory.radius_rad, read)
    votes_into(near, weights, memory.aims_, memory.radius_rad, counted)
    assert np.array_equal(read, counted)


def test_places_of_several_codes_are_counted_not_read():
    """With two codes' places near, votes_of counts the pairs (each code's counts are its own)."""
    rng = np.random.default_rng(3)
    memory = EpisodicMemory(12, MemoryOptions(capacity=100), LIMITS, rng)
    memory.partial_fit(rng.uniform(0, 255, (2, 12))[[0, 1] * 20], rng.normal(0.1, 0.005, (40, 2)))
    links = memory.links_
    near = np.sort(np.r_[_slots_of(links, 0), _slots_of(links, 1)])
    assert len(set(links[CODE_OF, near])) == 2
    weights = np.ones(len(near))
    read, counted = np.empty(len(near)), np.empty(len(near))
    votes_of(near, weights, links, memory.aims_, memory.radius_rad, read)
    votes_into(near, weights, memory.aims_, memory.radius_rad, counted)
    assert np.array_equal(read, counted) and read.max() > links[AGREE, near].max()
